#include "asynevo/frontend/sae.hpp"

#include <cassert>

namespace asynevo::frontend {

SurfaceOfActiveEvents::SurfaceOfActiveEvents(int width, int height, int64_t refractory_ns)
    : width_(width), height_(height), refractory_ns_(refractory_ns) {
  assert(width > 0 && height > 0 && refractory_ns >= 0);
  clear();
}

void SurfaceOfActiveEvents::clear() {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  for (int p = 0; p < 2; ++p) sae_[p].assign(n, kNever);
  latest_.assign(2 * n, kNever);
}

}  // namespace asynevo::frontend

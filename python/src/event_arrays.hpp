#pragma once
// Events between numpy and C++: columns (t int64 ns, x uint16, y uint16, p int8 ±1) handed to numpy
// without a copy, and numpy arrays checked and turned into Events (ValueError naming the array and the
// index for a wrong dtype or shape, mismatched lengths, time going backwards or a pixel outside the
// sensor).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo::python {

/// Events as four columns, the layout numpy users expect.
struct EventColumns {
  std::vector<int64_t> t;
  std::vector<uint16_t> x, y;
  std::vector<int8_t> p;

  std::size_t size() const { return t.size(); }
  void reserve(std::size_t n);
  void append(const std::vector<Event>& events);
};

/// Moves a vector into a 1-D numpy array that owns it (no copy).
template <class T>
pybind11::array_t<T> toNumpy(std::vector<T>&& values) {
  auto holder = std::make_unique<std::vector<T>>(std::move(values));
  std::vector<T>* owned = holder.get();
  // The capsule owns the vector from here on and frees it with the array.
  pybind11::capsule free_when_done(
      holder.release(), [](void* p) { std::unique_ptr<std::vector<T>>(static_cast<std::vector<T>*>(p)); });
  return pybind11::array_t<T>({static_cast<pybind11::ssize_t>(owned->size())}, {sizeof(T)}, owned->data(),
                              free_when_done);
}

/// Adds "t", "x", "y", "p" (moved out of `columns`) to `out`.
void addColumns(EventColumns&& columns, pybind11::dict& out);

/// Checks and converts arrays t (integer ns, non-decreasing), x, y (integers inside width × height) and
/// p (bool or integer: 1 ON, 0 or -1 OFF). Throws pybind11::value_error naming the array and index.
std::vector<Event> eventsFromArrays(const pybind11::handle& t, const pybind11::handle& x,
                                    const pybind11::handle& y, const pybind11::handle& p, int width,
                                    int height);

}  // namespace asynevo::python

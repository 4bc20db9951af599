#pragma once
// The C allocator for the commands that run the pipeline (glibc).

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace asynevo::cli {

/// One allocator arena for the whole process (glibc's M_ARENA_MAX = 1), set before a run starts its
/// frontend and backend threads. With an arena of its own, the backend thread's resident memory grows
/// by about 1 MiB per minute over a long run; with one shared arena it stays flat, about 28 MiB higher
/// from the start, at a CPU cost within 1 % (docs/results/soak.md). A no-op with other C libraries.
inline void useOneAllocatorArena() {
#if defined(__GLIBC__)
  mallopt(M_ARENA_MAX, 1);
#endif
}

}  // namespace asynevo::cli

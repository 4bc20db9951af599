#pragma once
// Events between numpy and C++: packets of events into numpy columns (t int64 ns, x uint16, y uint16,
// p int8 ±1) in one pass, and numpy arrays checked and turned into Events (ValueError naming the array and
// the index for a wrong dtype or shape, mismatched lengths, time going backwards or a pixel outside the
// sensor).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo::python {

/// Events read in packets, kept as the reader delivered them until they become numpy columns.
using EventChunks = std::vector<std::vector<Event>>;

/// Adds "t" (int64 ns), "x", "y" (uint16) and "p" (int8, ±1) to `out`: the arrays are allocated once
/// with the total size (uninitialized) and filled with the GIL released. Call with the GIL held.
void addColumns(const EventChunks& chunks, pybind11::dict& out);

/// Checks and converts arrays t (integer ns, non-decreasing), x, y (integers inside width × height) and
/// p (bool or integer: 1 ON, 0 or -1 OFF). Throws pybind11::value_error naming the array and index.
std::vector<Event> eventsFromArrays(const pybind11::handle& t, const pybind11::handle& x,
                                    const pybind11::handle& y, const pybind11::handle& p, int width,
                                    int height);

}  // namespace asynevo::python

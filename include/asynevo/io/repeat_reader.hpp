#pragma once
// An event stream played several times back to back (`asynevo run --repeat N`, the soak benchmark):
// each pass reopens the file and continues in time one mean event interval after the previous pass's
// last event, so a long stream is made from a short recording in constant memory. The camera's pose
// jumps back at every seam; nothing in the pipeline may assume otherwise.

#include <functional>
#include <memory>

#include "asynevo/io/event_reader.hpp"

namespace asynevo {

/// `open` makes a fresh reader of the same stream for each of `passes` passes (≥ 1). info() is the
/// first reader's; stats() counts the events of all passes. A pass without events is an InputError.
std::unique_ptr<EventReader> repeatEvents(std::function<std::unique_ptr<EventReader>()> open, int passes);

}  // namespace asynevo

#pragma once
// The start of an event stream left out (`asynevo run --skip-ms MS`): the events less than MS after
// the stream's first event are read and dropped, as if the recording had begun later. The evaluation
// matrix runs a frontend setting at a few such start offsets (docs/evaluation_matrix.md#start-offsets).

#include <cstdint>
#include <memory>

#include "asynevo/io/event_reader.hpp"

namespace asynevo {

/// `reader` without the events before its first event's time + skip_ns (skip_ns ≥ 0; 0 passes every
/// event). Packets keep their record indices (first_index counts the dropped events too); stats() is
/// the inner reader's, with `events` the events delivered and `skipped_at_start` the events dropped.
/// A stream that ends before the cut is an InputError naming the file, the cut and the stream's span.
std::unique_ptr<EventReader> skipStartOfStream(std::unique_ptr<EventReader> reader, int64_t skip_ns);

}  // namespace asynevo

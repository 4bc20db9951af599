#pragma once
// Streaming access to event files. A reader hands out time-ordered packets of bounded size, so a
// multi-gigabyte recording is processed in constant memory. Every event is checked (finite time,
// pixel inside the sensor, valid polarity, time not going backwards beyond a tolerance); a violation
// throws InputError naming the file and the line (text), record (fixed-size binary records) or byte
// offset (Prophesee RAW and DAT; AEDAT 4.0: the offset of the packet, with the packet and event index;
// ROS bag: the offset of the message record, or of its compressed chunk, with the message index).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "asynevo/core/event.hpp"

namespace asynevo {

struct ReaderOptions {
  /// "auto", "ecd", "mvsec", "aevt", "evt3" (Prophesee RAW EVT 3.0), "evt2" (Prophesee RAW EVT 2.0),
  /// "dat" (Prophesee DAT), "aedat4" (iniVation AEDAT 4.0), "rosbag" (ROS1 bag, format 2.0), "dsec"
  /// (DSEC-style HDF5: DSEC, TUM-VIE, M3ED)
  std::string format = "auto";
  /// The topic of a container with several event streams (ROS bag); "" = the only event topic.
  std::string topic;
  int width = 0;                      ///< sensor columns; 0 = the format's own or default (ECD: 240)
  int height = 0;                     ///< sensor rows; 0 = the format's own or default (ECD: 180)
  /// Where width and height were set, for messages ("--sensor", "the configuration c.yaml", ...; see
  /// io/sensor_size.hpp). A size that differs from the one a file's header states is an error naming it.
  std::string size_origin = "the reader options";
  /// DSEC: the rectification map (rectify_map.h5) applied to the events. "" = the rectify_map.h5 beside the
  /// events file when there is one, "none" = no rectification (raw pixels), else the map file. Other formats
  /// reject a map file.
  std::string rectify_map;
  int packet_size = 65536;            ///< events per packet
  int64_t max_time_reversal_ns = 0;   ///< backward steps up to this are clamped to the previous time
};

/// What a reader knows about its stream without reading it all.
struct StreamInfo {
  std::string path;     ///< the event file
  std::string format;   ///< "ecd", "mvsec", "aevt", "evt3", "evt2", "dat", "aedat4", "rosbag", "dsec"
  int width = 0;
  int height = 0;
  std::string size_origin;  ///< where width and height came from: ReaderOptions::size_origin, or the format's
                            ///< ("the ECD text default", "the .aevt header", ...)
  /// The rectification map applied to the events (DSEC's rectify_map.h5): they are then in the rectified
  /// camera's pixels. "" = none, events in raw pixels.
  std::string rectify_map;
};

/// One stream of a container file that holds several (AEDAT 4.0: events, frames, IMU, triggers; ROS bag:
/// its topics, with the message type as `type`, the topic as `name` and messages as `packets`).
struct ContainerStream {
  int id = 0;
  std::string type;         ///< the format's type name: "EVTS", "FRME", "IMUS", "TRIG", ...
  std::string name;         ///< the recorder's name for it ("events", "imu", ...); may be empty
  int width = 0;            ///< its geometry where the file gives one, else 0
  int height = 0;
  uint64_t packets = 0;     ///< packets of this stream seen so far
  uint64_t elements = 0;    ///< events, IMU samples or triggers in them (0 for streams not decoded)
  bool delivered = false;   ///< the stream the reader delivers events from
};

/// Counters a reader keeps while streaming.
struct ReaderStats {
  uint64_t events = 0;           ///< events delivered so far
  uint64_t clamped_times = 0;    ///< events whose time went back within the tolerance (clamped)
  uint64_t skipped_lines = 0;    ///< blank or comment ('#') lines in text formats
  uint64_t trigger_events = 0;   ///< external-trigger events in the stream (counted, not delivered)
  uint64_t ignored_words = 0;    ///< encoded words skipped: vendor extensions (Prophesee OTHERS/CONTINUED) and
                                 ///< events before the stream's first time base or row
  uint64_t imu_samples = 0;      ///< IMU samples in the file (counted, not delivered; AEDAT 4.0)
  uint64_t rectified_outside = 0;  ///< events whose rectified pixel is outside the sensor (dropped; DSEC with
                                   ///< a rectification map)
  std::vector<ContainerStream> streams;  ///< the streams of a container file (AEDAT 4.0); empty otherwise
  uint64_t skipped_at_start = 0;  ///< events read and dropped before the stream's cut (io/skip_reader.hpp)
};

class EventReader {
 public:
  virtual ~EventReader() = default;
  /// Replaces `packet`'s events with the next ones (at most packet_size). Returns false, with an
  /// empty packet, at the end of the stream. Throws InputError on bad data.
  virtual bool read(EventPacket& packet) = 0;
  virtual const StreamInfo& info() const = 0;
  virtual const ReaderStats& stats() const = 0;
};

/// Opens an event file. With format "auto" the format is detected from the file's content.
/// Throws InputError when the file is missing, unreadable, empty or of an unknown format.
std::unique_ptr<EventReader> openEventReader(const std::string& path, const ReaderOptions& options = {});

/// Reads a whole (small) file into memory; for tests and tools. Large files should be streamed.
std::vector<Event> readAllEvents(const std::string& path, const ReaderOptions& options = {});

}  // namespace asynevo

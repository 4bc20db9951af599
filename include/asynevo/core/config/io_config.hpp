#pragma once
// Configuration of event input: sensor geometry and the reader's checks.

#include <cstdint>

namespace asynevo {

struct SensorConfig {
  int width = 240;   ///< sensor columns (DAVIS240C default; ECD calib.txt does not store it)
  int height = 180;  ///< sensor rows
  /// Not a key: true once a configuration file names the size. Only then does the size rank above the
  /// dataset's own (sensor.yaml, calibration, format; io/sensor_size.hpp); else it is the fallback.
  bool set_by_file = false;

  template <class V>
  void visit(V& v) {
    v("width", width, "sensor columns in pixels (ECD calib.txt has no resolution; DAVIS240C = 240)");
    v("height", height, "sensor rows in pixels (DAVIS240C = 180)");
  }
  void validate() const;
};

struct InputConfig {
  int packet_size = 65536;          ///< events per packet handed out by a reader
  double max_time_reversal_us = 0;  ///< backward time steps up to this are clamped and counted

  template <class V>
  void visit(V& v) {
    v("packet_size", packet_size, "events per packet delivered by a reader (bounds reader memory)");
    v("max_time_reversal_us", max_time_reversal_us,
      "an event earlier than its predecessor by at most this much is clamped to the predecessor's "
      "time and counted; a larger step back is an error naming the line or record");
  }
  void validate() const;
};

}  // namespace asynevo

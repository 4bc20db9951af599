#pragma once
// Shared pieces of the fuzz harnesses (docs/reliability.md). Every reader takes a path, so the input is
// written to a file first. An asynevo::Error is the expected answer to bad input (a located, clean
// rejection); anything else is a finding: another exception type, a crash, a sanitizer report, or
// accepted data that breaks the reader's own promises (events outside the sensor, time going back,
// NaN poses), which the checks below turn into an abort.

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "asynevo/core/error.hpp"
#include "asynevo/core/event.hpp"
#include "asynevo/core/stamped_pose.hpp"

namespace asynevo::fuzz {

/// The fuzzer's bytes as a file named after the process (one harness process reads one at a time).
class InputFile {
 public:
  InputFile(const uint8_t* data, std::size_t size, const std::string& suffix) {
    const char* tmp = std::getenv("TMPDIR");
    path_ = std::string(tmp && *tmp ? tmp : "/tmp") + "/asynevo_fuzz_" + std::to_string(getpid()) + suffix;
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    if (std::fclose(f) != 0) std::abort();
  }
  ~InputFile() { std::remove(path_.c_str()); }
  InputFile(const InputFile&) = delete;
  InputFile& operator=(const InputFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void require(bool ok, const std::string& what) {
  if (!ok) finding(what);
}

/// Runs `body`; an asynevo::Error is a clean rejection, any other exception a finding.
template <class Body>
void rejectCleanly(Body&& body) {
  try {
    body();
  } catch (const Error&) {
  } catch (const std::exception& e) {
    finding(std::string("an exception that is not an asynevo::Error escaped: ") + e.what());
  } catch (...) {
    finding("a non-std exception escaped");
  }
}

/// What every accepted pose sequence promises: finite values, unit quaternions, time never going back.
inline void requireValidTrajectory(const StampedTrajectory& trajectory) {
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const StampedPose& p = trajectory[i];
    require(p.p_w_c.allFinite() && p.q_w_c.coeffs().allFinite(), "an accepted pose is not finite");
    require(std::abs(p.q_w_c.norm() - 1.0) < 1e-6, "an accepted quaternion is not unit length");
    if (i > 0) require(p.t_ns >= trajectory[i - 1].t_ns, "accepted poses go back in time");
  }
}

/// What every accepted event promises: inside the sensor, polarity ±1, time never going back.
inline void requireValidEvents(const EventPacket& packet, int width, int height, int64_t& last_t_ns) {
  for (const Event& e : packet.events) {
    require(e.x < width && e.y < height, "an accepted event is outside the sensor");
    require(e.polarity == 1 || e.polarity == -1, "an accepted event has a polarity other than +1/-1");
    require(e.t_ns >= last_t_ns, "accepted events go back in time");
    last_t_ns = e.t_ns;
  }
}

}  // namespace asynevo::fuzz

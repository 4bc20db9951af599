// Format detection and the reader factory.
#include "asynevo/io/event_reader.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>

#include "aedat4_header.hpp"
#include "aedat4_reader.hpp"
#include "asynevo/core/error.hpp"
#include "asynevo/io/event_file.hpp"
#include "asynevo/io/file_handle.hpp"
#include "dsec_reader.hpp"
#include "ecd_text_reader.hpp"
#include "event_file_reader.hpp"
#include "hdf5_isolation.hpp"
#include "mvsec_reader.hpp"
#include "prophesee_reader.hpp"
#include "rosbag_reader.hpp"

namespace asynevo {

namespace {

namespace aedat4 = io_detail::aedat4;

using io_detail::kHdf5Signature;

std::string detectFormat(const std::string& path) {
  FileHandle file = openFile(path, "rb");
  if (!file) throw InputError(path, std::string("cannot open event file: ") + std::strerror(errno));
  unsigned char head[4096];
  const std::size_t n = std::fread(head, 1, sizeof(head), file.get());
  if (n == 0) throw InputError(path, "the event file is empty");
  if (n >= 8 && std::memcmp(head, kHdf5Signature, 8) == 0) return io_detail::detectHdf5EventFormat(path);  // mvsec, dsec
  if (n >= 8 && std::memcmp(head, kEventFileMagic, 8) == 0) return "aevt";
  if (n >= aedat4::kMagicBytes && std::memcmp(head, aedat4::kMagic, aedat4::kMagicBytes) == 0) return "aedat4";
  if (n >= io_detail::kRosbagMagicBytes &&
      std::memcmp(head, io_detail::kRosbagMagic, io_detail::kRosbagMagicBytes) == 0)
    return "rosbag";
  if (n >= 9 && std::memcmp(head, "#ROSBAG V", 9) == 0) {
    const auto line = std::string(reinterpret_cast<const char*>(head), n);
    throw InputError::atByte(path, 0,
                             "the version line '" + line.substr(0, line.find_first_of("\r\n")) +
                                 "' names a bag format AsynEVO does not read (only '#ROSBAG V2.0')");
  }
  const std::size_t prefix = sizeof(aedat4::kVersionPrefix) - 1;
  if (n >= prefix && std::memcmp(head, aedat4::kVersionPrefix, prefix) == 0) {  // AEDAT 2.0 or 3.x
    const auto line = std::string(reinterpret_cast<const char*>(head), n);
    throw InputError::atByte(path, 0,
                             "the version line '" + line.substr(0, line.find_first_of("\r\n")) +
                                 "' names an AEDAT version AsynEVO does not read (only AEDAT 4.0, '#!AER-DAT4.0')");
  }
  if (n >= 2 && head[0] == '%' && head[1] == ' ') {  // a Prophesee RAW or DAT header ("% keyword value" lines)
    const io_detail::PropheseeHeader header = io_detail::readPropheseeHeader(file.get(), path);
    const std::string format = io_detail::propheseeFormatFromHeader(header, path);
    if (format.empty()) {
      throw InputError(path,
                       "a '%' header that names no Prophesee format (no 'evt' or 'format' line of a RAW file, no "
                       "'Data file containing' line of a DAT file); give --format evt3, evt2 or dat");
    }
    return format;
  }
  if (std::memchr(head, '\0', n) != nullptr) {
    throw InputError(path,
                     "unknown binary format (supported: ECD text, MVSEC HDF5, AsynEVO .aevt, Prophesee RAW EVT 3.0 "
                     "and EVT 2.0, Prophesee DAT, AEDAT 4.0, ROS bag 2.0; a RAW or DAT file without its '%' header needs --format evt3, "
                     "evt2 or dat)");
  }
  return "ecd";
}

/// True for a file libhdf5 is about to parse: format mvsec or dsec, named or detected by the signature.
bool isHdf5EventFile(const std::string& path, const std::string& format) {
  if (format == "mvsec" || format == "dsec") return true;
  return format == "auto" && io_detail::hasHdf5Signature(path);
}

/// The reader of the named (or detected) format, opened in this process.
std::unique_ptr<EventReader> openHere(const std::string& path, const ReaderOptions& options) {
  const std::string format = options.format == "auto" ? detectFormat(path) : options.format;
  // A named rectification map is a request: a format that cannot apply one says so instead of ignoring it.
  if (!options.rectify_map.empty() && options.rectify_map != "none" && format != "dsec") {
    throw InputError(path,
                     fmt::format("a rectification map ({}) applies to DSEC-style HDF5 events only, and this "
                                 "file is of format {}",
                                 options.rectify_map, format));
  }
  if (format == "ecd") return std::make_unique<io_detail::EcdTextReader>(path, options);
  if (format == "mvsec") return std::make_unique<io_detail::MvsecReader>(path, options);
  if (format == "aevt") return std::make_unique<io_detail::EventFileReader>(path, options);
  if (format == "evt3") return std::make_unique<io_detail::Evt3Reader>(path, options);
  if (format == "evt2") return std::make_unique<io_detail::Evt2Reader>(path, options);
  if (format == "dat") return std::make_unique<io_detail::DatReader>(path, options);
  if (format == "aedat4") return std::make_unique<io_detail::Aedat4Reader>(path, options);
  if (format == "rosbag") return std::make_unique<io_detail::RosbagReader>(path, options);
  if (format == "dsec") return std::make_unique<io_detail::DsecReader>(path, options);
  throw InputError(path, "unknown event format '" + format +
                             "' (supported: auto, ecd, mvsec, aevt, evt3, evt2, dat, aedat4, rosbag, dsec)");
}

}  // namespace

std::unique_ptr<EventReader> openEventReader(const std::string& path, const ReaderOptions& options) {
  if (options.packet_size <= 0) throw ConfigError("packet size must be positive");
  // libhdf5 meets the file in a child process first: its format detection, the reader's opening and
  // the first packet (io/hdf5_isolation.hpp).
  if (isHdf5EventFile(path, options.format)) {
    io_detail::parseHdf5InChild(path, [&] {
      const std::unique_ptr<EventReader> reader = openHere(path, options);
      EventPacket packet;
      reader->read(packet);
    });
  }
  return openHere(path, options);
}

std::vector<Event> readAllEvents(const std::string& path, const ReaderOptions& options) {
  auto reader = openEventReader(path, options);
  std::vector<Event> all;
  EventPacket packet;
  while (reader->read(packet)) all.insert(all.end(), packet.events.begin(), packet.events.end());
  return all;
}

}  // namespace asynevo

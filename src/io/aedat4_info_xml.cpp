// The XML info node of an AEDAT 4.0 IOHeader: DV's configuration-tree export, e.g.
//   <dv version="2.0">
//     <node name="outInfo" path="/mainloop/Recorder/outInfo/">
//       <node name="0" path=".../outInfo/0/">
//         <attr key="typeIdentifier" type="string">EVTS</attr>
//         <node name="info" path=".../outInfo/0/info/">
//           <attr key="sizeX" type="int">320</attr> <attr key="sizeY" type="int">240</attr>
// Only <node> nesting and <attr key="...">value</attr> matter here; a small tag scanner reads them (no
// DTDs, no CDATA; the five predefined entities and numeric character references are decoded).
#include <fmt/format.h>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <string>
#include <vector>

#include "aedat4_header.hpp"
#include "asynevo/core/error.hpp"

namespace asynevo::io_detail::aedat4 {

namespace {

class InfoScanner {
 public:
  InfoScanner(const std::string& xml, const std::string& path, uint64_t offset)
      : xml_(xml), path_(path), offset_(offset) {}

  std::vector<Stream> streams() {
    std::vector<std::string> nodes;  // names of the open <node> elements
    std::size_t pos = 0;
    while ((pos = xml_.find('<', pos)) != std::string::npos) {
      if (xml_.compare(pos, 4, "<!--") == 0) {
        pos = endOf(pos, "-->");
        continue;
      }
      const std::size_t close = endOf(pos, ">");
      const std::string tag = xml_.substr(pos + 1, close - pos - 2);
      const bool self_closing = !tag.empty() && tag.back() == '/';
      if (tag.rfind("node", 0) == 0 && isNameEnd(tag, 4)) {
        if (!self_closing) nodes.push_back(attribute(tag, "name", pos));
      } else if (tag == "/node") {
        if (nodes.empty()) fail(pos, "'</node>' without an open <node>");
        nodes.pop_back();
      } else if (tag.rfind("attr", 0) == 0 && isNameEnd(tag, 4)) {
        const std::string key = attribute(tag, "key", pos);
        std::string value;
        if (!self_closing) {
          const std::size_t end = xml_.find("</attr>", close);
          if (end == std::string::npos) fail(pos, "an <attr> element without '</attr>'");
          value = decode(xml_.substr(close, end - close), close);
          pos = end + 7;
        } else {
          pos = close;
        }
        store(nodes, key, value, pos);
        continue;
      }
      pos = close;
    }
    std::vector<Stream> result;
    for (const Stream& s : streams_) result.push_back(s);
    std::sort(result.begin(), result.end(), [](const Stream& a, const Stream& b) { return a.id < b.id; });
    return result;
  }

 private:
  [[noreturn]] void fail(std::size_t pos, const std::string& message) const {
    throw InputError::atByte(path_, offset_ + pos, "IOHeader info node: " + message);
  }

  // The position after `terminator`, searched from `pos`.
  std::size_t endOf(std::size_t pos, const char* terminator) const {
    const std::size_t end = xml_.find(terminator, pos);
    if (end == std::string::npos) fail(pos, std::string("unterminated tag (no '") + terminator + "')");
    return end + std::char_traits<char>::length(terminator);
  }

  static bool isNameEnd(const std::string& tag, std::size_t at) {
    return at == tag.size() || tag[at] == ' ' || tag[at] == '/' || tag[at] == '\t' || tag[at] == '\n' || tag[at] == '\r';
  }

  // The value of attribute `key` (key="value" or key='value') inside a start tag; "" when absent.
  std::string attribute(const std::string& tag, const std::string& key, std::size_t pos) const {
    std::size_t at = 0;
    while ((at = tag.find(key + "=", at)) != std::string::npos) {
      if (at > 0 && (tag[at - 1] == ' ' || tag[at - 1] == '\t' || tag[at - 1] == '\n' || tag[at - 1] == '\r')) {
        const std::size_t quote = at + key.size() + 1;
        if (quote >= tag.size() || (tag[quote] != '"' && tag[quote] != '\'')) fail(pos, "attribute '" + key + "' without quotes");
        const std::size_t end = tag.find(tag[quote], quote + 1);
        if (end == std::string::npos) fail(pos, "attribute '" + key + "' without its closing quote");
        return decode(tag.substr(quote + 1, end - quote - 1), pos);
      }
      at += key.size();
    }
    return "";
  }

  std::string decode(const std::string& text, std::size_t pos) const {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] != '&') {
        out += text[i];
        continue;
      }
      const std::size_t semi = text.find(';', i);
      if (semi == std::string::npos) fail(pos, "an '&' without ';'");
      const std::string entity = text.substr(i + 1, semi - i - 1);
      if (entity == "lt") out += '<';
      else if (entity == "gt") out += '>';
      else if (entity == "amp") out += '&';
      else if (entity == "quot") out += '"';
      else if (entity == "apos") out += '\'';
      else if (entity.size() > 1 && entity[0] == '#') {
        const bool hex = entity[1] == 'x';
        char* end = nullptr;
        const long code = std::strtol(entity.c_str() + (hex ? 2 : 1), &end, hex ? 16 : 10);
        if (*end != '\0' || code <= 0 || code > 0x7F) fail(pos, "character reference '&" + entity + ";' is not ASCII");
        out += static_cast<char>(code);
      } else {
        fail(pos, "unknown entity '&" + entity + ";'");
      }
      i = semi;
    }
    return out;
  }

  // An attribute of a stream node (nodes = [..., "outInfo", ID]) or of its info child ([..., ID, "info"]).
  void store(const std::vector<std::string>& nodes, const std::string& key, const std::string& value, std::size_t pos) {
    const auto out_info = std::find(nodes.rbegin(), nodes.rend(), "outInfo");
    if (out_info == nodes.rend()) return;
    const auto depth = static_cast<std::size_t>(out_info - nodes.rbegin());  // nodes below outInfo
    const bool in_stream = depth == 1;
    const bool in_info = depth == 2 && nodes.back() == "info";
    if (!in_stream && !in_info) return;
    Stream& stream = streamNamed(nodes[nodes.size() - depth], pos);
    if (in_stream && key == "typeIdentifier") stream.type = value;
    if (in_stream && key == "originalOutputName") stream.name = value;
    if (in_info && key == "sizeX") stream.width = size(value, key, pos);
    if (in_info && key == "sizeY") stream.height = size(value, key, pos);
  }

  Stream& streamNamed(const std::string& name, std::size_t pos) {
    char* end = nullptr;
    const long id = std::strtol(name.c_str(), &end, 10);
    if (name.empty() || *end != '\0' || id < 0 || id > INT32_MAX)
      fail(pos, "stream node name '" + name + "' is not a stream id (a non-negative integer)");
    for (Stream& s : streams_) {
      if (s.id == id) return s;
    }
    streams_.push_back(Stream{});
    streams_.back().id = static_cast<int>(id);
    return streams_.back();
  }

  // sizeX / sizeY: 1..32767 (event coordinates are int16).
  int size(const std::string& value, const std::string& key, std::size_t pos) const {
    char* end = nullptr;
    const long v = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || v < 1 || v > 32767)
      fail(pos, fmt::format("{} '{}' is not a sensor dimension in 1..32767", key, value));
    return static_cast<int>(v);
  }

  const std::string& xml_;
  const std::string& path_;
  uint64_t offset_;
  std::vector<Stream> streams_;
};

}  // namespace

std::vector<Stream> parseStreams(const std::string& xml, const std::string& path, uint64_t xml_offset) {
  return InfoScanner(xml, path, xml_offset).streams();
}

}  // namespace asynevo::io_detail::aedat4

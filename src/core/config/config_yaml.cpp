// YAML loading and printing of the configuration. Sections describe their fields through
// visit(v); the two visitors here turn that description into a strict loader and a documented
// printer, so adding a field is one line in its section header.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "asynevo/core/config/config.hpp"
#include "asynevo/core/error.hpp"

namespace asynevo {

namespace {

template <class T>
const char* typeName() {
  if constexpr (std::is_same_v<T, bool>) return "true or false";
  if constexpr (std::is_integral_v<T>) return "an integer";
  if constexpr (std::is_floating_point_v<T>) return "a finite number";
  if constexpr (std::is_same_v<T, std::string>) return "a string";
  if constexpr (std::is_same_v<T, std::vector<double>>) return "a list of numbers";
  return "a value";
}

class YamlLoader {
 public:
  YamlLoader(const YAML::Node& node, const std::string& origin, std::string prefix)
      : node_(node), origin_(origin), prefix_(std::move(prefix)) {}

  template <class Section>
  void section(const char* key, Section& section) {
    known_.insert(key);
    const YAML::Node child = node_[key];
    if (!child || child.IsNull()) return;
    if (!child.IsMap()) fail(child, fmt::format("'{}{}' must be a mapping of keys", prefix_, key));
    YamlLoader sub(child, origin_, prefix_ + key + ".");
    section.visit(sub);
    sub.rejectUnknownKeys();
  }

  template <class T>
  void operator()(const char* key, T& value, const char* /*doc*/) {
    known_.insert(key);
    const YAML::Node child = node_[key];
    if (!child) return;
    const std::string full = prefix_ + key;
    try {
      if constexpr (std::is_same_v<T, std::vector<double>>) {
        if (!child.IsSequence()) throw YAML::Exception(child.Mark(), "not a sequence");
        value = child.as<std::vector<double>>();
        for (double x : value)
          if (!std::isfinite(x)) throw YAML::Exception(child.Mark(), "not finite");
      } else {
        if (!child.IsScalar()) throw YAML::Exception(child.Mark(), "not a scalar");
        value = child.as<T>();
        if constexpr (std::is_floating_point_v<T>) {
          if (!std::isfinite(value)) throw YAML::Exception(child.Mark(), "not finite");
        }
      }
    } catch (const YAML::Exception&) {
      fail(child, fmt::format("'{}' must be {}", full, typeName<T>()));
    }
  }

  void rejectUnknownKeys() const {
    for (const auto& item : node_) {
      if (!item.first.IsScalar()) {  // "? " complex keys: a mapping, list or nothing as the key
        const YAML::Node& where = item.first.Mark().line >= 0 ? item.first : node_;
        fail(where, fmt::format("a configuration key{} is {}, not a name (a stray '?' before it?)",
                                prefix_.empty() ? "" : " in '" + prefix_.substr(0, prefix_.size() - 1) + "'",
                                item.first.IsMap() ? "a mapping" : item.first.IsSequence() ? "a list" : "empty"));
      }
      const std::string key = item.first.as<std::string>();
      if (known_.count(key) == 0) {
        std::string known;
        for (const auto& k : known_) known += (known.empty() ? "" : ", ") + k;
        fail(item.first, fmt::format("unknown configuration key '{}{}' (known here: {})", prefix_, key,
                                     known));
      }
    }
  }

 private:
  [[noreturn]] void fail(const YAML::Node& where, const std::string& message) const {
    throw InputError::atLine(origin_, static_cast<uint64_t>(where.Mark().line + 1), message);
  }

  YAML::Node node_;
  const std::string& origin_;
  std::string prefix_;
  std::set<std::string> known_;
};

class YamlPrinter {
 public:
  explicit YamlPrinter(YAML::Emitter& out) : out_(out) {}

  template <class Section>
  void section(const char* key, Section& section) {
    out_ << YAML::Key << key << YAML::Value << YAML::BeginMap;
    section.visit(*this);
    out_ << YAML::EndMap;
  }

  template <class T>
  void operator()(const char* key, T& value, const char* doc) {
    out_ << YAML::Key << key << YAML::Value;
    if constexpr (std::is_floating_point_v<T>) {
      out_ << fmt::format("{}", value);  // shortest text that reads back to the same double
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      out_ << YAML::Flow << YAML::BeginSeq;
      for (double x : value) out_ << fmt::format("{}", x);
      out_ << YAML::EndSeq;
    } else {
      out_ << value;
    }
    out_ << YAML::Comment(doc);
  }

 private:
  YAML::Emitter& out_;
};

}  // namespace

void applyConfigYaml(const std::string& yaml_text, const std::string& origin, Config& config) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError::atLine(origin, static_cast<uint64_t>(e.mark.line + 1),
                             "malformed YAML: " + e.msg);
  }
  if (!root || root.IsNull()) return;  // an empty file changes nothing
  if (!root.IsMap()) throw InputError(origin, "the configuration must be a mapping of sections");
  YamlLoader loader(root, origin, "");
  config.visit(loader);
  loader.rejectUnknownKeys();
  config.validate();
  const YAML::Node sensor = root["sensor"];
  if (sensor && sensor.IsMap() && (sensor["width"] || sensor["height"])) {
    if (!sensor["width"] || !sensor["height"]) {
      throw InputError::atLine(origin, static_cast<uint64_t>(sensor.Mark().line + 1),
                               "'sensor' gives only one of width and height: give both, or neither to take the "
                               "size from the dataset");
    }
    config.sensor.set_by_file = true;
  }
}

Config loadConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open configuration file");
  std::stringstream text;
  text << in.rdbuf();
  Config config;
  applyConfigYaml(text.str(), path, config);
  return config;
}

std::string configToYaml(const Config& config) {
  Config copy = config;  // visit() is shared with the loader and therefore non-const
  YAML::Emitter out;
  out << YAML::BeginMap;
  YamlPrinter printer(out);
  copy.visit(printer);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::string configDigest(const Config& config) {
  uint64_t hash = 1469598103934665603ULL;  // FNV-1a 64
  for (unsigned char c : configToYaml(config)) {
    hash ^= c;
    hash *= 1099511628211ULL;
  }
  return fmt::format("{:016x}", hash);
}

}  // namespace asynevo

#include "sgslam/config/yaml_io.h"

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include "sgslam/common/error.h"
#include "sgslam/common/regular_file.h"
#include "sgslam/config/removed_keys.h"

namespace sgslam {

namespace fs = std::filesystem;

namespace {

std::string Where(const fs::path& file, const YAML::Node& node) {
  return file.string() + ":" + std::to_string(node.Mark().line + 1);
}

template <class T>
void ReadValue(const fs::path& file, const std::string& key, const YAML::Node& node, T& out);

// A table of named numbers (e.g. per-class weights): replaces the default table.
[[maybe_unused]] void ReadValue(const fs::path& file, const std::string& key, const YAML::Node& node, std::map<std::string, double>& out) {
  if (!node.IsMap()) throw ConfigError(Where(file, node) + ": " + key + " must be a map of name: number");
  std::map<std::string, double> table;
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    ReadValue(file, key + "." + name, kv.second, table[name]);
  }
  out = std::move(table);
}

template <class T>
void ReadValue(const fs::path& file, const std::string& key, const YAML::Node& node, T& out) {
  if (!node.IsScalar()) throw ConfigError(Where(file, node) + ": " + key + " must be a single value");
  try {
    if constexpr (std::is_same_v<T, bool>) {
      out = node.as<bool>();
    } else if constexpr (std::is_integral_v<T>) {
      // as<int>() accepts "3.7" on some yaml-cpp versions; require an integer text.
      const std::string text = node.Scalar();
      std::size_t used = 0;
      const long long v = std::stoll(text, &used);
      if (used != text.size()) throw YAML::BadConversion(node.Mark());
      // 4294967346 must not wrap round to 50.
      if (std::cmp_less(v, std::numeric_limits<T>::min()) || std::cmp_greater(v, std::numeric_limits<T>::max())) {
        throw ConfigError(Where(file, node) + ": " + key + " = " + text + " is out of range (at most " +
                          std::to_string(std::numeric_limits<T>::max()) + ")");
      }
      out = static_cast<T>(v);
    } else {
      out = node.as<T>();
    }
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception&) {
    const char* type = std::is_same_v<T, bool> ? "true or false"
                       : std::is_integral_v<T> ? "an integer"
                       : std::is_floating_point_v<T> ? "a number"
                                                     : "a string";
    throw ConfigError(Where(file, node) + ": " + key + " must be " + type + ", got '" + node.Scalar() + "'");
  }
}

}  // namespace

namespace {

// The whole configuration printed (config_used.yaml) is 8 KB: a config file a
// hundred times that is the wrong file, refused before it is read.
constexpr std::uint64_t kMaxConfigBytes = 1 << 20;

// The line of a node as an editor shows it (1-based).
int LineOf(const YAML::Node& node) { return node.Mark().line + 1; }

// A key given twice in one map, at any depth: yaml-cpp keeps the first value (and
// drops a second section whole), PyYAML the last, so an edit made below a copied
// key would be ignored without a word. `seen` holds the positions of the maps and
// lists checked, so an alias of one (the same node) is not walked again.
void CheckUniqueKeys(const fs::path& file, const YAML::Node& node, const std::string& prefix,
                     std::set<std::size_t>& seen) {
  if ((!node.IsMap() && !node.IsSequence()) || !seen.insert(static_cast<std::size_t>(node.Mark().pos)).second) return;
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) CheckUniqueKeys(file, item, prefix, seen);
    return;
  }
  std::map<std::string, int> first_line;
  for (const auto& kv : node) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "";
    if (kv.first.IsScalar()) {
      if (const auto [at, fresh] = first_line.emplace(key, LineOf(kv.first)); !fresh) {
        throw ConfigError(file.string() + ":" + std::to_string(LineOf(kv.first)) + ": '" + prefix + key +
                          "' given twice, at lines " + std::to_string(at->second) + " and " +
                          std::to_string(LineOf(kv.first)) + ": one of the two would be ignored; keep one");
      }
    }
    CheckUniqueKeys(file, kv.second, prefix + key + ".", seen);
  }
}

// The file's YAML. A file that is not a regular file (a FIFO would block the
// reader), is too large, is not YAML or repeats a key throws ConfigError naming it.
YAML::Node LoadYaml(const fs::path& file) {
  std::string text;
  try {
    text = ReadRegularFile(file, "config file", kMaxConfigBytes);
  } catch (const InputError& e) {
    throw ConfigError(e.what());
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError("cannot parse config file " + file.string() + ": " + e.what());
  }
  std::set<std::size_t> seen;
  CheckUniqueKeys(file, root, "", seen);
  return root;
}

}  // namespace

bool ConfigFileHasSection(const fs::path& file, const std::string& name) {
  const YAML::Node root = LoadYaml(file);
  return root.IsMap() && root[name];
}

namespace {

std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// " (did you mean 'x'?)" for the closest of `known` within a third of the name's
// length (a typo, not another word); empty otherwise.
std::string Suggestion(const std::string& name, const std::set<std::string>& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, name.size() / 3) + 1;
  for (const std::string& k : known) {
    if (const std::size_t d = EditDistance(name, k); d < best_distance) best = k, best_distance = d;
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

// Reads the map `node` into `section`, whose keys are `prefix` + key (sub-sections
// recursively). A key this version no longer has (removed_keys.h) goes to
// `obsolete` when it holds its last value (a config_used.yaml of an earlier
// version: the run does what it asks) and to `removed` otherwise (it cannot); other
// unknown keys go to `unknown`.
template <class S>
void ReadSection(const fs::path& file, const std::string& prefix, const YAML::Node& node, S& section,
                 std::vector<std::string>& unknown, std::vector<std::string>& removed,
                 std::vector<std::string>& obsolete) {
  std::set<std::string> known_keys;
  section.Visit([&](const char* key, auto& value, const char*) {
    known_keys.insert(key);
    const YAML::Node v = node[key];
    if (!v) return;
    if constexpr (ConfigSubsection<std::decay_t<decltype(value)>>) {
      if (!v.IsMap()) throw ConfigError(Where(file, v) + ": '" + prefix + key + "' must be a map of keys");
      ReadSection(file, prefix + key + ".", v, value, unknown, removed, obsolete);
    } else {
      ReadValue(file, prefix + key, v, value);
    }
  });
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (known_keys.count(key)) continue;
    if (const RemovedConfigKey* gone = FindRemovedConfigKey(prefix + key)) {
      const std::string text = Where(file, kv.first) + ": '" + prefix + key + "' is no longer a key: " +
                               gone->now + " (its value was " + gone->last_value + ")";
      if (kv.second.IsScalar() && SameConfigValue(kv.second.Scalar(), gone->last_value)) {
        obsolete.push_back(prefix + key);
      } else {
        removed.push_back(text + "; the file sets it to something else, which this version cannot do");
      }
      continue;
    }
    unknown.push_back(Where(file, kv.first) + ": unknown key '" + prefix + key + "'" + Suggestion(key, known_keys));
  }
}

}  // namespace

void LoadConfigFile(const fs::path& file, Config& config) {
  const YAML::Node root = LoadYaml(file);
  if (root.IsNull()) return;  // an empty file changes nothing
  if (!root.IsMap()) throw ConfigError(file.string() + ": the top level must be a map of sections");

  // A file may ask for its unknown keys to be warned about instead (one written
  // for another version of sgslam, say): `unknown_keys: warn` at its top level.
  bool strict = true;
  if (const YAML::Node policy = root[kUnknownKeysDirective]) {
    std::string value;
    ReadValue(file, kUnknownKeysDirective, policy, value);
    if (value != "error" && value != "warn") {
      throw ConfigError(Where(file, policy) + ": " + kUnknownKeysDirective + " must be error or warn, got '" + value + "'");
    }
    strict = value == "error";
  }
  std::vector<std::string> unknown, removed, obsolete;
  std::set<std::string> known_sections;
  config.VisitSections([&](const char* name, auto& section) {
    known_sections.insert(name);
    const YAML::Node node = root[name];
    if (!node) return;
    if (!node.IsMap()) throw ConfigError(Where(file, node) + ": section '" + name + "' must be a map");
    ReadSection(file, std::string(name) + ".", node, section, unknown, removed, obsolete);
  });
  if (!obsolete.empty()) {
    std::string keys;
    for (const std::string& k : obsolete) keys += (keys.empty() ? "" : ", ") + k;
    spdlog::warn("{}: {} key(s) this version no longer has hold the values it uses and are ignored: {}", file.string(),
                 obsolete.size(), keys);
  }
  for (const auto& kv : root) {
    const std::string name = kv.first.Scalar();
    if (!known_sections.count(name) && name != kUnknownKeysDirective) {
      unknown.push_back(Where(file, kv.first) + ": unknown section '" + name + "'" + Suggestion(name, known_sections));
    }
  }
  if (!strict) {
    for (const std::string& r : removed) spdlog::warn("{} ignored", r);
    for (const std::string& u : unknown) spdlog::warn("{} ignored", u);
    return;
  }
  if (!removed.empty()) {
    std::string message = "configuration keys this version no longer has (docs/configuration.md, \"Removed keys\"; '" +
                          std::string(kUnknownKeysDirective) + ": warn' at the top of the file ignores them):";
    for (const std::string& r : removed) message += "\n  " + r;
    throw ConfigError(message);
  }
  if (unknown.empty()) return;
  std::string message = "unknown configuration keys (docs/configuration.md lists them all; put '" +
                        std::string(kUnknownKeysDirective) + ": warn' at the top of the file to ignore them):";
  for (const std::string& u : unknown) message += "\n  " + u;
  throw ConfigError(message);
}

namespace {

std::string Quoted(const std::string& text) {
  YAML::Emitter quoted;
  quoted << YAML::DoubleQuoted << text;
  return quoted.c_str();
}

}  // namespace

template <class T>
std::string ConfigValueText(const T& value) {
  std::ostringstream out;
  if constexpr (std::is_same_v<T, std::map<std::string, double>>) {
    out << "{";
    for (const auto& [entry, number] : value) {
      out << (out.tellp() > 1 ? ", " : "") << Quoted(entry) << ": " << number;
    }
    out << "}";
  } else if constexpr (std::is_same_v<T, std::string>) {
    out << Quoted(value);
  } else if constexpr (std::is_same_v<T, bool>) {
    out << (value ? "true" : "false");
  } else if constexpr (std::is_floating_point_v<T>) {
    char buf[64];  // shortest text that reads back to the same double
    const auto r = std::to_chars(buf, buf + sizeof buf, value);
    out << std::string_view(buf, static_cast<std::size_t>(r.ptr - buf));
  } else {
    out << value;
  }
  return out.str();
}
template std::string ConfigValueText(const int&);
template std::string ConfigValueText(const double&);
template std::string ConfigValueText(const bool&);
template std::string ConfigValueText(const std::string&);
template std::string ConfigValueText(const std::map<std::string, double>&);

namespace {

// `section`'s keys at `indent`, sub-sections one level deeper.
template <class S>
void WriteSection(std::ostringstream& out, const std::string& indent, const S& section) {
  const_cast<S&>(section).Visit([&](const char* key, const auto& value, const char* unit) {
    out << indent << key << ":";
    using T = std::decay_t<decltype(value)>;
    if constexpr (ConfigSubsection<T>) {
      out << "  # " << unit << "\n";
      WriteSection(out, indent + "  ", value);
    } else if constexpr (std::is_same_v<T, std::map<std::string, double>>) {
      out << "  # " << unit << "\n";
      for (const auto& [entry, number] : value) out << indent << "  " << Quoted(entry) << ": " << number << "\n";
    } else {
      out << " " << ConfigValueText(value) << "  # " << unit << "\n";
    }
  });
}

}  // namespace

std::string ConfigToYaml(const Config& config) {
  std::ostringstream out;
  config.VisitSections([&](const char* name, const auto& section) {
    out << name << ":\n";
    WriteSection(out, "  ", section);
  });
  return out.str();
}

}  // namespace sgslam

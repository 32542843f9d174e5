#include "hdvio/core/config.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "hdvio/core/error.h"
#include "hdvio/core/yaml_keys.h"

namespace hdvio {

struct ConfigReader::State {
  std::string file;
  YAML::Node effective_root;
  // Keys read per map, identified by the map's key path.
  std::map<std::string, std::set<std::string>> used;
};

namespace {

long lineOf(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.line >= 0 ? m.line + 1 : 0;
}

template <class T> const char* typeName();
template <> const char* typeName<bool>() { return "a boolean (true/false)"; }
template <> const char* typeName<int>() { return "an integer"; }
template <> const char* typeName<std::int64_t>() { return "an integer"; }
template <> const char* typeName<double>() { return "a number"; }
template <> const char* typeName<std::string>() { return "a string"; }
template <> const char* typeName<std::vector<double>>() { return "a list of numbers"; }
template <> const char* typeName<std::vector<int>>() { return "a list of integers"; }
template <> const char* typeName<std::vector<std::string>>() { return "a list of strings"; }

// yaml-cpp converts leniently (e.g. 1.5 -> int fails, but "yes" -> bool succeeds); these
// wrappers reject what a user would not mean.
template <class T> bool convertScalar(const YAML::Node& n, T* out) {
  if (!n.IsScalar()) return false;
  try {
    *out = n.as<T>();
  } catch (const YAML::Exception&) {
    return false;
  }
  return true;
}
template <> bool convertScalar<double>(const YAML::Node& n, double* out) {
  if (!n.IsScalar()) return false;
  try {
    *out = n.as<double>();
  } catch (const YAML::Exception&) {
    return false;
  }
  return std::isfinite(*out);
}
template <> bool convertScalar<bool>(const YAML::Node& n, bool* out) {
  if (!n.IsScalar()) return false;
  const std::string s = n.Scalar();
  if (s == "true" || s == "True") { *out = true; return true; }
  if (s == "false" || s == "False") { *out = false; return true; }
  return false;
}
template <> bool convertScalar<std::string>(const YAML::Node& n, std::string* out) {
  if (!n.IsScalar()) return false;
  *out = n.Scalar();
  return true;
}

template <class T> bool convert(const YAML::Node& n, T* out) { return convertScalar(n, out); }
template <class E> bool convertList(const YAML::Node& n, std::vector<E>* out) {
  if (!n.IsSequence()) return false;
  std::vector<E> v;
  for (const auto& item : n) {
    E e;
    if (!convertScalar(item, &e)) return false;
    v.push_back(e);
  }
  *out = v;
  return true;
}
template <> bool convert(const YAML::Node& n, std::vector<double>* out) { return convertList(n, out); }
template <> bool convert(const YAML::Node& n, std::vector<int>* out) { return convertList(n, out); }
template <> bool convert(const YAML::Node& n, std::vector<std::string>* out) {
  return convertList(n, out);
}

template <class T> YAML::Node toYaml(const T& v) { return YAML::Node(v); }
YAML::Node toYaml(const std::vector<double>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double x : v) n.push_back(x);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

}  // namespace

void rejectDuplicateYamlKeys(const YAML::Node& node, const std::string& file) {
  if (node.IsMap()) {
    std::map<std::string, long> seen;
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      const auto [it, inserted] = seen.emplace(key, lineOf(kv.first));
      if (!inserted)
        throw InputError(file, lineOf(kv.first), "key '" + key + "' repeats the one on line " +
                                                     std::to_string(it->second));
      rejectDuplicateYamlKeys(kv.second, file);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) rejectDuplicateYamlKeys(item, file);
  }
}

ConfigReader::ConfigReader(std::shared_ptr<State> state, YAML::Node node, YAML::Node effective,
                           std::string path)
    : state_(std::move(state)), node_(node), effective_(effective), path_(std::move(path)) {}

ConfigReader ConfigReader::fromString(const std::string& yaml, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw InputError(name, e.mark.line + 1, "invalid YAML: " + e.msg);
  }
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw InputError(name, lineOf(root), "expected a map of keys at top level");
  rejectDuplicateYamlKeys(root, name);
  auto state = std::make_shared<State>();
  state->file = name;
  state->effective_root = YAML::Node(YAML::NodeType::Map);
  return ConfigReader(state, root, state->effective_root, "");
}

ConfigReader ConfigReader::fromFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return fromString(ss.str(), path);
}

const std::string& ConfigReader::file() const { return state_->file; }

std::string ConfigReader::keyPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void ConfigReader::fail(const YAML::Node& at, const std::string& key,
                        const std::string& problem) const {
  throw InputError(state_->file, lineOf(at), "key '" + keyPath(key) + "': " + problem);
}

void ConfigReader::fail(const std::string& key, const std::string& problem) const {
  const YAML::Node at = node_[key];
  fail(at.IsDefined() ? at : node_, key, problem);
}

bool ConfigReader::has(const std::string& key) const {
  return node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node ConfigReader::lookup(const std::string& key, bool required) const {
  state_->used[path_].insert(key);
  const YAML::Node n = node_[key];
  if (!n.IsDefined() || n.IsNull()) {
    if (required) fail(node_, key, "required key is missing");
    return n;
  }
  return n;
}

template <class T>
void ConfigReader::read(const std::string& key, T* value) const {
  const YAML::Node n = lookup(key, true);
  if (!convert(n, value)) fail(n, key, std::string("expected ") + typeName<T>());
  YAML::Node eff = effective_;
  eff[key] = toYaml(*value);
}

template <class T>
void ConfigReader::readOptional(const std::string& key, T* value) const {
  const YAML::Node n = lookup(key, false);
  if (has(key) && !convert(n, value)) fail(n, key, std::string("expected ") + typeName<T>());
  YAML::Node eff = effective_;
  eff[key] = toYaml(*value);
}

void ConfigReader::readInRange(const std::string& key, double* value, double lo, double hi,
                               bool required) const {
  if (required) read(key, value); else readOptional(key, value);
  if (*value < lo || *value > hi) {
    std::ostringstream msg;
    msg << "value " << *value << " out of range [" << lo << ", " << hi << "]";
    fail(node_[key].IsDefined() ? node_[key] : node_, key, msg.str());
  }
}

void ConfigReader::readInRange(const std::string& key, int* value, int lo, int hi,
                               bool required) const {
  if (required) read(key, value); else readOptional(key, value);
  if (*value < lo || *value > hi) {
    std::ostringstream msg;
    msg << "value " << *value << " out of range [" << lo << ", " << hi << "]";
    fail(node_[key].IsDefined() ? node_[key] : node_, key, msg.str());
  }
}

void ConfigReader::readVector(const std::string& key, std::vector<double>* value,
                              std::size_t size, bool required) const {
  if (required) read(key, value); else readOptional(key, value);
  if (value->size() != size)
    fail(node_[key].IsDefined() ? node_[key] : node_, key,
         "expected a list of " + std::to_string(size) + " numbers, got " +
             std::to_string(value->size()));
}

void ConfigReader::readChoice(const std::string& key, std::string* value,
                              const std::vector<std::string>& choices, bool required) const {
  if (required) read(key, value); else readOptional(key, value);
  for (const auto& c : choices)
    if (c == *value) return;
  std::string all;
  for (const auto& c : choices) all += (all.empty() ? "" : ", ") + c;
  fail(node_[key].IsDefined() ? node_[key] : node_, key,
       "'" + *value + "' is not one of: " + all);
}

ConfigReader ConfigReader::section(const std::string& key) const {
  const YAML::Node n = lookup(key, true);
  if (!n.IsMap()) fail(n, key, "expected a map");
  YAML::Node eff = effective_;
  eff[key] = YAML::Node(YAML::NodeType::Map);
  state_->used[keyPath(key)];  // opened: finish() checks its keys too
  return ConfigReader(state_, n, eff[key], keyPath(key));
}

ConfigReader ConfigReader::optionalSection(const std::string& key) const {
  if (has(key)) return section(key);
  state_->used[path_].insert(key);
  YAML::Node eff = effective_;
  eff[key] = YAML::Node(YAML::NodeType::Map);
  return ConfigReader(state_, YAML::Node(YAML::NodeType::Map), eff[key], keyPath(key));
}

std::vector<ConfigReader> ConfigReader::list(const std::string& key) const {
  const YAML::Node n = lookup(key, true);
  if (!n.IsSequence()) fail(n, key, "expected a list");
  YAML::Node eff = effective_;
  eff[key] = YAML::Node(YAML::NodeType::Sequence);
  std::vector<ConfigReader> out;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const std::string item_path = keyPath(key) + "[" + std::to_string(i) + "]";
    if (!n[i].IsMap())
      throw InputError(state_->file, lineOf(n[i]), "key '" + item_path + "': expected a map");
    eff[key].push_back(YAML::Node(YAML::NodeType::Map));
    state_->used[item_path];
    out.push_back(ConfigReader(state_, n[i], eff[key][i], item_path));
  }
  return out;
}

void ConfigReader::finish() const {
  const auto& used = state_->used[path_];
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (!used.count(key)) fail(kv.first, key, "unknown key");
  }
  // Sections and list items opened from this map are checked as well, so a typo deep inside a
  // section is caught even if its reader forgot to call finish().
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (kv.second.IsMap() && state_->used.count(keyPath(key))) {
      ConfigReader(state_, kv.second, YAML::Node(), keyPath(key)).finish();
    } else if (kv.second.IsSequence()) {
      for (std::size_t i = 0; i < kv.second.size(); ++i) {
        const std::string item_path = keyPath(key) + "[" + std::to_string(i) + "]";
        if (kv.second[i].IsMap() && state_->used.count(item_path))
          ConfigReader(state_, kv.second[i], YAML::Node(), item_path).finish();
      }
    }
  }
}

void ConfigReader::recordEffective(const std::string& key, double value) const {
  YAML::Node eff = effective_;
  eff[key] = toYaml(value);
}

void ConfigReader::recordEffective(const std::string& key, const std::vector<double>& value) const {
  YAML::Node eff = effective_;
  eff[key] = toYaml(value);
}

std::string ConfigReader::effectiveYaml() const {
  YAML::Emitter out;
  out << state_->effective_root;
  return std::string(out.c_str()) + "\n";
}

#define HDVIO_INSTANTIATE(T)                                                   \
  template void ConfigReader::read<T>(const std::string&, T*) const;           \
  template void ConfigReader::readOptional<T>(const std::string&, T*) const;
HDVIO_INSTANTIATE(bool)
HDVIO_INSTANTIATE(int)
HDVIO_INSTANTIATE(std::int64_t)
HDVIO_INSTANTIATE(double)
HDVIO_INSTANTIATE(std::string)
HDVIO_INSTANTIATE(std::vector<double>)
HDVIO_INSTANTIATE(std::vector<int>)
HDVIO_INSTANTIATE(std::vector<std::string>)
#undef HDVIO_INSTANTIATE

}  // namespace hdvio

#pragma once
// Strict YAML configuration. Every key a program reads is recorded; finish() turns any key
// that was never read into an error, so a typo never silently falls back to a default.
// Errors name the file, the line and the key path. effectiveYaml() returns everything read,
// defaults included, for writing next to results.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace hdvio {

class ConfigReader {
 public:
  static ConfigReader fromFile(const std::string& path);
  static ConfigReader fromString(const std::string& yaml, const std::string& name = "<string>");

  bool has(const std::string& key) const;

  // Supported T: bool, int, int64_t, double, std::string, std::vector<double>,
  // std::vector<int>, std::vector<std::string>.
  template <class T> void read(const std::string& key, T* value) const;          // required
  template <class T> void readOptional(const std::string& key, T* value) const;  // *value = default
  void readInRange(const std::string& key, double* value, double lo, double hi,
                   bool required = false) const;
  void readInRange(const std::string& key, int* value, int lo, int hi, bool required = false) const;
  // A list of exactly `size` numbers.
  void readVector(const std::string& key, std::vector<double>* value, std::size_t size,
                  bool required = false) const;
  void readChoice(const std::string& key, std::string* value,
                  const std::vector<std::string>& choices, bool required = false) const;
  // A choice read by name straight into its enum (the names are what the YAML and the
  // effective configuration show); *value is the default and must be one of the choices.
  template <class E>
  void readEnum(const std::string& key, E* value,
                const std::vector<std::pair<std::string, E>>& choices,
                bool required = false) const {
    std::string name;
    std::vector<std::string> names;
    for (const auto& [n, e] : choices) {
      names.push_back(n);
      if (e == *value) name = n;
    }
    readChoice(key, &name, names, required);
    for (const auto& [n, e] : choices)
      if (n == name) *value = e;
  }

  ConfigReader section(const std::string& key) const;  // nested map, required
  // Nested map if present, else an empty one, so every default read from it is still written
  // to the effective configuration.
  ConfigReader optionalSection(const std::string& key) const;
  std::vector<ConfigReader> list(const std::string& key) const;  // sequence of maps, required

  // Throws InputError naming every key of this map that was never read.
  void finish() const;
  // Throws InputError for a problem a program finds in a key's value (or, for a key that is
  // absent, in this map): the file, the line of the key (or of the map) and the key path.
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  // Replaces a key's value in the effective configuration: for a default a program decides
  // from the data (e.g. the IMU noise of a dataset's sensor.yaml), so the file says what ran.
  void recordEffective(const std::string& key, double value) const;
  void recordEffective(const std::string& key, const std::vector<double>& value) const;
  std::string effectiveYaml() const;
  const std::string& file() const;
  const std::string& path() const { return path_; }  // key path of this map, e.g. "sim.wind"

 private:
  struct State;
  ConfigReader(std::shared_ptr<State> state, YAML::Node node, YAML::Node effective,
               std::string path);
  YAML::Node lookup(const std::string& key, bool required) const;
  [[noreturn]] void fail(const YAML::Node& at, const std::string& key,
                         const std::string& problem) const;
  std::string keyPath(const std::string& key) const;

  std::shared_ptr<State> state_;
  YAML::Node node_;
  YAML::Node effective_;
  std::string path_;
};

}  // namespace hdvio

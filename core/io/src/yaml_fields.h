#pragma once
// A YAML map of calibration fields (ASL sensor.yaml, Kalibr camchain/imu yaml) whose errors
// carry the file and the line of the offending key.
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio::io {

class YamlFields {
 public:
  // Parses the file; throws InputError unless it is a YAML map without repeated keys.
  explicit YamlFields(const std::string& path);

  // The map under key (Kalibr's cam0: / imu0:), reporting errors against the same file.
  YamlFields child(const std::string& key) const;

  bool has(const std::string& key) const { return static_cast<bool>(root_[key]); }
  YAML::Node node(const std::string& key) const;
  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& problem) const;
  // Throws at the first key not in allowed.
  void rejectUnknownKeys(std::initializer_list<const char*> allowed) const;

  double number(const YAML::Node& n, const std::string& key) const;
  double number(const std::string& key) const { return number(node(key), key); }
  std::vector<double> numbers(const std::string& key, int expected_size) const;
  std::string text(const std::string& key) const;
  // EuRoC's {rows: 4, cols: 4, data: [16 values]} rigid transform.
  Pose transform(const std::string& key) const;
  // Kalibr's rigid transform: four rows of four numbers.
  Pose transformRows(const std::string& key) const;

  const std::string& path() const { return path_; }

 private:
  YamlFields(std::string path, YAML::Node root) : path_(std::move(path)), root_(std::move(root)) {}
  Pose rigid(const Mat4& T, const YAML::Node& n, const std::string& key) const;

  std::string path_;
  YAML::Node root_;
};

}  // namespace hdvio::io

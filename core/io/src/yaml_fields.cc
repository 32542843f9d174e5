#include "yaml_fields.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "hdvio/core/error.h"
#include "hdvio/core/yaml_keys.h"

namespace hdvio::io {

YamlFields::YamlFields(const std::string& path) : path_(path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  // OpenCV's "%YAML:1.0" directive is not YAML 1.2; blank it but keep the line numbering.
  if (text.rfind("%YAML", 0) == 0) {
    const std::size_t eol = text.find('\n');
    text.replace(0, eol == std::string::npos ? text.size() : eol, "");
  }
  try {
    root_ = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
  }
  if (!root_.IsMap()) throw InputError(path, 0, "expected a YAML map of sensor parameters");
  rejectDuplicateYamlKeys(root_, path);
}

YamlFields YamlFields::child(const std::string& key) const {
  const YAML::Node n = node(key);
  if (!n.IsMap()) fail(n, key, "expected a map");
  return YamlFields(path_, n);
}

YAML::Node YamlFields::node(const std::string& key) const {
  YAML::Node n = root_[key];
  if (!n) throw InputError(path_, 0, "missing key '" + key + "'");
  return n;
}

void YamlFields::fail(const YAML::Node& n, const std::string& key, const std::string& problem) const {
  throw InputError(path_, n.Mark().line + 1, "key '" + key + "': " + problem);
}

void YamlFields::rejectUnknownKeys(std::initializer_list<const char*> allowed) const {
  for (const auto& kv : root_) {
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    for (const char* a : allowed) known = known || key == a;
    if (known) continue;
    std::string list;
    for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw InputError(path_, kv.first.Mark().line + 1, "unknown key '" + key + "' (known: " + list + ")");
  }
}

double YamlFields::number(const YAML::Node& n, const std::string& key) const {
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(n, key, "expected a number");
  }
  if (!std::isfinite(v)) fail(n, key, "non-finite value");
  return v;
}

std::vector<double> YamlFields::numbers(const std::string& key, int expected_size) const {
  const YAML::Node n = node(key);
  if (!n.IsSequence()) fail(n, key, "expected a list of numbers");
  if (expected_size >= 0 && static_cast<int>(n.size()) != expected_size) {
    fail(n, key, "expected " + std::to_string(expected_size) + " values, found " + std::to_string(n.size()));
  }
  std::vector<double> out;
  for (const auto& item : n) out.push_back(number(item, key));
  return out;
}

std::string YamlFields::text(const std::string& key) const {
  const YAML::Node n = node(key);
  if (!n.IsScalar()) fail(n, key, "expected a string");
  return n.as<std::string>();
}

Pose YamlFields::transform(const std::string& key) const {
  const YAML::Node n = node(key);
  if (!n.IsMap() || !n["rows"] || !n["cols"] || !n["data"]) fail(n, key, "expected a map with rows, cols and data");
  if (number(n["rows"], key + ".rows") != 4 || number(n["cols"], key + ".cols") != 4)
    fail(n, key, "expected a 4x4 matrix");
  const YAML::Node d = n["data"];
  if (!d.IsSequence() || d.size() != 16) fail(d, key + ".data", "expected 16 values");
  Mat4 T;
  for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = number(d[i], key + ".data");
  return rigid(T, d, key);
}

Pose YamlFields::transformRows(const std::string& key) const {
  const YAML::Node n = node(key);
  if (!n.IsSequence() || n.size() != 4) fail(n, key, "expected four rows of four numbers");
  Mat4 T;
  for (int r = 0; r < 4; ++r) {
    const YAML::Node row = n[r];
    if (!row.IsSequence() || row.size() != 4) fail(row, key, "expected four rows of four numbers");
    for (int c = 0; c < 4; ++c) T(r, c) = number(row[c], key);
  }
  return rigid(T, n, key);
}

Pose YamlFields::rigid(const Mat4& T, const YAML::Node& n, const std::string& key) const {
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    fail(n, key, "last row must be [0, 0, 0, 1]");
  const Mat3 R = T.topLeftCorner<3, 3>();
  const double orthonormality = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality > 1e-6 || R.determinant() < 0.0) {
    fail(n, key, "rotation part is not orthonormal (max |R^T R - I| = " + std::to_string(orthonormality) +
                     ", det = " + std::to_string(R.determinant()) + ")");
  }
  return Pose(normalizeRotation(R), Vec3(T.topRightCorner<3, 1>()));
}

}  // namespace hdvio::io

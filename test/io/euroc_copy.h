#pragma once
// Private, editable copies of the EuRoC excerpt for the bad-input tests, and line editing.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_data.h"

namespace hdvio::io::test {

inline std::vector<std::string> readLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

inline void writeLines(const std::string& path, const std::vector<std::string>& lines, const char* eol = "\n") {
  std::ofstream out(path, std::ios::trunc | std::ios::binary);
  for (const auto& l : lines) out << l << eol;
}

// Line numbers are 1-based as in the error messages.
inline void editLine(const std::string& path, int line, const std::string& text) {
  auto lines = readLines(path);
  lines.at(line - 1) = text;
  writeLines(path, lines);
}

// Copies the excerpt's CSV and YAML files to <root>/mav0 and links its images: the whole image
// folder, or (images_one_by_one) each image, so that a test may replace single images.
inline void copyEurocExcerpt(const std::filesystem::path& root, bool images_one_by_one = false) {
  namespace fs = std::filesystem;
  const fs::path src = fs::path(dataPath(kEuroc)) / "mav0";
  const fs::path mav0 = root / "mav0";
  for (const char* rel : {"imu0/data.csv", "imu0/sensor.yaml", "cam0/data.csv", "cam0/sensor.yaml",
                          "state_groundtruth_estimate0/data.csv"}) {
    fs::create_directories((mav0 / rel).parent_path());
    fs::copy_file(src / rel, mav0 / rel);
    fs::permissions(mav0 / rel, fs::perms::owner_read | fs::perms::owner_write);
  }
  if (!images_one_by_one) {
    fs::create_directory_symlink(src / "cam0" / "data", mav0 / "cam0" / "data");
    return;
  }
  fs::create_directories(mav0 / "cam0" / "data");
  for (const auto& e : fs::directory_iterator(src / "cam0" / "data"))
    fs::create_symlink(e.path(), mav0 / "cam0" / "data" / e.path().filename());
}

}  // namespace hdvio::io::test

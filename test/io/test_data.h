#pragma once
// Paths of the real recordings used by the io tests; tests skip when the data folder is absent.
#include <unistd.h>

#include <filesystem>
#include <string>

namespace hdvio::io::test {

inline std::string dataPath(const std::string& relative) {
  return (std::filesystem::path(HDVIO_DATA_DIR) / relative).string();
}

inline const char* kEuroc = "euroc/V1_01_easy_excerpt";
inline const char* kBlackbirdTrain = "blackbird/clover_yawForward_maxSpeed5p0/train";
inline const char* kBlackbirdVal = "blackbird/clover_yawForward_maxSpeed5p0/val";
// meas_rpm layouts: 5 columns (timestamp first) in the 2022 circle/updown/random flights,
// 4 columns in the 2021 "v_*" flights.
inline const char* kDido5Col = "dido/circle_a_1.5_v_2.5_r_1.5_yaw_2022-02-21-23-25-15";
inline const char* kDido4Col = "dido/v_1.4_a_2.0_s_1_yaw_0_n_3_2021-12-29-20-43-00_2_";
inline const char* kNeuroBem = "neurobem/figure8_1_bemnn20210218170320seg2.csv";

// A fresh directory under the system temp folder, removed with everything in it at scope exit.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("hdvio_io_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string operator/(const std::string& rel) const { return (path_ / rel).string(); }

 private:
  std::filesystem::path path_;
};

#define HDVIO_REQUIRE_DATA(rel)                                                          \
  do {                                                                                   \
    if (!std::filesystem::exists(::hdvio::io::test::dataPath(rel)))                      \
      GTEST_SKIP() << "real data not found: " << ::hdvio::io::test::dataPath(rel);       \
  } while (0)

}  // namespace hdvio::io::test

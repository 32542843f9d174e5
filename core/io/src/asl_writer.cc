#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/csv.h"
#include "hdvio/io/image.h"
#include "sensor_yaml.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

void writeFile(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw InputError(file.string(), 0, "cannot write file");
}

// Appends "t,v1,...,vn\n" with full precision.
void appendRow(std::string* s, Timestamp t, std::initializer_list<double> values) {
  *s += std::to_string(t);
  for (double v : values) {
    *s += ',';
    *s += formatDouble(v);
  }
  *s += '\n';
}

std::string imuCsv(const Sequence& seq) {
  std::string s =
      "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
      "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
  for (const auto& m : seq.imu)
    appendRow(&s, m.t, {m.gyro.x(), m.gyro.y(), m.gyro.z(), m.accel.x(), m.accel.y(), m.accel.z()});
  return s;
}

std::string groundTruthCsv(const Sequence& seq) {
  bool velocity = true, biases = true;
  for (const auto& g : seq.groundtruth) {
    velocity = velocity && g.has_velocity;
    biases = biases && g.has_biases;
  }
  biases = biases && velocity;  // the 17-column layout includes velocity
  std::string s = "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []";
  if (velocity) s += ", v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1]";
  if (biases) {
    s += ", b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1]"
         ", b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]";
  }
  s += '\n';
  for (const auto& g : seq.groundtruth) {
    const Vec3& p = g.T_WB.p;
    const Quat& q = g.T_WB.q;
    s += std::to_string(g.t);
    for (double v : {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()}) s += "," + formatDouble(v);
    if (velocity) for (int i = 0; i < 3; ++i) s += "," + formatDouble(g.v_W[i]);
    if (biases) {
      for (int i = 0; i < 3; ++i) s += "," + formatDouble(g.gyro_bias[i]);
      for (int i = 0; i < 3; ++i) s += "," + formatDouble(g.accel_bias[i]);
    }
    s += '\n';
  }
  return s;
}

// Copies images into stage/cam0/data unless they already live in final/cam0/data (images in
// a container are written out as PNG); returns the
// cam0/data.csv text.
std::string stageImages(const Sequence& seq, const fs::path& final_mav0, const fs::path& stage_mav0) {
  const fs::path final_dir = fs::weakly_canonical(final_mav0 / "cam0" / "data");
  std::string s = "#timestamp [ns],filename\n";
  fs::create_directories(stage_mav0 / "cam0" / "data");
  for (const auto& image : seq.images) {
    if (image.span) {  // inside a container (a ROS bag): decoded and written as a lossless PNG
      const std::string name = std::to_string(image.t) + ".png";
      const fs::path dst = stage_mav0 / "cam0" / "data" / name;
      if (!cv::imwrite(dst.string(), loadImage(image))) throw InputError(dst.string(), 0, "cannot write image");
      s += std::to_string(image.t) + "," + name + "\n";
      continue;
    }
    const fs::path src = fs::weakly_canonical(fs::absolute(image.path));
    if (!fs::is_regular_file(src)) throw InputError(image.path, 0, "image file does not exist");
    std::string name;
    if (src.parent_path() == final_dir) {
      name = src.filename().string();
    } else {
      name = std::to_string(image.t) + src.extension().string();
      std::error_code ec;
      fs::copy_file(src, stage_mav0 / "cam0" / "data" / name, fs::copy_options::overwrite_existing, ec);
      if (ec) throw InputError(src.string(), 0, "cannot copy image: " + ec.message());
    }
    s += std::to_string(image.t) + "," + name + "\n";
  }
  return s;
}

void stageSequence(const Sequence& seq, const fs::path& final_mav0, const fs::path& m) {
  writeFile(m / "imu0" / "data.csv", imuCsv(seq));
  if (seq.imu_calibration) writeFile(m / "imu0" / "sensor.yaml", imuSensorYaml(*seq.imu_calibration));
  if (seq.camera) {
    validateCamera(*seq.camera, "camera calibration of sequence " + seq.name);
    writeFile(m / "cam0" / "sensor.yaml", cameraSensorYaml(*seq.camera));
    writeFile(m / "cam0" / "data.csv", stageImages(seq, final_mav0, m));
  }
  if (!seq.thrust.empty()) {
    std::string s = "#timestamp [ns],T_x [m s^-2],T_y [m s^-2],T_z [m s^-2]\n";
    for (const auto& x : seq.thrust) appendRow(&s, x.t, {x.thrust.x(), x.thrust.y(), x.thrust.z()});
    writeFile(m / "thrust0" / "data.csv", s);
  }
  if (!seq.rotor.empty()) {
    std::string s = "#timestamp [ns],w_1 [rad s^-1],w_2 [rad s^-1],w_3 [rad s^-1],w_4 [rad s^-1]\n";
    for (const auto& r : seq.rotor) appendRow(&s, r.t, {r.speeds[0], r.speeds[1], r.speeds[2], r.speeds[3]});
    writeFile(m / "rotor0" / "data.csv", s);
    if (seq.rotor_calibration) writeFile(m / "rotor0" / "sensor.yaml", rotorSensorYaml(*seq.rotor_calibration));
  }
  if (!seq.groundtruth.empty()) writeFile(m / "state_groundtruth_estimate0" / "data.csv", groundTruthCsv(seq));
  if (!seq.forces.empty()) {
    std::string s = "#timestamp [ns],f_ext_x [m s^-2],f_ext_y [m s^-2],f_ext_z [m s^-2],"
                    "f_drag_x [m s^-2],f_drag_y [m s^-2],f_drag_z [m s^-2]\n";
    for (const auto& f : seq.forces)
      appendRow(&s, f.t, {f.external.x(), f.external.y(), f.external.z(), f.drag.x(), f.drag.y(), f.drag.z()});
    writeFile(m / "force_groundtruth0" / "data.csv", s);
  }
  if (!seq.landmarks.empty() || !seq.landmark_observations.empty()) {
    std::string p = "#landmark_id,p_x [m],p_y [m],p_z [m]\n";
    for (const auto& [id, x] : seq.landmarks)
      p += std::to_string(id) + "," + formatDouble(x.x()) + "," + formatDouble(x.y()) + "," + formatDouble(x.z()) + "\n";
    writeFile(m / "landmarks0" / "points.csv", p);
    std::string o = "#timestamp [ns],landmark_id,u [px],v [px]\n";
    for (const auto& ob : seq.landmark_observations)
      o += std::to_string(ob.t) + "," + std::to_string(ob.landmark_id) + "," + formatDouble(ob.u) + "," +
           formatDouble(ob.v) + "\n";
    writeFile(m / "landmarks0" / "data.csv", o);
  }
}

// Moves every staged file into the destination tree (which already exists).
void mergeInto(const fs::path& stage, const fs::path& out) {
  for (const auto& entry : fs::recursive_directory_iterator(stage)) {
    if (!entry.is_regular_file()) continue;
    const fs::path target = out / fs::relative(entry.path(), stage);
    fs::create_directories(target.parent_path());
    fs::rename(entry.path(), target);
  }
  fs::remove_all(stage);
}

}  // namespace

void writeAsl(const Sequence& seq, const std::string& out_folder) {
  if (seq.imu.empty()) throw InputError(out_folder, 0, "refusing to write a sequence without IMU samples");
  if (!seq.images.empty() && !seq.camera)
    throw InputError(out_folder, 0, "sequence lists images but has no camera calibration");
  fs::path out = fs::absolute(out_folder).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  const fs::path stage =
      out.parent_path() / ("." + out.filename().string() + ".partial-" + std::to_string(::getpid()));
  try {
    fs::remove_all(stage);
    stageSequence(seq, out / "mav0", stage / "mav0");
    if (!fs::exists(out)) {
      fs::rename(stage, out);
    } else {
      mergeInto(stage, out);
    }
  } catch (const fs::filesystem_error& e) {
    std::error_code ignored;
    fs::remove_all(stage, ignored);
    throw InputError(e.path1().string(), 0, std::string("cannot write: ") + e.code().message());
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(stage, ignored);
    throw;
  }
}

}  // namespace hdvio::io

#pragma once
// Turns a SimConfig into a Sequence: IMU (noise + bias random walk), ground truth at the IMU
// rate, thrust channel (miscalibration, lag, noise), rotor speeds, ground-truth forces,
// camera calibration, rendered images and ground-truth landmark tracks.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "hdvio/core/camera_model.h"
#include "hdvio/core/sequence.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/sim/renderer.h"
#include "hdvio/sim/scene.h"
#include "hdvio/sim/sim_config.h"
#include "hdvio/sim/vehicle_model.h"

namespace hdvio::sim {

struct SimulationResult {
  Sequence sequence;
  std::vector<TrueState> states;  // at the IMU timestamps (true thrust, forces, rates)
  int clamped_rotor_samples = 0;  // rotor would need negative thrust (speed set to 0)
  io::GateData gates;  // race with a camera: gate corner map and detections (else empty)
};

class Simulator {
 public:
  // Builds the model, scene and renderer; throws InputError for impossible configurations.
  explicit Simulator(const SimConfig& config);
  ~Simulator();

  // Everything except images. With a camera: calibration, landmarks and their tracks.
  SimulationResult simulate() const;
  // Renders all frames as PNGs into image_dir and lists them in result->sequence.images.
  void renderImages(SimulationResult* result, const std::string& image_dir) const;

  // One 8-bit frame at time t (s since start), with the configured noise/exposure/blur.
  cv::Mat renderFrame(double time, int frame_index) const;
  Pose cameraPose(double time) const;  // T_WC

  Timestamp timestampOf(double time) const { return config_.start_time_ns + fromSeconds(time); }
  const VehicleModel& model() const { return model_; }
  const CameraModel* camera() const { return camera_.get(); }
  const Scene* scene() const { return scene_.get(); }
  const SimConfig& config() const { return config_; }

 private:
  std::vector<double> cameraTimes() const;

  SimConfig config_;
  VehicleModel model_;
  std::unique_ptr<CameraModel> camera_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Renderer> renderer_;
};

// Camera calibration of a simulated sequence (what cam0/sensor.yaml says).
CameraCalibration cameraCalibrationOf(const CameraSimConfig& config);

}  // namespace hdvio::sim

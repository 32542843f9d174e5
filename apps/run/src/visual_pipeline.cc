// Visual methods (vio, vimo, vid, hdvio): the sliding-window backend over a sequence's frames,
// whose landmark observations come from the semi-direct frontend on cam0 images or from the
// simulator's landmark tracks (`frontend.source`); see docs/visual_pipeline.md.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "hdvio/core/error.h"
#include "hdvio/learned/residual_force_provider.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/progress.h"
#include "hdvio/pipeline/visual_frontend_config_loader.h"

namespace hdvio::run {
namespace {

class VisualPipeline : public MethodPipeline {
 public:
  VisualPipeline(const std::string& method, const ConfigReader& cfg, const ExperimentFile& file)
      : method_(parseVioMethod(method)), file_(file), backend_cfg_(cfg.optionalSection("backend")) {
    options_ = loadVioBackendOptions(backend_cfg_, method_);
    const ConfigReader r = cfg.optionalSection("run");
    r.readOptional("init_from_groundtruth", &run_.init_from_groundtruth);
    // The start (VioStarter, on tracks and images alike): visual-inertial initialization, static
    // when the start is at rest or the initialization times out, ground truth as an option.
    r.readOptional("visual_inertial_init", &run_.visual_inertial_init);
    r.readInRange("vi_init_window_s", &run_.vi_init_window_s, 0.5, 10.0);
    r.readInRange("vi_init_timeout_s", &run_.vi_init_timeout_s, 0.0, 60.0);
    // Prior sigmas of a static start's guessed velocity (m/s) and tilt (rad).
    r.readInRange("guess_velocity_sigma", &run_.guess_velocity_sigma, 1e-3, 100.0);
    r.readInRange("guess_tilt_sigma", &run_.guess_tilt_sigma, 1e-4, 1.0);
    r.readInRange("pixel_noise_sigma", &run_.pixel_noise_sigma, 0.0, 100.0);
    r.readInRange("image_noise_sigma", &run_.image_noise_sigma, 0.0, 50.0);
    int seed = static_cast<int>(run_.seed);
    r.readInRange("seed", &seed, 0, 1 << 30);
    run_.seed = static_cast<std::uint32_t>(seed);
    // Only the first seconds of the flight (from its first image; without images, its first
    // IMU sample): profiles and quick checks. 0 = the whole flight.
    r.readInRange("duration_s", &duration_s_, 0.0, 1e6);
    r.finish();
    frontend_ = loadVisualFrontendConfig(cfg.optionalSection("frontend"));
    // hdvio: the learned residual force (residual_force: {type: tcn, weights: ...}); zero if
    // absent. type ground_truth (diagnostics, simulated flights) uses the sequence's true drag.
    if (cfg.has("residual_force")) {
      if (method_ != VioMethod::kHdvio)
        throw InputError(file.path, 0, "residual_force is only used by method hdvio");
      const ConfigReader rf = cfg.section("residual_force");
      std::string type;
      rf.readChoice("type", &type, {"zero", "tcn", "ground_truth"}, true);
      if (type == "ground_truth") {
        rf.finish();
        if (options_.dynamics.drag.enabled())  // the true drag already is all of it
          throw InputError(file.path, 0,
                           "residual_force type ground_truth is the whole drag; drop "
                           "backend.drag_linear / drag_quadratic");
        ground_truth_residual_ = true;
      } else {
        provider_ = learned::makeResidualForceProvider(rf, file.dir);
        adoptDragLaw(provider_->dragLaw(), file.path);
        adoptModelForceWalk(provider_->forceWalk(), backend_cfg_, &options_);
        adoptModelEnvelope(provider_->envelope(), backend_cfg_, &options_);
      }
    }
  }

  RunResults run(const Sequence& seq) override {
    if (duration_s_ <= 0.0 || (seq.images.empty() && seq.imu.empty())) return runOn(seq);
    const Timestamp start = seq.images.empty() ? seq.imu.front().t : seq.images.front().t;
    const Timestamp end = start + fromSeconds(duration_s_);
    RunResults results = runOn(sequenceUntil(seq, end));
    results.input_span = {start, end};
    return results;
  }

 private:
  RunResults runOn(const Sequence& seq) {
    VioBackendOptions options = options_;
    if (seq.imu_calibration) adoptImuNoise(*seq.imu_calibration, backend_cfg_, &options);
    const std::vector<ThrustSample> thrust = thrustSamples(seq);
    if (ground_truth_residual_) {
      if (seq.forces.empty())
        throw InputError(seq.name, 0,
                         "residual_force type ground_truth needs the simulator's "
                         "force_groundtruth0/; the sequence has none");
      provider_ = std::make_shared<learned::GroundTruthResidualForceProvider>(seq.forces);
    }
    if (usesDynamics(method_) && thrust.empty())
      throw InputError(seq.name, 0,
                       "method needs thrust: collective thrust (thrust0/ or rotor speeds with a "
                       "rotor calibration), the sequence has none");
    RunResults results;
    VioRunOutput out;
    std::vector<double> backend_ms;  // per image (on images; per frame on tracks: timing.csv)
    if (resolveObservationSource(frontend_.source, seq) == ObservationSource::kTracks) {
      out = runVioOnTracks(seq, options, run_, provider_);
      std::fprintf(stderr, "hdvio_run: started from the %s initialization at %.2f s\n",
                   toString(out.start).c_str(), toSeconds(out.start_t - seq.imu.front().t));
    } else {
      Progress progress(toString(method_) + " (images)", seq.images.front().t, seq.images.back().t);
      ImageRunOutput images = runVioOnImages(seq, options, run_, frontend_, provider_, true,
                                             [&progress](Timestamp t) { progress.update(t); });
      progress.finish();
      out = std::move(images.vio);
      results.stages.push_back({"initialization", images.init_time_s, images.init_images});
      results.stages.push_back({"image_loading", images.load_time_s,
                                static_cast<int>(images.images.size())});
      StageTiming frontend{"frontend", images.frontend_time_s,
                           static_cast<int>(images.images.size()), {}};
      backend_ms.reserve(images.images.size());
      for (const ImageFrameRecord& im : images.images) {
        results.images.push_back({im.t, im.load_ms, im.frontend_ms, im.backend_ms,
                                  im.tracked_features, im.frontend_keyframe != 0,
                                  im.used_by_backend});
        frontend.call_ms.push_back(im.frontend_ms);
        backend_ms.push_back(im.backend_ms);
      }
      results.stages.push_back(std::move(frontend));
      // The frontend's parts, named "frontend/<part>": a breakdown of the row above, not a
      // further stage (hdvio_bench leaves them out of the runtime sum).
      const std::pair<const char*, double frontend::FrameTiming::*> parts[] = {
          {"pyramid", &frontend::FrameTiming::pyramid_ms},
          {"alignment", &frontend::FrameTiming::alignment_ms},
          {"reprojection", &frontend::FrameTiming::reprojection_ms},
          {"optimization", &frontend::FrameTiming::optimization_ms},
          {"depth_filter", &frontend::FrameTiming::depth_filter_ms},
          {"keyframe", &frontend::FrameTiming::keyframe_ms}};
      for (const auto& [name, field] : parts) {
        StageTiming part{std::string("frontend/") + name, 0.0,
                         static_cast<int>(images.images.size()), {}};
        for (const ImageFrameRecord& im : images.images) {
          part.call_ms.push_back(im.frontend_stages.*field);
          part.total_s += 1e-3 * im.frontend_stages.*field;
        }
        results.stages.push_back(std::move(part));
      }
    }

    results.states = out.states;
    results.has_force = usesDynamics(method_);
    // The model's force (learned residual + drag law), evaluated by the estimator after the run.
    results.residual_force_B = out.model_force_B;
    for (const auto& f : out.frames)
      results.timing.push_back({f.state.t, 1e3 * f.solve_time_s, f.solver_iterations,
                                f.landmarks_in_window, f.observations_used, f.keyframe});
    results.stages.push_back({"backend", out.backend_time_s, static_cast<int>(out.frames.size()),
                              std::move(backend_ms)});
    return results;
  }

  // A network trained on what a drag law leaves (weight file version 3) brings the law: the
  // dynamics add it at the state's velocity. backend.drag_* may repeat its coefficients, not
  // contradict them. The file's sigma is the law's own residual, which the network was trained
  // to explain, so it is not the hybrid model's error: the dynamics use it only when
  // backend.drag_sigma* asks for a sigma (with it they had 2.5x the ATE on random_v5_wind,
  // docs/benchmarks.md). The network's own error does not reach the factor yet.
  void adoptDragLaw(const DragLaw& law, const std::string& config_path) {
    if (!law.enabled()) return;
    DragLaw& drag = options_.dynamics.drag;
    const auto same = [](const Vec3& a, const Vec3& b) { return (a - b).norm() <= 1e-6 * std::max(1.0, b.norm()); };
    if (drag.enabled() && (!same(drag.linear, law.linear) || !same(drag.quadratic, law.quadratic) ||
                           !same(drag.rotor, law.rotor) || std::abs(drag.lift - law.lift) > 1e-9))
      throw InputError(config_path, 0,
                       "backend.drag_* keys differ from the drag law the residual-force network was "
                       "trained with (its weight file)");
    const DragLaw given = drag;
    drag = law;
    drag.sigma = given.sigma;
    drag.sigma_speed = given.sigma_speed;
    drag.sigma_rate = given.sigma_rate;
    drag.sigma_thrust = given.sigma_thrust;
  }

  VioMethod method_;
  ExperimentFile file_;
  ConfigReader backend_cfg_;  // kept to record the IMU noise a sequence's calibration gives
  VioBackendOptions options_;
  VioRunOptions run_;
  VisualFrontendConfig frontend_;
  std::shared_ptr<learned::ResidualForceProvider> provider_;
  bool ground_truth_residual_ = false;  // provider_ is built from each sequence's forces
  double duration_s_ = 0.0;
};

}  // namespace

const std::vector<std::string>& visualMethods() {
  static const std::vector<std::string> kMethods = {"vio", "vimo", "vid", "hdvio"};
  return kMethods;
}

std::unique_ptr<MethodPipeline> makeVisualPipeline(const std::string& method,
                                                   const ConfigReader& cfg,
                                                   const ExperimentFile& file) {
  return std::make_unique<VisualPipeline>(method, cfg, file);
}

}  // namespace hdvio::run

#include "hdvio/pipeline/visual_frontend_config_loader.h"

#include <string>

#include "hdvio/core/error.h"

namespace hdvio {
namespace {

void loadDetector(const ConfigReader& r, frontend::DetectorOptions* o) {
  r.readInRange("cell_size", &o->cell_size, 4, 512);
  r.readInRange("levels", &o->levels, 1, 5);
  r.readInRange("fast_threshold", &o->fast_threshold, 1, 255);
  r.readInRange("min_score", &o->min_score, 0.0, 1e6);
  r.readInRange("border", &o->border, 1, 64);
  r.finish();
}

void loadAlignment(const ConfigReader& r, frontend::SparseAlignmentOptions* o) {
  r.readInRange("max_level", &o->max_level, 0, 8);
  r.readInRange("min_level", &o->min_level, 0, 8);
  if (o->min_level > o->max_level)
    throw InputError(r.file(), 0, "frontend.alignment: min_level must not exceed max_level");
  r.readInRange("max_iterations", &o->max_iterations, 1, 1000);
  r.readInRange("huber_threshold", &o->huber_threshold, 1e-3, 255.0);
  r.readInRange("intensity_sigma", &o->intensity_sigma, 1e-3, 255.0);
  r.readInRange("rotation_prior_sigma", &o->rotation_prior_sigma, 1e-6, 10.0);
  r.finish();
}

void loadPose(const ConfigReader& r, frontend::PoseOptimizerOptions* o) {
  r.readInRange("iterations", &o->iterations, 0, 100);
  r.readInRange("huber_px", &o->huber_px, 1e-3, 100.0);
  r.readInRange("outlier_px", &o->outlier_px, 1e-3, 100.0);
  r.finish();
}

void loadDepthFilter(const ConfigReader& r, frontend::DepthFilterOptions* o) {
  r.readInRange("pixel_noise", &o->pixel_noise, 1e-3, 100.0);
  r.readInRange("convergence_ratio", &o->convergence_ratio, 1.0, 1e6);
  r.readInRange("relative_sigma", &o->relative_sigma, 0.0, 1.0);
  r.readInRange("min_updates_relative", &o->min_updates_relative, 1, 1000);
  r.readInRange("max_zmssd_per_pixel", &o->max_zmssd_per_pixel, 1.0, 1e6);
  r.readInRange("max_search_steps", &o->max_search_steps, 1, 100000);
  r.readInRange("min_parallax_ratio", &o->min_parallax_ratio, 0.0, 1.0);
  r.readInRange("max_keyframe_age", &o->max_keyframe_age, 1, 1000);
  r.readInRange("max_pyramid_level", &o->max_pyramid_level, 0, 8);
  r.finish();
}

}  // namespace

VisualFrontendConfig loadVisualFrontendConfig(const ConfigReader& r) {
  VisualFrontendConfig c;
  r.readEnum("source", &c.source,
             {{"auto", ObservationSource::kAuto}, {"tracks", ObservationSource::kTracks},
              {"images", ObservationSource::kImages}});
  r.readOptional("backend_pose_prior", &c.backend_pose_prior);
  r.readOptional("backend_feedback", &c.backend_feedback);
  r.readInRange("min_features_for_backend", &c.min_features_for_backend, 0, 100000);

  frontend::FrontendOptions& o = c.options;
  r.readInRange("pyramid_levels", &o.pyramid_levels, 1, 8);
  r.readInRange("max_features", &o.max_features, 1, 100000);
  r.readInRange("min_tracked_features", &o.min_tracked_features, 3, 100000);
  r.readInRange("keyframe_min_tracked", &o.keyframe_min_tracked, 0, 100000);
  r.readInRange("keyframe_distance", &o.keyframe_distance, 1e-4, 10.0);
  r.readInRange("max_keyframes", &o.max_keyframes, 2, 1000);
  r.readInRange("init_depth", &o.init_depth, 1e-2, 1e3);
  r.readInRange("init_min_depth", &o.init_min_depth, 1e-3, 1e3);
  r.readInRange("bootstrap_max_frames", &o.bootstrap_max_frames, 0, 100000);
  r.readInRange("bootstrap_min_converged", &o.bootstrap_min_converged, 0, 100000);
  r.readInRange("max_relocalization_frames", &o.max_relocalization_frames, 0, 100000);
  r.readOptional("constant_velocity", &o.constant_velocity);
  r.readInRange("structure_points_per_frame", &o.structure_points_per_frame, 0, 100000);
  r.readInRange("landmark_max_failures", &o.landmark_max_failures, 1, 100000);
  loadDetector(r.optionalSection("detector"), &o.detector);
  loadAlignment(r.optionalSection("alignment"), &o.alignment);
  loadPose(r.optionalSection("pose"), &o.pose);
  loadDepthFilter(r.optionalSection("depth_filter"), &o.depth_filter);
  r.finish();
  return c;
}

ObservationSource resolveObservationSource(ObservationSource configured, const Sequence& seq) {
  const bool tracks = !seq.landmark_observations.empty();
  if (configured == ObservationSource::kAuto)
    configured = tracks ? ObservationSource::kTracks : ObservationSource::kImages;
  if (configured == ObservationSource::kTracks && !tracks)
    throw InputError(seq.source, 0,
                     "frontend.source is 'tracks' but the sequence has no landmark tracks "
                     "(landmarks0/); use source: images");
  if (configured == ObservationSource::kImages && !seq.hasImages())
    throw InputError(seq.source, 0,
                     "visual method needs cam0 images with a camera calibration (or landmark "
                     "tracks with frontend.source: tracks); the sequence has none");
  return configured;
}

}  // namespace hdvio

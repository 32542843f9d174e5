#pragma once
// One method of hdvio_run, in two steps: configured from the experiment YAML (each method reads
// its own sections, so unknown keys are rejected before any data is loaded), then run over a
// sequence. Visual methods (frontend + smoother) and inertial methods (the IMO filter family)
// implement it in their own files; hdvio_run only dispatches.
#include <memory>
#include <string>
#include <vector>

#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/run/result_writer.h"

namespace hdvio::run {

class MethodPipeline {
 public:
  virtual ~MethodPipeline() = default;
  // Throws InputError when the sequence lacks a sensor the method needs (e.g. thrust).
  virtual RunResults run(const Sequence& seq) = 0;
};

struct ExperimentFile {
  std::string path;  // the YAML file, for error messages
  std::string dir;   // relative paths in it (e.g. network weights) are resolved against this
};

// vio, vimo, vid, hdvio
const std::vector<std::string>& visualMethods();
// imo, tlio, model_ekf, net_only, gate_io
const std::vector<std::string>& inertialMethods();

std::unique_ptr<MethodPipeline> makeVisualPipeline(const std::string& method,
                                                   const ConfigReader& cfg,
                                                   const ExperimentFile& file);
std::unique_ptr<MethodPipeline> makeInertialPipeline(const std::string& method,
                                                     const ConfigReader& cfg,
                                                     const ExperimentFile& file);
// gate_io (apps/run/src/gate_io_pipeline.cc; makeInertialPipeline dispatches to it).
std::unique_ptr<MethodPipeline> makeGateIoPipeline(const ConfigReader& cfg, const ExperimentFile& file);

}  // namespace hdvio::run

#pragma once
// The gate_io method's `gate:` section (docs/gate_io.md): the gate-corner update options of
// imo_updaters.h and whether the detections are used at all. Strict like every config: unknown
// keys are errors.
#include "hdvio/backend/imo/imo_updaters.h"
#include "hdvio/core/config.h"

namespace hdvio::imo {

struct GateCornerSection {
  GateCornerOptions options;
  // false: the IMU-only (dead-reckoning) baseline, no gate updates and no gate files needed.
  bool use_detections = true;
};

// Reads `gate:` into *section (defaults = what it holds) and calls g.finish().
void readGateCornerSection(const ConfigReader& g, GateCornerSection* section);

}  // namespace hdvio::imo

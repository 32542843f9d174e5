#include "hdvio/backend/imo/gate_corner_section.h"

namespace hdvio::imo {

void readGateCornerSection(const ConfigReader& g, GateCornerSection* section) {
  GateCornerOptions& o = section->options;
  g.readInRange("pixel_sigma", &o.pixel_sigma, 1e-3, 100.0);
  g.readInRange("gate_probability", &o.gate_probability, -1.0, 0.999999);
  g.readInRange("corner_gate_probability", &o.corner_gate_probability, -1.0, 0.999999);
  g.readOptional("use_detections", &section->use_detections);
  g.finish();
}

}  // namespace hdvio::imo

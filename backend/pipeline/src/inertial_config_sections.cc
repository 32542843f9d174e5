#include "hdvio/pipeline/inertial_config_sections.h"

#include <cmath>

#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"

namespace hdvio {

void readInertialRunSection(const ConfigReader& r, InertialRunSpan* span) {
  r.readInRange("start_offset_s", &span->start_offset_s, 0.0, 1e6);
  r.readInRange("duration_s", &span->duration_s, 0.0, 1e6);
  r.finish();
}

void readThrustSection(const ConfigReader& t, const std::string& config_path, RotorThrust* thrust) {
  t.readInRange("coefficient_over_mass", &thrust->coefficient_over_mass, 0.0, 1.0);
  thrust->axis = readVec3(t, "axis", thrust->axis);
  t.finish();
  if (std::abs(thrust->axis.norm() - 1.0) > 1e-6)
    throw InputError(config_path, 0, "thrust.axis must be a unit vector");
}

DisplacementUse readGateIoDisplacement(const ConfigReader& cfg) {
  DisplacementUse use = DisplacementUse::kNone;
  cfg.readEnum("displacement", &use,
               {{"none", DisplacementUse::kNone}, {"network", DisplacementUse::kFilterUpdate}});
  return use;
}

}  // namespace hdvio

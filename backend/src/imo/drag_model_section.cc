#include "hdvio/backend/imo/drag_model_section.h"

#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"

namespace hdvio::imo {

void readDragModelSection(const ConfigReader& m, const std::string& config_path,
                          DragModelSection* section) {
  m.readInRange("integration_step_s", &section->integration_step_s, 1e-4, 0.1);
  m.readInRange("window_s", &section->window_s, 0.05, 5.0);
  m.readInRange("thrust_scale", &section->model.thrust_scale, 0.1, 10.0);
  section->model.drag.linear = readVec3(m, "linear_drag", section->model.drag.linear);
  m.readOptional("attitude_jacobian", &section->attitude_jacobian);
  m.finish();
  if ((section->model.drag.linear.array() < 0.0).any())
    throw InputError(config_path, 0, "model.linear_drag must be >= 0");
}

}  // namespace hdvio::imo

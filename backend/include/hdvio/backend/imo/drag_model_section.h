#pragma once
// The model_ekf method's `model:` section (docs/imo.md): the drag model of drag_model.h and how
// its displacement is integrated. Strict like every config: unknown keys are errors.
#include <string>

#include "hdvio/backend/imo/drag_model.h"
#include "hdvio/backend/imo/imo_stepper.h"
#include "hdvio/core/config.h"

namespace hdvio::imo {

struct DragModelSection {
  DragModel model;                   // thrust_scale, linear_drag
  double integration_step_s = 0.005;
  double window_s = ImoRunOptions().window_s;  // the displacement window (ImoRunOptions::window_s)
  bool attitude_jacobian = true;     // attitude Jacobian of the model displacement
};

// Reads `model:` into *section (defaults = what it holds) and calls m.finish(). InputError
// (naming config_path) for a negative linear drag.
void readDragModelSection(const ConfigReader& m, const std::string& config_path,
                          DragModelSection* section);

}  // namespace hdvio::imo

#pragma once
// Reads the `frontend:` section of a visual experiment (vio, vimo, vid, hdvio) into the
// VisualFrontendConfig beside it (visual_frontend_config.h): where the backend's landmark
// observations come from and, for images, the semi-direct frontend's options. Strict like every
// config: unknown keys are errors. See docs/visual_pipeline.md.
#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/pipeline/visual_frontend_config.h"

namespace hdvio {

VisualFrontendConfig loadVisualFrontendConfig(const ConfigReader& section);

// kTracks or kImages for this sequence; throws InputError when the sequence lacks what the
// chosen source needs (tracks, or a camera with images).
ObservationSource resolveObservationSource(ObservationSource configured, const Sequence& seq);

}  // namespace hdvio

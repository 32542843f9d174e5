#pragma once
// The `frontend:` section of a visual experiment (vio, vimo, vid, hdvio): where the backend's
// landmark observations come from and, for images, the semi-direct frontend's options. Strict
// like every config: unknown keys are errors. The struct is the pipeline's
// (backend/pipeline visual_frontend_config.h). See docs/visual_pipeline.md.
#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/pipeline/visual_frontend_config.h"

namespace hdvio::run {

VisualFrontendConfig loadVisualFrontendConfig(const ConfigReader& section);

// kTracks or kImages for this sequence; throws InputError when the sequence lacks what the
// chosen source needs (tracks, or a camera with images).
ObservationSource resolveObservationSource(ObservationSource configured, const Sequence& seq);

}  // namespace hdvio::run

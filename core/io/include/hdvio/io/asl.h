#pragma once
// The EuRoC / ASL folder layout of FORMATS.md, extended with thrust0, rotor0,
// force_groundtruth0 and landmarks0 (simulated landmark tracks).
#include <string>

#include "hdvio/core/sequence.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

// Reads <folder>/mav0 (or <folder> itself when it is the mav0 folder). Only imu0 is required.
// Images are not loaded: Sequence::images holds absolute paths (see loadImage in image.h).
// Throws InputError naming file, line and problem on any malformed input.
Sequence readAsl(const std::string& folder, const ReadOptions& options = {});

// Writes every present part of the sequence as <out_folder>/mav0/..., with full precision so
// that readAsl gives back identical samples. Images that are not already inside
// <out_folder>/mav0/cam0/data/ are copied there as <timestamp><extension>; images inside a
// ROS bag (ImageRef::span) are decoded and written as <timestamp>.png. Files are staged
// next to the destination and moved into place only once everything was written.
void writeAsl(const Sequence& sequence, const std::string& out_folder);

}  // namespace hdvio::io

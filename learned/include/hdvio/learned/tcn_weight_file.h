#pragma once
// The TCN weight file: plain text, line oriented, self-describing (docs/learned.md).
//
//   hdvio_tcn 1                       format name and version
//   input_channels 6
//   kernel_size 2
//   window 10
//   sample_rate_hz 100
//   variance_head 0                   1: a log-variance head follows the force head
//   layers 7
//   layer <out_channels> <dilation>   one line per convolution, input to output
//   vector input_mean <n>             followed by one line of n numbers
//   vector input_std <n>
//   matrix conv<l>.weight <rows> <cols>   followed by <rows> lines of <cols> numbers
//   vector conv<l>.bias <n>
//   matrix head.weight 3 <width>      vector head.bias 3
//   [matrix logvar.weight 3 <width>   vector logvar.bias 3]
//   end
//
// Version 2 (residual networks, displacement models, compact binary tensors) adds, in this
// order after the version line: "task force|displacement", "inputs thrust_gyro|accel_gyro",
// "output_sigma <s1> <s2> <s3>" or "output_sigma none", then the version-1 header lines, then
// "residual 0|1" after variance_head, and "encoding text|float32" after the layer lines.
// Residual tensors: per block l, conv<2l>, conv<2l+1> and, when the width changes,
// skip<l>.weight (out x in) and skip<l>.bias. With float32 encoding the tensors (same order,
// row-major) follow as "data <count>" + '\n' + count little-endian float32 + '\n' + "end".
//
// Version 3 (a force network trained on what a drag law leaves, core/drag_law.h) is version 2
// with "drag_law <dx> <dy> <dz> <cx> <cy> <cz>" (or "drag_law none") after output_sigma;
// written only when the info holds a law. A law with a rotor or lift term or a residual sigma
// appends "<rx> <ry> <rz> <lift> <sx> <sy> <sz>" to that line (older readers refuse it).
//
// Version 4 (the IMO reference release's network, scripts/convert_imo_release_checkpoint.py)
// is version 3 (drag_law line always present, "none" allowed) with "sample_times end|begin"
// after drag_law (where a displacement window's samples sit, displacement_model.h) and
// "block_relu 0|1", "window_padding 0|1" after residual (tcn.h); written only when one of
// them differs from its default (end, 0, 0).
//
// Version 5 (a force network with the walk of its held-out error, force_model_error.h) is
// version 4 with "force_walk <m/s^2/sqrt(s)>" after sample_times; written only when positive.
//
// Version 6 (a force network trained on an estimator's trajectory instead of ground truth,
// hdvio_train's data.train_estimates) is version 5 with "supervision groundtruth|estimate" after
// force_walk; written only for "estimate".
//
// Version 7 (a force network that states what its training samples held, core/model_envelope.h)
// is version 6 (supervision line always present) with "envelope <speed_max m/s> <rate_max rad/s>
// <thrust_min> <thrust_max m/s^2>" after supervision; written only when the info has one.
//
// Blank lines and lines starting with '#' are ignored. Any other deviation (missing or extra
// tensor, wrong shape, unparsable or non-finite number, data after "end") is an InputError
// naming the file and the line.
#include <string>
#include <vector>

#include "hdvio/core/drag_law.h"
#include "hdvio/core/model_envelope.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

// What a version-2 file says about the network beyond its layers.
struct TcnFileInfo {
  std::string task = "force";          // "force" (residual force) | "displacement" (IMO/TLIO)
  std::string inputs = "thrust_gyro";  // "thrust_gyro" | "accel_gyro"
  std::vector<double> output_sigma;    // empty or 3 positive values (output units)
  DragLaw drag_law;                    // force networks: the law they complement (none: zero)
  std::string sample_times = "end";    // "end" | "begin": displacement window sample times
  double force_walk = 0.0;             // force networks: random walk of their error (0: unknown)
  std::string supervision = "groundtruth";  // "groundtruth" | "estimate": the training targets
  ModelEnvelope envelope;  // force networks: what training held (unbounded: not stated)
};

enum class TcnEncoding { kText, kFloat32 };

struct TcnFile {
  Tcn tcn;
  TcnFileInfo info;
};

// Versions 1 to 7. Version 1 files get the default info.
TcnFile loadTcnFile(const std::string& path);
TcnFile parseTcnFile(const std::string& text, const std::string& name);
// Version 2, 3 when info holds a drag law, 4 with a version-4 field, 5 with a force walk, 6 for
// a network supervised by an estimate, 7 with a training envelope.
std::string formatTcnFile(const Tcn& tcn, const TcnFileInfo& info, const std::string& comment = "",
                          TcnEncoding encoding = TcnEncoding::kText);
void saveTcnFile(const Tcn& tcn, const TcnFileInfo& info, const std::string& path,
                 const std::string& comment = "", TcnEncoding encoding = TcnEncoding::kText);

// The functions below read any version; formatTcnWeights writes version 1 for plain networks
// (older readers keep working) and version 2 with default info for residual ones.
Tcn loadTcnWeights(const std::string& path);
Tcn parseTcnWeights(const std::string& text, const std::string& name);

std::string formatTcnWeights(const Tcn& tcn, const std::string& comment = "");
// Writes to <path>.tmp and renames, so a reader never sees half a file.
void saveTcnWeights(const Tcn& tcn, const std::string& path, const std::string& comment = "");

}  // namespace hdvio::learned

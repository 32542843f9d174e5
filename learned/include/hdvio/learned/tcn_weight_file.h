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
// Blank lines and lines starting with '#' are ignored. Any other deviation (missing or extra
// tensor, wrong shape, unparsable or non-finite number, data after "end") is an InputError
// naming the file and the line.
#include <string>

#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

Tcn loadTcnWeights(const std::string& path);
Tcn parseTcnWeights(const std::string& text, const std::string& name);

std::string formatTcnWeights(const Tcn& tcn, const std::string& comment = "");
// Writes to <path>.tmp and renames, so a reader never sees half a file.
void saveTcnWeights(const Tcn& tcn, const std::string& path, const std::string& comment = "");

}  // namespace hdvio::learned

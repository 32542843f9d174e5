#pragma once
// Progress of a run over a sequence, on stderr: a self-overwriting line on a terminal, a line
// per 10 % otherwise (logs stay short).
#include <string>

#include "hdvio/core/time.h"

namespace hdvio::run {

class Progress {
 public:
  Progress(std::string label, Timestamp t_begin, Timestamp t_end);
  void update(Timestamp t);
  void finish();

 private:
  std::string label_;
  Timestamp t_begin_;
  Timestamp t_end_;
  bool terminal_;
  int last_shown_ = -1;  // percent (terminal) or decile (log)
};

}  // namespace hdvio::run

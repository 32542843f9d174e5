#include "hdvio/run/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace hdvio::run {

Progress::Progress(std::string label, Timestamp t_begin, Timestamp t_end)
    : label_(std::move(label)), t_begin_(t_begin), t_end_(t_end), terminal_(isatty(2) != 0) {}

void Progress::update(Timestamp t) {
  const double span = std::max<double>(1.0, static_cast<double>(t_end_ - t_begin_));
  const double fraction = std::clamp(static_cast<double>(t - t_begin_) / span, 0.0, 1.0);
  const int percent = static_cast<int>(100.0 * fraction);
  const int shown = terminal_ ? percent : percent / 10;
  if (shown == last_shown_) return;
  last_shown_ = shown;
  const double done_s = toSeconds(t - t_begin_), total_s = toSeconds(t_end_ - t_begin_);
  if (terminal_)
    std::fprintf(stderr, "\r%s %3d%% (%.1f of %.1f s)", label_.c_str(), percent, done_s, total_s);
  else
    std::fprintf(stderr, "%s %3d%% (%.1f of %.1f s)\n", label_.c_str(), 10 * shown, done_s,
                 total_s);
}

void Progress::finish() {
  if (terminal_ && last_shown_ >= 0) std::fprintf(stderr, "\n");
}

}  // namespace hdvio::run

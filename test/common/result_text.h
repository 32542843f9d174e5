#pragma once
// hdvio_run's trajectory and velocity formats (apps/run result_writer.cc), written from states
// in a test, for byte-for-byte comparisons with what hdvio_run wrote.
#include <sstream>
#include <string>
#include <vector>

#include "hdvio/core/nav_state.h"

namespace hdvio::test {

inline std::string trajectoryText(const std::vector<NavState>& states) {
  std::ostringstream s;
  s.precision(9);
  s << std::fixed << "# timestamp[s] tx ty tz qx qy qz qw\n";
  for (const NavState& x : states)
    s << toSeconds(x.t) << ' ' << x.T_WB.p.x() << ' ' << x.T_WB.p.y() << ' ' << x.T_WB.p.z()
      << ' ' << x.T_WB.q.x() << ' ' << x.T_WB.q.y() << ' ' << x.T_WB.q.z() << ' ' << x.T_WB.q.w()
      << '\n';
  return s.str();
}

// Without the header line (hdvio_run's file starts with one).
inline std::string velocityText(const std::vector<NavState>& states) {
  std::ostringstream s;
  s.precision(9);
  s << std::fixed;
  for (const NavState& x : states)
    s << x.t << ',' << x.v_W.x() << ',' << x.v_W.y() << ',' << x.v_W.z() << '\n';
  return s.str();
}

inline std::string withoutHeader(const std::string& text) {
  return text.substr(text.find('\n') + 1);
}

}  // namespace hdvio::test

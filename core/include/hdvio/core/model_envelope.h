#pragma once
// What a learned dynamics model saw in training: the range of body speed, body rate and
// mass-normalized collective thrust its training samples held (hdvio_train writes it into the
// weight file; the estimator widens the external force's walk where a flight leaves it, since
// the model's measured error says nothing there).
#include <algorithm>
#include <limits>

namespace hdvio {

struct ModelEnvelope {
  double speed_max = std::numeric_limits<double>::infinity();  // m/s, |v| (body = world norm)
  double rate_max = std::numeric_limits<double>::infinity();   // rad/s, |gyro - bias|
  double thrust_min = 0.0;                                      // m/s^2, |thrust|
  double thrust_max = std::numeric_limits<double>::infinity();  // m/s^2

  // True unless some bound is finite (a model without a stated envelope).
  bool unbounded() const {
    return speed_max == std::numeric_limits<double>::infinity() &&
           rate_max == std::numeric_limits<double>::infinity() && thrust_min <= 0.0 &&
           thrust_max == std::numeric_limits<double>::infinity();
  }
  bool contains(double speed, double rate, double thrust) const { return excess(speed, rate, thrust) == 0.0; }
  // How far outside: the largest relative distance beyond a bound (speed / speed_max - 1, ...,
  // thrust_min / thrust - 1), 0 inside.
  double excess(double speed, double rate, double thrust) const {
    double e = std::max({0.0, speed / speed_max - 1.0, rate / rate_max - 1.0, thrust / thrust_max - 1.0});
    if (thrust_min > 0.0) e = std::max(e, thrust > 0.0 ? thrust_min / thrust - 1.0 : std::numeric_limits<double>::infinity());
    return e;
  }
};

}  // namespace hdvio

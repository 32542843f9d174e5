#pragma once
// Truncated Taylor series in time: f(t0 + h) = sum_k c[k] h^k, k = 0..kSeriesOrder.
//
// Why: the simulator defines a flight by smooth analytic flat outputs (position, yaw) and must
// produce exact velocity, acceleration, angular velocity and angular acceleration, including
// through drag that depends on the attitude it is solving for. Evaluating every formula on
// Taylor series gives all those derivatives exactly (to round-off) without hand-derived
// chain rules. Arithmetic follows the standard recurrences (Griewank & Walther, ch. 13).
#include <array>
#include <cmath>

namespace hdvio::sim {

constexpr int kSeriesOrder = 5;  // position to 5th derivative -> angular acceleration exact

struct Series {
  std::array<double, kSeriesOrder + 1> c{};

  Series() = default;
  Series(double value) { c[0] = value; }  // NOLINT: constants mix freely with series
  static Series variable(double t0) {
    Series s(t0);
    s.c[1] = 1.0;
    return s;
  }
  double value() const { return c[0]; }
  // k-th time derivative at t0 (k! * c[k]).
  double derivative(int k) const {
    double f = 1.0;
    for (int i = 2; i <= k; ++i) f *= i;
    return f * c[k];
  }
};

// d/dt of the series. The top coefficient becomes unknown (set to 0): each differentiation
// lowers the number of valid orders by one.
inline Series derivative(const Series& a) {
  Series r;
  for (int k = 0; k < kSeriesOrder; ++k) r.c[k] = (k + 1) * a.c[k + 1];
  return r;
}

inline Series operator+(const Series& a, const Series& b) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) r.c[k] = a.c[k] + b.c[k];
  return r;
}
inline Series operator-(const Series& a, const Series& b) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) r.c[k] = a.c[k] - b.c[k];
  return r;
}
inline Series operator-(const Series& a) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) r.c[k] = -a.c[k];
  return r;
}
inline Series operator*(const Series& a, double s) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) r.c[k] = a.c[k] * s;
  return r;
}
inline Series operator*(double s, const Series& a) { return a * s; }
inline Series operator*(const Series& a, const Series& b) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) {
    double sum = 0.0;
    for (int j = 0; j <= k; ++j) sum += a.c[j] * b.c[k - j];
    r.c[k] = sum;
  }
  return r;
}
inline Series operator/(const Series& a, const Series& b) {
  Series r;
  for (int k = 0; k <= kSeriesOrder; ++k) {
    double sum = a.c[k];
    for (int j = 1; j <= k; ++j) sum -= b.c[j] * r.c[k - j];
    r.c[k] = sum / b.c[0];
  }
  return r;
}
inline Series operator/(const Series& a, double s) { return a * (1.0 / s); }
inline Series& operator+=(Series& a, const Series& b) { return a = a + b; }
inline Series& operator-=(Series& a, const Series& b) { return a = a - b; }

inline Series sqrt(const Series& a) {
  Series r;
  r.c[0] = std::sqrt(a.c[0]);
  for (int k = 1; k <= kSeriesOrder; ++k) {
    double sum = a.c[k];
    for (int j = 1; j < k; ++j) sum -= r.c[j] * r.c[k - j];
    r.c[k] = sum / (2.0 * r.c[0]);
  }
  return r;
}

inline Series exp(const Series& a) {
  Series r;
  r.c[0] = std::exp(a.c[0]);
  for (int k = 1; k <= kSeriesOrder; ++k) {
    double sum = 0.0;
    for (int j = 1; j <= k; ++j) sum += j * a.c[j] * r.c[k - j];
    r.c[k] = sum / k;
  }
  return r;
}

inline Series log(const Series& a) {
  Series r;
  r.c[0] = std::log(a.c[0]);
  for (int k = 1; k <= kSeriesOrder; ++k) {
    double sum = 0.0;
    for (int j = 1; j < k; ++j) sum += j * r.c[j] * a.c[k - j];
    r.c[k] = (a.c[k] - sum / k) / a.c[0];
  }
  return r;
}

// sin and cos together (their recurrences are coupled).
inline void sincos(const Series& a, Series* s, Series* co) {
  s->c[0] = std::sin(a.c[0]);
  co->c[0] = std::cos(a.c[0]);
  for (int k = 1; k <= kSeriesOrder; ++k) {
    double ss = 0.0, cc = 0.0;
    for (int j = 1; j <= k; ++j) {
      ss += j * a.c[j] * co->c[k - j];
      cc -= j * a.c[j] * s->c[k - j];
    }
    s->c[k] = ss / k;
    co->c[k] = cc / k;
  }
}
inline Series sin(const Series& a) {
  Series s, c;
  sincos(a, &s, &c);
  return s;
}
inline Series cos(const Series& a) {
  Series s, c;
  sincos(a, &s, &c);
  return c;
}

// tanh without overflow: evaluate on the non-negative side and use oddness.
inline Series tanh(const Series& a) {
  if (a.c[0] < 0.0) return -tanh(-a);
  const Series e = exp(-2.0 * a);
  return (1.0 - e) / (1.0 + e);
}

// log(cosh(x)) without overflow (the integral of tanh, used for smooth speed ramps).
inline Series logcosh(const Series& a) {
  if (a.c[0] < 0.0) return logcosh(-a);
  return a + log(1.0 + exp(-2.0 * a)) - std::log(2.0);
}

// atan2 through its derivative (x y' - y x') / (x^2 + y^2); value from std::atan2.
inline Series atan2(const Series& y, const Series& x) {
  const Series g = (x * derivative(y) - y * derivative(x)) / (x * x + y * y);
  Series r;
  r.c[0] = std::atan2(y.c[0], x.c[0]);
  for (int k = 1; k <= kSeriesOrder; ++k) r.c[k] = g.c[k - 1] / k;
  return r;
}

// 3-vectors and 3x3 matrices of series, just what the flatness map needs.
struct SVec3 {
  Series x, y, z;
  SVec3() = default;
  SVec3(const Series& a, const Series& b, const Series& c) : x(a), y(b), z(c) {}
  SVec3(double a, double b, double c) : x(a), y(b), z(c) {}
  const Series& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  Series& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
inline SVec3 operator+(const SVec3& a, const SVec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline SVec3 operator-(const SVec3& a, const SVec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline SVec3 operator-(const SVec3& a) { return {-a.x, -a.y, -a.z}; }
inline SVec3 operator*(const SVec3& a, const Series& s) { return {a.x * s, a.y * s, a.z * s}; }
inline SVec3 operator*(const Series& s, const SVec3& a) { return a * s; }
inline SVec3 operator*(const SVec3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline SVec3 operator*(double s, const SVec3& a) { return a * s; }
inline Series dot(const SVec3& a, const SVec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline SVec3 cross(const SVec3& a, const SVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline SVec3 normalized(const SVec3& a) { return a * (1.0 / sqrt(dot(a, a))); }
inline SVec3 derivative(const SVec3& a) { return {derivative(a.x), derivative(a.y), derivative(a.z)}; }

// Rotation as three column series (body axes in world coordinates).
struct SMat3 {
  SVec3 col[3];
  // R * v (body -> world)
  SVec3 operator*(const SVec3& v) const { return col[0] * v.x + col[1] * v.y + col[2] * v.z; }
  // R^T * v (world -> body)
  SVec3 transposeTimes(const SVec3& v) const { return {dot(col[0], v), dot(col[1], v), dot(col[2], v)}; }
};

}  // namespace hdvio::sim

// A plain D-component vector for the innermost particle kernels.
//
// Eigen's fixed-size 3-vectors straddle SSE registers (2 + 1 lanes) and cost shuffles on every
// operation; the pair kernel is dominated by such 3-vector arithmetic, which the compiler turns
// into straight scalar code with this type (about half the instructions per contact). Same
// interface subset as Eigen, so the contact laws (templates on the vector type) accept both.
#pragma once

#include <cmath>

namespace silt {

template <int D>
struct SVec {
  static constexpr int SizeAtCompileTime = D;  // as Eigen's fixed-size vectors
  double c[D];

  static SVec Zero() {
    SVec v;
    for (int k = 0; k < D; ++k) v.c[k] = 0.0;
    return v;
  }
  static SVec load(const double* p) {
    SVec v;
    for (int k = 0; k < D; ++k) v.c[k] = p[k];
    return v;
  }
  void store(double* p) const {
    for (int k = 0; k < D; ++k) p[k] = c[k];
  }
  double& operator[](int k) { return c[k]; }
  double operator[](int k) const { return c[k]; }
  double dot(const SVec& o) const {
    double s = 0;
    for (int k = 0; k < D; ++k) s += c[k] * o.c[k];
    return s;
  }
  double squaredNorm() const { return dot(*this); }
  double norm() const { return std::sqrt(squaredNorm()); }
  void setZero() { *this = Zero(); }
  SVec& operator+=(const SVec& o) {
    for (int k = 0; k < D; ++k) c[k] += o.c[k];
    return *this;
  }
  SVec& operator-=(const SVec& o) {
    for (int k = 0; k < D; ++k) c[k] -= o.c[k];
    return *this;
  }
  SVec& operator*=(double a) {
    for (int k = 0; k < D; ++k) c[k] *= a;
    return *this;
  }
  friend SVec operator+(SVec a, const SVec& b) { return a += b; }
  friend SVec operator-(SVec a, const SVec& b) { return a -= b; }
  friend SVec operator*(SVec a, double s) { return a *= s; }
  friend SVec operator*(double s, SVec a) { return a *= s; }
  friend SVec operator/(SVec a, double s) { return a *= 1.0 / s; }
  friend SVec operator-(SVec a) { return a *= -1.0; }
};

// Rotation algebra on SVec (see vec.hpp): w x n and n x f, with scalar rotations in 2D.
inline SVec<3> cross(const SVec<3>& a, const SVec<3>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
inline SVec<3> cross_w(const SVec<3>& w, const SVec<3>& n) { return cross(w, n); }
inline SVec<2> cross_w(double w, const SVec<2>& n) { return {{-w * n[1], w * n[0]}}; }
inline SVec<3> moment(const SVec<3>& n, const SVec<3>& f) { return cross(n, f); }
inline double moment(const SVec<2>& n, const SVec<2>& f) { return n[0] * f[1] - n[1] * f[0]; }

template <int D>
using SOmega = std::conditional_t<D == 3, SVec<3>, double>;

template <int D>
inline SOmega<D> somega_load(const double* a, size_t i) {
  if constexpr (D == 3) {
    return SVec<3>::load(a + 3 * i);
  } else {
    return a[i];
  }
}

}  // namespace silt

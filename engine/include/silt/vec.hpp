// Small fixed-size vectors and the 2D/3D rotation algebra shared by the particle kernels.
//
// Particle kernels are templates over the dimension D (2 = disks in a plane, 3 = spheres). In 2D
// the angular velocity and the torque are scalars (their z component); Omega<D> names that type
// and the helpers below keep the kernels free of runtime dimension branches.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <type_traits>

namespace silt {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

// Number of rotational degrees of freedom: 1 for a disk in the plane, 3 for a sphere.
template <int D>
inline constexpr int kRotDim = (D == 3) ? 3 : 1;
inline int rot_dim(int dim) { return dim == 3 ? 3 : 1; }

template <int D>
using Omega = std::conditional_t<D == 3, Vec3, double>;

template <int D>
inline Omega<D> omega_zero() {
  if constexpr (D == 3) {
    return Vec3::Zero();
  } else {
    return 0.0;
  }
}

// w x n for an angular velocity w and an in-space vector n.
inline Vec3 cross_w(const Vec3& w, const Vec3& n) { return w.cross(n); }
inline Vec2 cross_w(double w, const Vec2& n) { return Vec2(-w * n.y(), w * n.x()); }

// n x f, the moment of a force f at lever n (a scalar, its z component, in 2D).
inline Vec3 moment(const Vec3& n, const Vec3& f) { return n.cross(f); }
inline double moment(const Vec2& n, const Vec2& f) { return n.x() * f.y() - n.y() * f.x(); }

// Loading and storing per-particle values from the flat arrays of State (stride D or kRotDim).
template <int D>
inline Eigen::Map<Vec<D>> at(double* a, size_t i) {
  return Eigen::Map<Vec<D>>(a + D * i);
}
template <int D>
inline Eigen::Map<const Vec<D>> at(const double* a, size_t i) {
  return Eigen::Map<const Vec<D>>(a + D * i);
}
template <int D>
inline Omega<D> omega_at(const double* a, size_t i) {
  if constexpr (D == 3) {
    return Vec3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
  } else {
    return a[i];
  }
}
template <int D>
inline void omega_add(double* a, size_t i, const Omega<D>& w) {
  if constexpr (D == 3) {
    a[3 * i] += w.x();
    a[3 * i + 1] += w.y();
    a[3 * i + 2] += w.z();
  } else {
    a[i] += w;
  }
}
template <int D>
inline void omega_store(double* a, size_t i, const Omega<D>& w) {
  if constexpr (D == 3) {
    a[3 * i] = w.x();
    a[3 * i + 1] = w.y();
    a[3 * i + 2] = w.z();
  } else {
    a[i] = w;
  }
}
template <int D>
inline double omega_norm2(const Omega<D>& w) {
  if constexpr (D == 3) {
    return w.squaredNorm();
  } else {
    return w * w;
  }
}

}  // namespace silt

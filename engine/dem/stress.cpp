#include "dem/stress.hpp"

#include "core/parallel.hpp"
#include "silt/periodic_image.hpp"

namespace silt::dem {
namespace {

template <int D, bool Full>
std::array<double, 9> sums_dim(const State& s, const double* pair_force, bool kinetic) {
  const PeriodicImage<D> img(s.box);
  return deterministic_sums<9>(s.n, 2048, [&](int64_t lo, int64_t hi) {
    std::array<double, 9> acc{};
    auto wanted = [](int a, int b) { return Full || a == b || (a == 0 && b == 1); };
    for (int64_t i = lo; i < hi; ++i) {
      if (kinetic && !s.particle_frozen[i]) {
        const double* v = &s.particle_v[D * i];
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b)
            if (wanted(a, b)) acc[3 * a + b] += v[a] * v[b] / s.particle_inv_m[i];
      }
      for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
        const double* f = &pair_force[D * p];
        bool apart = true;  // contact_forces zeroes the force of pairs apart
        for (int a = 0; a < D; ++a) apart = apart && f[a] == 0.0;
        if (apart) continue;
        Vec<D> d = at<D>(s.particle_x.data(), i) - at<D>(s.particle_x.data(), s.pair_j[p]);
        img.apply(d);
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b)
            if (wanted(a, b)) acc[3 * a + b] += f[a] * d[b];
      }
    }
    return acc;
  });
}

}  // namespace

template <bool Full>
std::array<double, 9> virial_sums(const State& s) {
  return s.dim == 2 ? sums_dim<2, Full>(s, s.pair_f.data(), true) : sums_dim<3, Full>(s, s.pair_f.data(), true);
}

std::array<double, 9> pair_virial_sums(const State& s, const double* pair_force) {
  return s.dim == 2 ? sums_dim<2, true>(s, pair_force, false) : sums_dim<3, true>(s, pair_force, false);
}

template std::array<double, 9> virial_sums<true>(const State& s);
template std::array<double, 9> virial_sums<false>(const State& s);

}  // namespace silt::dem

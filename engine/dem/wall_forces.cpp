// Planar walls: the grain-grain laws with an infinite mass and radius (Izard 2014 sec. 2.1.1:
// m* = m_i; Hertz R_eq = 2 r_i from 2/R_eq = 1/r_i + 0), with the parameters of the wall's
// material against the grain's (Model::wall_contact).
//
// With the wall normal n pointing into the domain and gap = (x - p) . n - r, the contact point
// is at -r n from the centre, so the slip velocity is v - (v.n) n - r w x n and the torque of
// the tangential force is (-r n) x F_t. Each (grain, wall) pair keeps its own spring.
#include <cmath>

#include "core/parallel.hpp"
#include "dem/contact_laws.hpp"
#include "dem/stages.hpp"

namespace silt::dem {
namespace {

template <int D>
void walls_dim(const Model& m, State& s) {
  constexpr int R = kRotDim<D>;
  const int64_t groups = static_cast<int64_t>(m.materials.size());
  const int nw = s.n_walls;
  const double dt = s.dt;
  parallel_for(s.n, 1024, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      Omega<D> torque = omega_zero<D>();
      for (int wi = 0; wi < nw; ++wi) at<D>(s.wall_f.data(), static_cast<int64_t>(i) * nw + wi).setZero();
      if (!s.particle_frozen[i]) {
        const auto x = at<D>(s.particle_x.data(), i);
        const auto v = at<D>(s.particle_v.data(), i);
        const double r = s.particle_r[i];
        for (int wi = 0; wi < nw; ++wi) {
          const Wall& wall = m.walls[wi];
          // The law between this wall and the grain's material (dem/materials.hpp).
          const ContactParams& cp = m.wall_contact[wi * groups + s.particle_group[i]];
          const Vec<D> n = wall.normal.head<D>();
          Eigen::Map<Vec<D>> hist(s.wall_hist.data() + D * (static_cast<int64_t>(i) * nw + wi));
          const double gap = wall.gap<D>(x, r);
          if (gap >= 0) {
            hist.setZero();
            continue;
          }
          const double overlap = -gap;
          if (overlap > m.limits.max_overlap * r) s.events[event::kOverlap].raise(i, overlap / r);
          const double vn = v.dot(n);
          const double m_eff = 1.0 / s.particle_inv_m[i];
          NormalForce nf = normal_force(cp, m_eff, 2.0 * r, overlap, -vn);
          Vec<D> f = nf.fn * n;
          if (cp.friction > 0) {
            const Vec<D> vt = v - vn * n - cross_w(r * omega_at<D>(s.particle_w.data(), i), n);
            Vec<D> spring = hist;
            const double kt = cp.kt_ratio * nf.k;
            const Vec<D> ft = tangential_force(spring, n, vt, dt, kt, cp.friction * std::abs(nf.fn),
                                               tangential_dashpot(cp.zeta_t, m_eff, kt));
            hist = spring;
            f += ft;
            torque += -r * moment(n, ft);
          }
          at<D>(s.wall_f.data(), static_cast<int64_t>(i) * nw + wi) = f;
        }
      }
      omega_store<D>(s.particle_t_wall.data(), i, torque);
      (void)R;
    }
  });
}

}  // namespace

void wall_forces(const Model& m, State& s) {
  if (m.dim == 2) walls_dim<2>(m, s);
  else walls_dim<3>(m, s);
}

}  // namespace silt::dem

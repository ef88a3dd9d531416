// Stress-controlled box lengths, Peyneau (2009) eq. 3.11:
//   M d2L_a/dt2 = (Omega / L_a) (sigma_aa - Sigma_aa),
//   Omega sigma_aa = sum_i m_i v_ia^2 + sum_contacts f_ij,a d_ij,a   (compression positive),
// so a contact pressure below the target shrinks the box; and a stress-controlled shear rate,
// eq. 3.12 in this code's sign convention (flow v_x = gammadot y, tau = -sigma_xy > 0 resists it):
//   M L_x L_y / Omega d(gammadot)/dt = tau_imposed - tau,
// so a shear stress above the grains' resistance accelerates the shear. This stage computes the
// stresses after the forces of the new step and applies the second half kicks; the first half
// kicks and the drifts are in box_drift, called by kick_drift. Sums run over fixed chunks in
// order.
#include <algorithm>
#include <cmath>

#include "dem/stress.hpp"
#include "shear/cycle_origin.hpp"
#include "shear/stages.hpp"

namespace silt::shear {
namespace {

// sigma_aa on the controlled axes and, under stress-controlled shear, tau = -sigma_xy, from the
// grains' virial sums (dem/stress.hpp).
void set_box_stresses(const Model& m, State& s) {
  double vol = 1;
  for (int k = 0; k < m.dim; ++k) vol *= s.box.len[k];
  const std::array<double, 9> sum = dem::virial_sums<false>(s);
  if (m.box_control.on)
    for (int a = 0; a < m.dim; ++a)
      if (m.box_control.controlled[a]) s.box_stress[a] = sum[3 * a + a] / vol;
  if (m.shear.stress_controlled) s.shear_stress = -sum[1] / vol;
}

// Half kick dt/2 of the controlled lengths (eq. 3.11) and of a stress-controlled shear rate
// (eq. 3.12) from the stresses in State: the first half of a step (box_drift) and the second
// (box_kick) share it.
void half_kick(const Model& m, State& s) {
  if (m.velocities_solved) return;  // the rates are solved (a paste)
  double vol = 1;
  for (int k = 0; k < m.dim; ++k) vol *= s.box.len[k];
  const double h = 0.5 * s.dt;
  const CycleOrigin origin = cycle_origin(m, s);
  if (m.box_control.on)
    for (int a = 0; a < m.dim; ++a)
      if (m.box_control.controlled[a])
        s.box_rate[a] +=
            h * (vol / s.box.len[a]) * (s.box_stress[a] - m.box_control.stress(a, origin, s.t)) / m.box_control.mass;
  if (m.shear.stress_controlled)
    s.shear_rate += h * vol * (m.shear.stress - s.shear_stress) / (m.box_control.mass * s.box.len[0] * s.box.len[1]);
}

}  // namespace

// Box lengths and shear: half kicks from the stresses of the previous step (box_kick computed
// them), then their drift.
void box_drift(const Model& m, State& s) {
  const int D = m.dim;
  const double dt = s.dt;
  Vec3a& lambda = s.box_stretch;
  lambda = {1, 1, 1};
  half_kick(m, s);
  if (m.box_control.on)
    for (int k = 0; k < D; ++k) {
      if (!m.box_control.controlled[k]) continue;
      const double next = s.box.len[k] + dt * s.box_rate[k];
      lambda[k] = next / s.box.len[k];
      s.box.len[k] = next;
      // Below twice the interaction range, a grain would meet its own image.
      // (Written so that a NaN or an infinite length, a box rate that overflowed, raises it too.)
      if (!(next >= 2 * m.interaction_range() && std::isfinite(next))) s.events[event::kBoxCollapse].raise(k, next);
    }
  if (m.shear.on) {
    // The image above moves along x at gammadot L_y, and is carried by the stretch of L_x like
    // the grains (x -> lo + lambda (x - lo)): the image lattice deforms with them.
    s.le_displacement = lambda[0] * s.le_displacement + dt * s.shear_rate * s.box.len[1];
    s.shear_strain += dt * s.shear_rate;
    s.box.le_offset = s.le_displacement - s.box.len[0] * std::floor(s.le_displacement / s.box.len[0]);
    // A shift beyond about 1e16 box lengths (or an overflow) leaves no usable offset.
    if (!(s.box.le_offset >= 0 && s.box.le_offset <= s.box.len[0]))
      s.events[event::kBoxCollapse].raise(0, s.box.le_offset);
  }
  double strain = std::abs(s.shear_rate) * dt;
  for (int k = 0; k < D; ++k) strain = std::max(strain, std::abs(lambda[k] - 1.0));
  s.nbr_strain += strain;
}

void box_stress(const Model& m, State& s) { set_box_stresses(m, s); }

void impose_shear_rate(const Model& m, State& s) {
  if (m.shear.on && !m.shear.stress_controlled) s.shear_rate = m.shear.rate;
}

void box_kick(const Model& m, State& s) {
  set_box_stresses(m, s);
  half_kick(m, s);
}

}  // namespace silt::shear

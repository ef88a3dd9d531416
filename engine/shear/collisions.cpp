// How far the collisions of a sheared flow press the grains into each other (shear/collisions.hpp).
#include "shear/collisions.hpp"

#include <algorithm>
#include <cmath>

#include "dem/contact_laws.hpp"
#include "silt/text.hpp"

namespace silt::shear {

ShearCollision shear_collision(const Model& m) {
  ShearCollision c;
  // (a paste's grains move at solved velocities: no free collisions)
  if (!m.shear.on || m.shear.stress_controlled || m.n_grains == 0 || m.velocities_solved) return c;
  double heaviest = 0;
  for (int64_t i = 0; i < m.n_grains; ++i)
    if (!m.init.frozen[i]) heaviest = std::max(heaviest, m.init.mass[i]);
  const double m_eff = heaviest / 2, r_eq = m.r_max / 2, most = m.limits.max_overlap * m.r_max;
  const ContactParams& law = m.tc_pair.law;
  c.speed = std::abs(m.shear.rate) * 2 * m.r_max;
  const double energy = 0.5 * m_eff * c.speed * c.speed;
  // The elastic energy grows with the overlap: bisect on it (Hertz's h^(5/2), the linear h^2).
  double lo = 0, hi = most;
  while (dem::normal_elastic_energy(law, m_eff, r_eq, hi) < energy && hi < 1e6 * most) hi *= 2;
  for (int k = 0; k < 100 && hi - lo > 1e-12 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (dem::normal_elastic_energy(law, m_eff, r_eq, mid) < energy ? lo : hi) = mid;
  }
  c.ratio = energy > 0 ? 0.5 * (lo + hi) / most : 0.0;
  return c;
}

std::string collision_text(const Model& m, const ShearCollision& c) {
  return "the imposed shear makes neighbours meet at about gammadot 2 r_max = " + format_number(c.speed, 3) +
         m.unit("m/s") + ", where an undamped collision of the heaviest grains presses them by " +
         format_number(c.ratio, 3) + " of limits.max_overlap";
}

double rate_for(const Model& m, double value, double ratio, double target) {
  return value * std::pow(target / ratio, m.contact.law == NormalLaw::kHertz ? 1.25 : 1.0);
}

std::string stiffer_by(const Model& m, const std::string& key, double ratio, double target) {
  const double f = ratio / target;
  if (m.contact.law == NormalLaw::kSpringDashpot) return key + " " + format_number(f, 3) + " times shorter";
  if (m.contact.law == NormalLaw::kHertz) return key + " " + format_number(std::pow(f, 2.5), 3) + " times larger";
  return key + " " + format_number(f * f, 3) + " times larger";
}

std::string shear_overlap_advice(const Model& m, const State& s, const std::string& key) {
  const ShearCollision c = shear_collision(m);
  // A packing sheared from rest at once: its contacts are pressed by the affine strain before the
  // box, driven by the pressure, can dilate (shear2d_dry at I = 2 to 5 failed at strains 0.2 to
  // 0.5; prepared with prepare.dilation = 1.3 it ran 20,000 steps at I = 5), from a ratio of 0.1
  // (below, I = 1 on shear2d_dry, a packing sheared from rest runs: the failure is the contacts'
  // own then). Else the collisions, where they press by more than 0.35 of the limit, brought to
  // 0.3 (at I = 7 dilated, contacts made stiff enough for 0.4 ran 14,401 steps and failed; for 0.3,
  // 40,000 steps).
  const bool undilated =
      std::abs(s.shear_strain) < 1 && m.prepare.compress && m.prepare.dilation < 1.3 && c.ratio > 0.1;
  if (!(c.ratio > 0) || (!undilated && !(c.ratio > 0.35))) return "";
  const std::string rate_key =
      m.desc.first_given({"shear.rate", "shear.inertial_number", "shear.viscous_number"}, "shear.rate");
  std::string text = collision_text(m, c) +
                     " (the flow's fluctuations make collisions faster: sheared runs were seen to fail from 0.5 to "
                     "0.9 of it)";
  if (undilated)
    text += "; at a strain of " + format_number(std::abs(s.shear_strain), 2) +
            " the packing has not dilated yet: a packing sheared from rest at this rate presses its contacts before "
            "the box can grow, so start it dilated (prepare.dilation = 1.3) or shear it slower (" +
            rate_key + ")";
  else
    text +=
        "; make the contacts stiffer (" + stiffer_by(m, key, c.ratio, 0.3) + " brings it to 0.3) or lower " + rate_key;
  return text;
}

}  // namespace silt::shear

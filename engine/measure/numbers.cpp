// Dimensionless numbers of a flow: the inertial, stiffness and viscous numbers.
#include <cmath>

#include "measure/equilibrium.hpp"
#include "silt/observables.hpp"
#include "silt/text.hpp"

namespace silt {

double inertial_number(const Model& m, double shear_rate, double pressure) {
  if (!(pressure > 0)) return 0;
  return std::abs(shear_rate) * std::sqrt(m.m_a / (std::pow(m.a_max, m.dim - 2) * pressure));
}

double stiffness_number(const Model& m, double pressure, bool stiffest) {
  if (!(pressure > 0)) return 0;
  const double k = stiffest ? m.kappa_stiffness_max : m.kappa_stiffness_min;
  if (m.contact.law == NormalLaw::kHertz) return std::pow(k / pressure, 2.0 / 3.0);
  return k / (pressure * std::pow(m.a_max, m.dim - 2));
}

std::string stiffness_number_text(const Model& m, double pressure) {
  const double soft = stiffness_number(m, pressure), stiff = stiffness_number(m, pressure, true);
  if (soft == stiff) return format_number(soft, 5);
  return format_number(soft, 5) + " to " + format_number(stiff, 5) + " by pair of groups";
}

double static_force(const Model& m) {
  if (!m.box_control.on) return 0;
  return m.until_static.force_tol * (std::pow(m.a_max, m.dim - 1) * m.box_control.pressure);
}

double viscous_stress(const Model& m, double eta, double rate) {
  return eta * std::abs(rate) * std::pow(m.a_max, 3 - m.dim);
}

double viscous_time(const Model& m, double eta, double pressure) {
  if (!(pressure > 0)) return 0;
  return viscous_stress(m, eta, 1.0) / pressure;
}

double viscous_number(const Model& m, double eta, double rate, double pressure) {
  return std::abs(rate) * viscous_time(m, eta, pressure);
}

}  // namespace silt

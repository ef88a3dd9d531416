// Dimensionless numbers of a flow: the inertial, stiffness and viscous numbers.
#include <cmath>

#include "silt/observables.hpp"

namespace silt {

double inertial_number(const Model& m, double shear_rate, double pressure) {
  if (!(pressure > 0)) return 0;
  return std::abs(shear_rate) * std::sqrt(m.m_a / (std::pow(m.a_max, m.dim - 2) * pressure));
}

double stiffness_number(const Model& m, double pressure) {
  if (!(pressure > 0)) return 0;
  if (m.contact.law == NormalLaw::kHertz) return std::pow(m.contact.e_tilde / pressure, 2.0 / 3.0);
  return m.k_max / (pressure * std::pow(m.a_max, m.dim - 2));
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

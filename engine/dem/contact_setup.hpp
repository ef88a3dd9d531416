// Contact-law part of compile(): parameters, contact time and the time-step stability bound.
#pragma once

#include "silt/model.hpp"

namespace silt::dem {

// Reads [contact] into m.contact (only the keys of the chosen law).
void read_contact_law(const SceneDesc& d, Model& m);

// Lightest reduced mass, stiffest contact, contact time and velocity-Verlet stability limit.
// Requires the grains and m.limits.max_overlap.
void derive_contact_scales(const SceneDesc& d, Model& m);

// Duration of a binary collision for the scene's law, between grains of reduced mass m_eff and
// reduced radius r_eq; Hertz needs the largest overlap reached (its contact time depends on it).
double contact_time(const ContactParams& p, double m_eff, double r_eq, double max_overlap);

}  // namespace silt::dem

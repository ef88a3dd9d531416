// Contact-law part of compile(): parameters, contact time and the time-step stability bound.
#pragma once

#include <initializer_list>
#include <string>

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
// The contact time t_c is quoted at: Hertz's at the law's reference overlap (hertz_ref_overlap r_eq).
double reference_contact_time(const ContactParams& p, double m_eff, double r_eq);
// Hertz: the impact speed whose undamped collision reaches `overlap`, 1/2 m* v^2 = (2/5) k_h h^(5/2).
double hertz_speed_to(const ContactParams& p, double m_eff, double r_eq, double overlap);

// The key to stiffen a contact between the materials of the tables `prefixes` ("walls[1].",
// "grains[0]."): the softer one's modulus or k_n, each the table's own or else [contact]'s (a wall
// of k_n 1e9 against grains of [contact]'s 1e4 is contact.k_n: the spring in series is at most
// twice the softer); [contact]'s contact time for the spring-dashpot; [contact]'s key without
// tables.
std::string stiffness_key(const SceneDesc& d, NormalLaw law, std::initializer_list<std::string> prefixes = {});
// The key of a law's normal dashpot: contact.damping, contact.gamma_n (hooke) or contact.restitution
// (spring_dashpot); no material has one of its own.
std::string damping_key(NormalLaw law);

}  // namespace silt::dem

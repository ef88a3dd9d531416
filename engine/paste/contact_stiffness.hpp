// Implicit contacts (lubrication.contacts = "implicit"): the contact forces of the next
// configuration linearised into the solve. With explicit contacts (eq. 2.19, the thesis), a
// contact of stiffness k held by a lubrication resistance xi is stable only for dt < 2 xi / k;
// under the linear cutoff xi_N in contact grows as 1 / h_min but xi_T only as ln(1 / h_min), so
// at small h_min every step is held near 2 xi_T / k_T (about 5e-3 eta / P at h_min = 1e-8 a)
// while the packing takes decades of eta / P longer to settle. Implicit contacts solve
//   (Xi + dt K) V = F_cont + F_ext,
// K the contacts' stiffness along the same relative velocities at contact as Xi (the normal
// k_n dF/d(overlap), the tangential k_t while the spring sticks; a sliding spring, at the
// Coulomb limit, adds none): a linearised backward Euler, stable at any step for the springs.
// The equilibria (F_cont + F_ext = 0, V = 0) are those of the explicit scheme; the path to them
// differs by the step's error.
#pragma once

#include "paste/system.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::paste {

// Sets Connection::k_n and k_t of every connection of `links` in contact (dt times the
// stiffnesses) and zero for the others. Reads particle_r, particle_inv_m, particle_group,
// pair_hist, the connections' separations.
void set_contact_stiffness(const Model& m, const State& s, double dt, Links& links);

}  // namespace silt::paste

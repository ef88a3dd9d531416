// The grains' stress solved to an accuracy of its own (lubrication.stress_tolerance). A
// connection's force is xi times the grains' relative velocity, so at small h_min the lubrication
// multiplies the velocities' error by up to a / h_min: a solve to the residual's tolerance alone
// gave paste_3d_shear at h_min/a = 1e-12 stresses of any sign. The error is estimated from the
// solver's preconditioned residual (its last CG's, free), and the solve taken on while it is too
// large.
#pragma once
#include <string>
#include <vector>

#include "paste/params.hpp"
#include "paste/solve.hpp"
#include "paste/unknown_scale.hpp"
#include "silt/linalg.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::paste {

// After a solve of A x = b (the system of lubrication_solve, in the units `units`, converged):
// while the estimated error of the grains' stress (contacts, lubrication and implicit contacts'
// increment) exceeds p.stress_tolerance of it, or of the imposed pressure or the viscous stress
// eta gammadot where larger, the solve goes on from x at a residual tolerance lowered in
// proportion (10 to 1e4 times a round, down to 1e-15); a round that does not lower the residual is
// undone (round-off reached). Returns the last estimate; rep gains the rounds' iterations and
// their residual. The contact forces of the configuration are read from s.pair_f.
double solve_for_stress(const Model& m, const PasteParams& p, const SystemLayout& L, const std::vector<Connection>& cs,
                        const State& s, const UnknownScale& units, const linalg::SparseMatrix& A,
                        const linalg::Vector& b, linalg::Vector& x, PasteWorkspace& w, linalg::SolveReport& rep);

// What the run says when the grains' stress passes lubrication.stress_tolerance (its estimate
// after the solve taken as far as round-off lets it), and when it comes back within it; "" else.
std::string stress_notice(const Model& m, const State& s);

}  // namespace silt::paste

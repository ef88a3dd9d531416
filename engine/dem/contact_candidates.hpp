// Contact candidates: the listed pairs that contact_forces tests each step.
//
// In a dense bed most listed pairs do not touch, and many never come within a fraction of the
// skin of touching while the list lives. The candidates are the listed pairs whose gap
// |d| - r_i - r_j is below Model::contact_skin s_c, selected from the Verlet list (a second,
// inner list, as the Verlet list is to the cell list). A pair left out had a gap of at least s_c;
// it cannot touch before its two grains have together moved s_c, so the selection stays valid
// while twice a bound on any grain's displacement since it, plus the affine strain times the
// list range, stays below s_c. The bound is the sum of the largest displacement of each drift
// (State::nbr_step_disp).
//
// The candidates keep the order of the list and hold every touching pair, so the forces, and
// their sums, are those of a pass over the whole list, bit for bit. A pair left out that may
// still hold a force or a spring (pair_touch) has them cleared, as the touch test would.
#pragma once

#include "dem/workspace.hpp"
#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::dem {

// Select the candidates of the current list (per block of rows of the pair schedule).
void select_candidates(const Model& m, State& s, DemWorkspace& w);

// Account for the last drift, and select anew when the candidates may miss a contact (or when
// `rebuilt`: the list itself changed).
void update_candidates(const Model& m, State& s, DemWorkspace& w, bool rebuilt);

}  // namespace silt::dem

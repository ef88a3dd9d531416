// The origin of the cycles' phase, kept in the state (field box_cycle_origin: empty, or t0,
// phase0 and w), so that a checkpoint carries it and a new w takes over where the phase was.
#pragma once

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::shear {

FieldId cycle_origin_field();

// The state's origin; (0, 0, w of the model) when it holds none (a new state, a checkpoint of a
// run without cycles or from before the origin was kept).
CycleOrigin cycle_origin(const Model& m, const State& s);

// (t, box_cycle_origin) => (box_cycle_origin)
// At the start of a step: when the model's w is not the one the origin was taken under, the
// cycles go on from the phase reached at this time with the new w.
void cycle_origin_stage(const Model& m, State& s);

}  // namespace silt::shear

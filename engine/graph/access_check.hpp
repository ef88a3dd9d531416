// Checking a stage's access set against what it does (Jolt's BodyAccess grants, by comparison
// of field values instead of guarded pointers).
//
// Writes: every field is hashed before and after the stage; one that changed and is not among
// the stage's writes is reported. Reads: the stage is also run on a copy of the state in which
// every floating-point and boolean field it does not declare as read holds other values (doubles
// scaled and shifted, booleans flipped); the fields it writes must come out bit for bit as in
// the real run. A stage that reads an undeclared field, or that declares a write but leaves part
// of the field as it was, gives other values; the field is then named by poisoning one field at a
// time. Integer arrays (grain and pair indices) are not poisoned: garbage there would crash the
// stage rather than change its result.
//
// A stage that carries values in its module's workspace to the next stage of the step, or to its
// own next call (Stage::carries_workspace), runs once: its writes are checked, its reads are not.
//
// A violation is raised as the step's internal error, so the run stops and says which stage
// touched which field.
#pragma once

#include "graph/graph_builder.hpp"

namespace silt::graph {

// Runs st.fn on s, checking it; throws std::logic_error on a violation.
void run_checked(const Stage& st, const Model& m, State& s);

}  // namespace silt::graph

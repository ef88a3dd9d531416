// The adders of the built-in modules: each puts its module's stages into a step graph (or into
// the graph of the first state's forces, GraphBuilder::phase()), with their access sets, their
// dependencies and why, their force sources and their events' diagnoses.
#pragma once

#include "graph/graph_builder.hpp"

namespace silt::graph {

void add_core_stages(GraphBuilder& b);
void add_dem_stages(GraphBuilder& b);
void add_shear_stages(GraphBuilder& b);
void add_paste_stages(GraphBuilder& b);
void add_fluid_stages(GraphBuilder& b);

}  // namespace silt::graph

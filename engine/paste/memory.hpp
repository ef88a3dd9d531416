// The memory a lubricated paste will take, estimated when its scene is compiled: `silt check`
// prints it, and a scene that would not fit in the machine is refused before its first step.
//
// What grows is the Cholesky factor of Xi: its fill depends on the network of connections, so
// the estimate builds that network from the initial grains, brought to the solid fraction the
// run will reach (the scene's own with a fixed box; prepare.phi, or a jammed packing after a
// compression or under an imposed pressure, which compacts the paste), and has CHOLMOD analyse
// its pattern (linalg::block_factor_size: the grains' blocks, not their entries, so it stays
// cheap). The rest follows from the counts: the matrix and the per-connection assembly buffers
// (G^T xi G and its positions, kept while the connections stay), the triplets a new pattern is
// built from, the state's copy of the factorised matrix (twice: the state and its restart point)
// and the numerical factorisation's workspace.
#pragma once

#include <cstdint>

#include "silt/model.hpp"

namespace silt::paste {

struct PasteMemory {
  double phi = 0;           // the solid fraction the connections were counted at
  int64_t connections = 0;  // pairs closer than h_max there
  int64_t entries = 0;      // non-zero entries of Xi
  double factor = 0;        // the Cholesky factor held [bytes]
  double held = 0;          // everything else held between steps: matrix, buffers, the state's copies
  double transient = 0;     // the largest peak within a step beyond those (a new pattern, a factorisation)
  double total() const { return factor + held + transient; }
};

PasteMemory estimate_paste_memory(const Model& m);

}  // namespace silt::paste

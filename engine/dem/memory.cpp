// How much memory a scene's grains will take, from the field list: refused at compile time when
// it does not fit in the machine (a scene of 1e9 grains, grains tiny against their box).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/cell_grid.hpp"
#include "core/machine.hpp"
#include "dem/module.hpp"
#include "silt/text.hpp"

namespace silt::dem {
namespace {

// Bytes per grain of every field that follows the grains, and per listed pair of the pair
// fields, as the field list says (modules' fields included).
void field_bytes_per(int dim, int rot, int walls, double* per_grain, double* per_pair) {
  *per_grain = 0;
  *per_pair = 0;
  for (const FieldInfo& f : field_infos()) {
    const double e = static_cast<double>(f.elem_size);
    switch (f.extent) {
      case Extent::kGrain: *per_grain += e; break;
      case Extent::kGrainVec: *per_grain += e * dim; break;
      case Extent::kGrainRot: *per_grain += e * rot; break;
      case Extent::kGrainRotWalls: *per_grain += walls ? e * rot : 0; break;
      case Extent::kGrainWallVec: *per_grain += e * dim * walls; break;
      case Extent::kRowStart: *per_grain += e; break;
      case Extent::kPair: *per_pair += e; break;
      case Extent::kPairVec: *per_pair += e * dim; break;
      default: break;
    }
  }
}

}  // namespace

double grains_memory_bytes(const Model& m, int64_t n) {
  double per_grain = 0, per_pair = 0;
  field_bytes_per(m.dim, m.rot, static_cast<int>(m.walls.size()), &per_grain, &per_pair);
  // Listed pairs per grain: the grains within r_i + r_j + skin of one, half of them (a half list),
  // at a dense packing (0.74 in 3D, 0.91 in 2D), times 1.5 for polydispersity.
  const double r = m.r_mean > 0 ? m.r_mean : 1, reach = m.r_max > 0 ? m.interaction_range() : 2 * r;
  const double packing = m.dim == 3 ? 0.74 : 0.91;
  const double pairs_per_grain = 1.5 * 0.5 * packing * std::pow(reach / r, m.dim);
  // A grain: its fields twice (the state and the restart point), the model's initial values (about
  // 4 D + 5 numbers), its indices in the cell list and the renumbering (4), and its pairs: their
  // fields, the contact candidates, the previous list during a rebuild and the schedule (about 40
  // bytes).
  const double grain = 2 * per_grain + 8.0 * (4 * m.dim + 5) + 16 + pairs_per_grain * (2 * per_pair + 40);
  // The cell grid: one start index per cell, its cells bounded by the grains (neighbor_list.cpp).
  const double grid = 4.0 * (kMaxCellsPerGrain * static_cast<double>(n) + kMaxCellsExtra + 1);
  return static_cast<double>(n) * grain + grid + 4096 * 8.0;
}

void check_memory(const SceneDesc& d, const Model& m, int64_t n, const std::string& key) {
  const double need = grains_memory_bytes(m, n), have = available_memory_bytes();
  if (need > 0.9 * have)
    d.fail(key, "the scene needs about " + format_number(need / (1 << 30), 3) + " GiB for " + std::to_string(n) +
                    " grains; the machine has " + format_number(have / (1 << 30), 3) +
                    " GiB available: use fewer or larger grains");
}

}  // namespace silt::dem

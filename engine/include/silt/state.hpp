// State: everything that changes during a run, as flat arrays (structure of arrays).
//
// The array list is declared once (SILT_STATE_ARRAYS) and allocation, hashing, checkpoints and
// printing are derived from it. Arrays are named <entity>_<quantity>; each line gives its shape,
// unit, and the stage that writes it. Vectors are stored interleaved (x0 y0 z0 x1 ...): D
// entries per grain, with D = Model::dim; rotations have R = Model::rot entries (1 in 2D).
// Several States can share one Model (snapshots, restore, determinism tests).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "silt/model.hpp"

namespace silt {

// clang-format off
#define SILT_STATE_ARRAYS(X)                                                                                   \
  /* hot per-grain arrays */                                                                                   \
  X(double,  particle_x,      "N*D", "m",     "centre, wrapped into periodic directions; kick_drift")            \
  X(double,  particle_v,      "N*D", "m/s",   "velocity relative to the affine box flow; kick_drift, kick") \
  X(double,  particle_w,      "N*R", "rad/s", "angular velocity; kick_drift, kick")                       \
  X(double,  particle_f,      "N*D", "N",     "contact + wall force (gravity excluded); kick")            \
  X(double,  particle_t,      "N*R", "N m",   "torque; kick")                                             \
  X(double,  particle_r,      "N",   "m",     "radius; compile")                                                 \
  X(double,  particle_inv_m,  "N",   "1/kg",  "inverse mass, 0 for frozen grains; compile")                      \
  X(double,  particle_inv_i,  "N",   "1/(kg m^2)", "inverse moment of inertia, 0 for frozen grains; compile")    \
  X(double,  particle_disp,   "N*D", "m",     "displacement relative to the affine flow since the last neighbour build; kick_drift") \
  /* walls */                                                                                                  \
  X(double,  wall_f,          "N*W*D", "N",   "force on the grain from each wall this step; wall_forces")         \
  X(double,  particle_t_wall, "N*R", "N m",   "torque from the walls this step; wall_forces")                    \
  X(double,  wall_hist,       "N*W*D", "m",   "grain-wall tangential spring elongation; wall_forces")            \
  /* neighbour pairs: half Verlet list in CSR form, row i holds j > i sorted */                               \
  X(int32_t, nbr_start,       "N+1", "",      "first pair of row i; update_neighbors")                           \
  X(int32_t, pair_i,          "P",   "",      "first grain of the pair (the row); update_neighbors")             \
  X(int32_t, pair_j,          "P",   "",      "second grain of the pair; update_neighbors")                      \
  X(double,  pair_hist,       "P*D", "m",     "tangential spring elongation, kept while the pair is listed; contact_forces") \
  X(double,  pair_f,          "P*D", "N",     "force on i from j (0 when apart); contact_forces")                \
  X(uint8_t, pair_touch,      "P",   "",      "1 if the pair may hold a force or a spring: it touched at the last force evaluation, or was listed anew with a carried spring; 0 means both are zero; contact_forces") \
  /* cold per-grain arrays */                                                                                  \
  X(uint8_t, particle_frozen, "N",   "",      "1 for frozen grains; compile")                                    \
  X(int32_t, particle_id,     "N",   "",      "stable identity (index in the scene); compile")                   \
  X(int32_t, particle_group,  "N",   "",      "index of the [[grains]] table; compile")
// clang-format on

// Where a numerical event was first seen in a step (lowest index wins: deterministic).
struct Alarm {
  std::atomic<int64_t> first{std::numeric_limits<int64_t>::max()};
  std::atomic<double> value{0};
  Alarm() = default;
  Alarm(const Alarm& o) : first(o.first.load()), value(o.value.load()) {}
  Alarm& operator=(const Alarm& o) {
    first = o.first.load();
    value = o.value.load();
    return *this;
  }
  bool raised() const { return first.load() != std::numeric_limits<int64_t>::max(); }
  void raise(int64_t index, double v);
  void clear() { first = std::numeric_limits<int64_t>::max(); }
};

// Why a run stopped on a numerical failure (exit code 3).
struct StepFailure {
  bool failed = false;
  int64_t step = 0;
  std::string stage;      // stage that detected it
  int64_t particle = -1;  // grain id, when one is to blame
  std::string parameter;  // the parameter to change
  std::string message;    // full sentence
};

struct StageTime {
  double seconds = 0;
  int64_t calls = 0;
};

// A conflict-free order of the pair loop's blocks of rows (built in dem/pair_schedule.cpp).
struct PairSchedule {
  static constexpr int64_t kBlock = 256;  // rows per block
  std::vector<int32_t> blocks;        // block indices, grouped by colour
  std::vector<int32_t> colour_start;  // colour c holds blocks[colour_start[c] .. colour_start[c + 1])
  int colours() const { return static_cast<int>(colour_start.size()) - 1; }
  // The same order as a graph: block b may run once its n_before[b] predecessors have run (the
  // blocks of earlier colours that write a grain it writes, the nearest for each such grain); its
  // successors are after[after_start[b] .. after_start[b + 1]). roots: the blocks without
  // predecessors. Block b is the first to write the grains of the blocks
  // clears[clears_start[b] .. clears_start[b + 1]).
  std::vector<int32_t> n_before, after_start, after, roots, clears_start, clears;
  std::vector<int32_t> waiting;  // predecessors not yet run, during a pass (dem/pair_schedule.hpp)
};

struct State {
#define SILT_DECLARE_ARRAY(type, name, shape, unit, doc) std::vector<type> name;
  SILT_STATE_ARRAYS(SILT_DECLARE_ARRAY)
#undef SILT_DECLARE_ARRAY

  int dim = 3, rot = 3;
  int64_t n = 0;      // grains
  int n_walls = 0;

  double t = 0;       // simulated time [s]
  int64_t step = 0;   // steps done
  double dt = 0;      // step in use [s]

  Box box;                                    // current box; lengths change under stress control
  std::array<double, 3> box_rate{0, 0, 0};    // dL/dt [m/s]; kick_drift, box_kick
  std::array<double, 3> box_stress{0, 0, 0};  // sigma_aa driving the box [Pa]; box_kick
  double shear_rate = 0;         // gammadot of the Lees-Edwards flow v_x = gammadot (y - lo_y) [1/s]
  double shear_stress = 0;       // tau = -sigma_xy driving a stress-controlled shear [Pa]; box_kick
  double le_displacement = 0;    // displacement of the upper image since t = 0 [m]; kick_drift
  double shear_strain = 0;       // accumulated strain gamma = integral of gammadot dt; kick_drift
  double nbr_strain = 0;         // affine strain since the last neighbour build; kick_drift

  // Neighbour-list bookkeeping.
  bool nbr_valid = false;     // false forces a rebuild at the next update_neighbors
  double nbr_max_disp = 0;    // largest non-affine displacement since the last build [m]; kick_drift
  double nbr_step_disp = 0;   // largest non-affine displacement of the last drift [m]; kick_drift
  int64_t nbr_builds = 0;

  // Whether anything looks at the state at the end of this step. Simulation::run clears it for
  // the steps whose end nothing sees; such a step leaves pair_f as it was (scattered stores per
  // contact cost about a tenth of a step). Nothing in the dynamics reads pair_f but a
  // controlled box, which ignores the flag: the dynamics are the same bits, and pair_f is exact
  // at every boundary that a hook, a request, an interrupt or the caller sees.
  bool boundary_seen = true;

  // Numerical events raised by stages during the current step.
  Alarm alarm_nonfinite;  // grain index with a NaN/Inf velocity or position
  Alarm alarm_overlap;    // grain index of a pair overlapping beyond limits.max_overlap
  StepFailure failure;

  std::map<std::string, StageTime> profile;  // wall time per stage

  // Scratch space of the stages (cell lists, previous neighbour lists). Not part of the state's
  // identity: never hashed nor saved.
  struct Scratch {
    Scratch() = default;
    Scratch(const Scratch&) {}  // copies of a State start empty
    Scratch& operator=(const Scratch&) {  // and keep their own buffers, but not a schedule or
      schedule_valid = false;             // candidates of another list
      candidates_valid = false;
      return *this;
    }
    std::vector<int32_t> cell_of, cell_start, cell_items, row_count;
    std::vector<std::vector<int32_t>> chunk_j;  // partners found per chunk of rows
    std::vector<int32_t> old_start, old_j;
    std::vector<double> old_hist;
    std::vector<int32_t> perm;  // new index -> old index of the last spatial sort
    std::vector<std::byte> permute_buf;  // a per-grain array being renumbered by perm
    PairSchedule schedule;      // of the current pair list when schedule_valid
    bool schedule_valid = false;
    // Contact candidates (dem/contact_candidates.hpp): the listed pairs of block b that may touch
    // are cand_p/i/j[nbr_start[b * kBlock] .. cand_end[b]) (pair index, grains).
    std::vector<int32_t> cand_p, cand_i, cand_j, cand_end;
    bool candidates_valid = false;
    double cand_travel = 0;  // bound on any grain's displacement since the selection [m]
    double cand_strain = 0;  // nbr_strain at the selection
    int64_t cand_selections = 0;
  } scratch;

  int64_t n_pairs() const { return static_cast<int64_t>(pair_j.size()); }
  // Contact candidates of the current selection (dem/contact_candidates.hpp).
  int64_t n_candidates() const {
    int64_t c = 0;
    for (size_t b = 0; b < scratch.cand_end.size(); ++b)
      c += scratch.cand_end[b] - nbr_start[b * PairSchedule::kBlock];
    return c;
  }
};

// A fresh State at t = 0 from the Model's initial grains.
State make_state(const Model& m);

// FNV-1a hash of every array and of t, step, dt and the box: equal hashes mean bitwise equal
// states (the determinism test).
uint64_t state_hash(const State& s);

// Visit every array of the field list: f(name, std::vector<T>&).
template <class F>
void for_each_array(State& s, F&& f) {
#define SILT_VISIT_ARRAY(type, name, shape, unit, doc) f(#name, s.name);
  SILT_STATE_ARRAYS(SILT_VISIT_ARRAY)
#undef SILT_VISIT_ARRAY
}
template <class F>
void for_each_array(const State& s, F&& f) {
#define SILT_VISIT_ARRAY(type, name, shape, unit, doc) f(#name, s.name);
  SILT_STATE_ARRAYS(SILT_VISIT_ARRAY)
#undef SILT_VISIT_ARRAY
}

// Visit every array with its declared shape ("N", "N*D", "P", ...): f(name, shape, vector&).
template <class F>
void for_each_array_shaped(State& s, F&& f) {
#define SILT_VISIT_ARRAY(type, name, shape, unit, doc) f(#name, shape, s.name);
  SILT_STATE_ARRAYS(SILT_VISIT_ARRAY)
#undef SILT_VISIT_ARRAY
}

// Index of every grain id (inverse of particle_id): grains are kept in spatial order, so an
// index is not an identity.
std::vector<int64_t> index_of_ids(const State& s);

// Bytes held by the State's arrays (capacity), for memory reports.
size_t state_bytes(const State& s);

}  // namespace silt

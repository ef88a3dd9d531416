// State: everything that changes during a run, as flat arrays (structure of arrays) and scalars.
//
// The field list is declared once (SILT_STATE_FIELDS), grouped by the module that owns each
// field, with its extent (what it is indexed by, silt/fields.hpp), unit, and the stage that
// writes it. Allocation, hashing, checkpoints, grain renumbering, the ids of the stages' access
// sets and the shell's `fields` command are derived from it; a module may add fields of its own
// (double arrays) through its ModuleSpec. Vectors are stored interleaved (x0 y0 z0 x1 ...): D
// entries per grain, with D = Model::dim; rotations have R = Model::rot entries (1 in 2D).
// Several States can share one Model (snapshots, restore, determinism tests).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "silt/events.hpp"
#include "silt/fields.hpp"
#include "silt/model.hpp"
#include "silt/profile.hpp"

namespace silt {

// X(module, type, name, extent, unit, doc)
// clang-format off
#define SILT_STATE_FIELDS(X)                                                                                    \
  /* ---- core: time and the periodic box */                                                                   \
  X(core,  double,  t,               kScalar,      "s",     "simulated time; advance_clock")                   \
  X(core,  int64_t, step,            kScalar,      "",      "steps done; advance_clock")                       \
  X(core,  double,  dt,              kScalar,      "s",     "time step of the step under way; choose_dt")      \
  X(core,  Box,     box,             kScalar,      "m",     "current box: lengths change under stress control, the Lees-Edwards offset under shear; kick_drift") \
  /* ---- dem: hot per-grain arrays */                                                                         \
  X(dem,   double,  particle_x,      kGrainVec,    "m",     "centre, wrapped into periodic directions; kick_drift") \
  X(dem,   double,  particle_v,      kGrainVec,    "m/s",   "velocity relative to the affine box flow; kick_drift, kick") \
  X(dem,   double,  particle_w,      kGrainRot,    "rad/s", "angular velocity; kick_drift, kick")              \
  X(dem,   double,  particle_f,      kGrainVec,    "N",     "pair forces, then the sum of every force source (gravity excluded); contact_forces, kick") \
  X(dem,   double,  particle_t,      kGrainRot,    "N m",   "pair torques, then the sum of every torque source; contact_forces, kick") \
  X(dem,   double,  particle_r,      kGrain,       "m",     "radius; compile")                                 \
  X(dem,   double,  particle_inv_m,  kGrain,       "1/kg",  "inverse mass, 0 for frozen grains; compile")      \
  X(dem,   double,  particle_inv_i,  kGrain,       "1/(kg m^2)", "inverse moment of inertia, 0 for frozen grains; compile") \
  X(dem,   double,  particle_disp,   kGrainVec,    "m",     "displacement relative to the affine flow since the last neighbour build; kick_drift") \
  /* ---- dem: walls */                                                                                        \
  X(dem,   double,  wall_f,          kGrainWallVec, "N",    "force on the grain from each wall this step; wall_forces") \
  X(dem,   double,  particle_t_wall, kGrainRotWalls, "N m", "torque from the walls this step; wall_forces")    \
  X(dem,   double,  wall_hist,       kGrainWallVec, "m",    "grain-wall tangential spring elongation; wall_forces") \
  /* ---- dem: neighbour pairs, a half Verlet list in CSR form: row i holds j > i sorted */                  \
  X(dem,   int32_t, nbr_start,       kRowStart,    "",      "first pair of row i; update_neighbors")           \
  X(dem,   int32_t, pair_i,          kPair,        "",      "first grain of the pair (the row); update_neighbors") \
  X(dem,   int32_t, pair_j,          kPair,        "",      "second grain of the pair; update_neighbors")      \
  X(dem,   double,  pair_hist,       kPairVec,     "m",     "tangential spring elongation, kept while the pair is listed; contact_forces") \
  X(dem,   double,  pair_f,          kPairVec,     "N",     "force on i from j (0 when apart); contact_forces") \
  X(dem,   uint8_t, pair_touch,      kPair,        "",      "1 if the pair may hold a force or a spring: it touched at the last force evaluation, or was listed anew with a carried spring; 0 means both are zero; contact_forces") \
  /* ---- dem: neighbour-list bookkeeping */                                                                  \
  X(dem,   bool,    nbr_valid,       kScalar,      "",      "false forces a rebuild at the next update_neighbors; update_neighbors") \
  X(dem,   double,  nbr_max_disp,    kScalar,      "m",     "largest non-affine displacement since the last build; kick_drift") \
  X(dem,   double,  nbr_step_disp,   kScalar,      "m",     "largest non-affine displacement of the last drift; kick_drift") \
  X(dem,   double,  nbr_strain,      kScalar,      "",      "affine strain since the last neighbour build; kick_drift, update_neighbors") \
  X(dem,   int64_t, nbr_builds,      kScalar,      "",      "neighbour-list builds so far; update_neighbors") \
  /* ---- dem: cold per-grain arrays */                                                                       \
  X(dem,   uint8_t, particle_frozen, kGrain,       "",      "1 for frozen grains; compile")                    \
  X(dem,   int32_t, particle_id,     kGrain,       "",      "stable identity (index in the scene); compile")   \
  X(dem,   int32_t, particle_group,  kGrain,       "",      "index of the [[grains]] table; compile")          \
  /* ---- shear: stress-controlled box lengths and Lees-Edwards shear */                                      \
  X(shear, Vec3a,   box_rate,        kScalar,      "m/s",   "dL/dt of each box length; kick_drift, box_kick")  \
  X(shear, Vec3a,   box_stress,      kScalar,      "Pa",    "sigma_aa driving each controlled length; box_kick") \
  X(shear, Vec3a,   box_stretch,     kScalar,      "",      "L(t + dt) / L(t) of each length in the step under way; box_drift") \
  X(shear, double,  shear_rate,      kScalar,      "1/s",   "gammadot of the flow v_x = gammadot (y - lo_y); kick_drift, box_kick") \
  X(shear, double,  shear_stress,    kScalar,      "Pa",    "tau = -sigma_xy driving a stress-controlled shear; box_kick") \
  X(shear, double,  le_displacement, kScalar,      "m",     "displacement of the upper image since t = 0; kick_drift") \
  X(shear, double,  shear_strain,    kScalar,      "",      "accumulated strain, the integral of gammadot dt; kick_drift")
// clang-format on

// Ids of the built-in fields: fid::particle_x, ...; module fields follow fid::kBuiltinCount.
namespace fid {
enum : FieldId {
#define SILT_FIELD_ID(module, type, name, extent, unit, doc) name,
  SILT_STATE_FIELDS(SILT_FIELD_ID)
#undef SILT_FIELD_ID
      kBuiltinCount
};
}  // namespace fid

// Storage of a field: the value itself for a scalar, a vector otherwise.
template <class T, Extent E>
using FieldStorage = std::conditional_t<E == Extent::kScalar, T, std::vector<T>>;
// Whether a field's storage (as for_each_field passes it) is an array.
template <class T>
inline constexpr bool kIsArray = false;
template <class T>
inline constexpr bool kIsArray<std::vector<T>> = true;

struct State {
#define SILT_DECLARE_FIELD(module, type, name, extent, unit, doc) FieldStorage<type, Extent::extent> name{};
  SILT_STATE_FIELDS(SILT_DECLARE_FIELD)
#undef SILT_DECLARE_FIELD
  // Fields of modules (double arrays), by id - fid::kBuiltinCount; empty for modules the scene
  // does not enable.
  std::vector<std::vector<double>> module_fields;

  // Dimensions of the arrays (from the Model).
  int dim = 3, rot = 3;
  int64_t n = 0;  // grains
  int n_walls = 0;
  std::array<int64_t, 3> cells{0, 0, 0};  // grid cells per direction (0: no grid)

  // Whether anything looks at the state at the end of this step. Simulation::run clears it for
  // the steps whose end nothing sees; such a step leaves pair_f as it was (scattered stores per
  // contact cost about a tenth of a step). Nothing in the dynamics reads pair_f but a
  // controlled box, which ignores the flag. In a step of the DEM alone it also leaves its second
  // half kick to the next step (dem::late_kick_drift), or makes it and the next step's kick and
  // drift inside its pair loop (dem::kick_and_next_drift): the state between two such steps is
  // half kicked, or already moved. The dynamics are the same bits, and the state is exact at
  // every boundary that a hook, a request, an interrupt or the caller sees.
  bool boundary_seen = true;

  // Numerical events raised by stages during the current step, an exception thrown by one, and
  // the failure they made (Simulation::step).
  Events events;
  InternalErrorSlot internal;
  StepFailure failure;

  Profile profile;  // wall time per stage

  int64_t n_pairs() const { return static_cast<int64_t>(pair_j.size()); }
  // A module's field by id.
  std::vector<double>& module_field(FieldId id) { return module_fields.at(id - fid::kBuiltinCount); }
  const std::vector<double>& module_field(FieldId id) const { return module_fields.at(id - fid::kBuiltinCount); }
};

// A fresh State at t = 0 from the Model's initial grains; every field of the enabled modules
// allocated at its extent.
State make_state(const Model& m);

// Number of items of a field of this extent in this state (pair extents: the current list).
int64_t extent_size(const State& s, Extent e);

// The modules' fields of a state fitted to the modules `m` turns on: a module's that is off are
// emptied; one's that is on, of a fixed extent, are made as a new state has them (zeros) where
// they do not fit: any length but their extent's (kMismatched: a state made without the module,
// or the grid of another model, kept across a recompile), or none at all, grid fields aside
// (kEmptyPerGrain: a checkpoint written with the module off, whose other lengths are checked).
enum class FitFields { kMismatched, kEmptyPerGrain };
void fit_module_fields(const Model& m, State& s, FitFields how);

// Visit every field: f(const FieldInfo&, storage&), storage being the scalar (T&) or the vector
// (std::vector<T>&); module fields come last, as std::vector<double>&.
template <class S, class F>
void for_each_field(S& s, F&& f) {
  const auto& info = field_infos();
#define SILT_VISIT_FIELD(module, type, name, extent, unit, doc) f(info[fid::name], s.name);
  SILT_STATE_FIELDS(SILT_VISIT_FIELD)
#undef SILT_VISIT_FIELD
  for (size_t k = 0; k < s.module_fields.size(); ++k) f(info[fid::kBuiltinCount + k], s.module_fields[k]);
}

// The bytes that make a field's value, in a fixed order: g(const void*, size_t) once per run of
// bytes (a vector: its length, then its data; a Box: member by member, without padding).
template <class G>
void field_bytes(const double& v, G&& g) {
  g(&v, sizeof v);
}
template <class G>
void field_bytes(const int64_t& v, G&& g) {
  g(&v, sizeof v);
}
template <class G>
void field_bytes(const bool& v, G&& g) {
  g(&v, sizeof v);
}
template <class G>
void field_bytes(const Vec3a& v, G&& g) {
  g(v.data(), sizeof(double) * 3);
}
template <class G>
void field_bytes(const Box& b, G&& g) {
  g(b.lo.data(), sizeof(double) * 3);
  g(b.len.data(), sizeof(double) * 3);
  g(b.periodic.data(), sizeof(bool) * 3);
  g(&b.lees_edwards, sizeof(bool));
  g(&b.le_offset, sizeof(double));
}
template <class T, class G>
void field_bytes(const std::vector<T>& v, G&& g) {
  const uint64_t n = v.size();
  g(&n, sizeof n);
  if (n) g(v.data(), n * sizeof(T));
}

// Hash of one field (XXH3), and of every field (FNV-1a, as the shell's `hash` prints it): equal
// hashes mean bitwise equal states (every field of the list is in it, and nothing else is state).
uint64_t field_hash(const State& s, FieldId id);
uint64_t state_hash(const State& s);
// Each field's field_hash, by id (the access check compares them around a stage).
std::vector<uint64_t> field_hashes(const State& s);

// A double array field by id (built-in or a module's); throws std::logic_error for another kind.
std::span<double> double_field(State& s, FieldId id);
std::span<const double> double_field(const State& s, FieldId id);

// Index of every grain id (inverse of particle_id): grains are kept in spatial order, so an
// index is not an identity.
std::vector<int64_t> index_of_ids(const State& s);

// Bytes held by the State's fields (capacity), for memory reports.
size_t state_bytes(const State& s);

}  // namespace silt

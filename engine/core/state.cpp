#include "silt/state.hpp"

#include <memory>
#include <new>
#include <stdexcept>

#include <xxhash.h>

#include "core/rng.hpp"

namespace silt {

int64_t extent_size(const State& s, Extent e) {
  const int64_t n = s.n, D = s.dim, R = s.rot, W = s.n_walls;
  const int64_t p = s.n_pairs();
  const auto& c = s.cells;
  switch (e) {
    case Extent::kScalar: return 1;
    case Extent::kGrain: return n;
    case Extent::kGrainVec: return n * D;
    case Extent::kGrainRot: return n * R;
    case Extent::kGrainRotWalls: return W > 0 ? n * R : 0;
    case Extent::kGrainWallVec: return n * W * D;
    case Extent::kRowStart: return n + 1;
    case Extent::kPair: return p;
    case Extent::kPairVec: return p * D;
    case Extent::kCell: return c[0] * c[1] * (D == 3 ? c[2] : 1);
    case Extent::kFaceX: return (c[0] + 1) * c[1] * (D == 3 ? c[2] : 1);
    case Extent::kFaceY: return c[0] * (c[1] + 1) * (D == 3 ? c[2] : 1);
    case Extent::kFaceZ: return D == 3 ? c[0] * c[1] * (c[2] + 1) : 0;
    case Extent::kFree: return 0;
  }
  return 0;
}

void fit_module_fields(const Model& m, State& s, FitFields how) {
  const auto& info = field_infos();
  s.module_fields.resize(info.size() - fid::kBuiltinCount);
  for (size_t k = 0; k < s.module_fields.size(); ++k) {
    const FieldInfo& f = info[fid::kBuiltinCount + k];
    std::vector<double>& v = s.module_fields[k];
    if (!m.module_on(f.module)) {
      v.clear();
      continue;
    }
    if (f.extent == Extent::kFree) continue;
    const int64_t want = extent_size(s, f.extent);
    const bool refit =
        how == FitFields::kMismatched ? static_cast<int64_t>(v.size()) != want : v.empty() && !on_grid(f.extent);
    if (refit) v.assign(static_cast<size_t>(want), 0.0);
  }
}

State make_state(const Model& m) {
  State s;
  const int64_t n = m.n_grains;
  s.dim = m.dim;
  s.rot = m.rot;
  s.n = n;
  s.n_walls = static_cast<int>(m.walls.size());
  s.cells = m.cells;
  // Every array at its extent, zero (the pair list is empty until the first neighbour build);
  // the fields of the modules the scene enables, the others empty.
  s.module_fields.resize(field_infos().size() - fid::kBuiltinCount);
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      const bool on = f.id < fid::kBuiltinCount || m.module_on(f.module);
      v.assign(on ? static_cast<size_t>(extent_size(s, f.extent)) : 0, {});
    }
  });
  // The initial values.
  s.dt = m.dt;
  s.box = m.box;
  s.particle_x = m.init.x;
  s.particle_v = m.init.v;
  s.particle_w = m.init.w;
  s.particle_r = m.init.radius;
  for (int64_t i = 0; i < n; ++i) {
    const bool frozen = m.init.frozen[i];
    s.particle_inv_m[i] = frozen ? 0.0 : 1.0 / m.init.mass[i];
    s.particle_inv_i[i] = frozen ? 0.0 : 1.0 / m.init.inertia[i];
    s.particle_id[i] = static_cast<int32_t>(i);
  }
  s.particle_frozen = m.init.frozen;
  s.particle_group = m.init.group;
  s.shear_rate = m.shear.rate;
  s.nbr_valid = false;
  return s;
}

namespace {

// A field's bytes through XXH3 (64 bit): 0.5 ms for 8 MiB where FNV-1a, a multiplication a
// byte, takes 10 ms; the paste fingerprints its stored factor matrix (megabytes) at every solve
// with it, and the sanitizer build's access check every field around every stage. The streaming
// state is made once per thread, not per hash.
template <class V>
uint64_t xxh3_of(const V& v) {
  struct Free {
    void operator()(XXH3_state_t* st) const { XXH3_freeState(st); }
  };
  thread_local const std::unique_ptr<XXH3_state_t, Free> state(XXH3_createState());
  XXH3_state_t* st = state.get();
  if (!st) throw std::bad_alloc();
  XXH3_64bits_reset(st);
  field_bytes(v, [&](const void* p, size_t bytes) { XXH3_64bits_update(st, p, bytes); });
  return XXH3_64bits_digest(st);
}

}  // namespace

uint64_t field_hash(const State& s, FieldId id) {
  uint64_t h = 0;
  for_each_field(s, [&](const FieldInfo& f, const auto& v) {
    if (f.id == id) h = xxh3_of(v);
  });
  return h;
}

std::vector<uint64_t> field_hashes(const State& s) {
  std::vector<uint64_t> out;
  for_each_field(s, [&](const FieldInfo&, const auto& v) { out.push_back(xxh3_of(v)); });
  return out;
}

uint64_t state_hash(const State& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  for_each_field(s, [&](const FieldInfo&, const auto& v) {
    field_bytes(v, [&](const void* p, size_t bytes) { h = fnv1a(p, bytes, h); });
  });
  return h;
}

namespace {
template <class S>
auto double_field_of(S& s, FieldId id) {
  using Span = std::conditional_t<std::is_const_v<S>, std::span<const double>, std::span<double>>;
  Span out;
  bool found = false;
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if (f.id != id) return;
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::vector<double>>) {
      out = Span(v.data(), v.size());
      found = true;
    }
  });
  if (!found) throw std::logic_error("field " + field_info(id).name + " is not an array of doubles");
  return out;
}
}  // namespace

std::span<double> double_field(State& s, FieldId id) { return double_field_of(s, id); }
std::span<const double> double_field(const State& s, FieldId id) { return double_field_of(s, id); }

std::vector<int64_t> index_of_ids(const State& s) {
  std::vector<int64_t> out(s.n, -1);
  for (int64_t i = 0; i < s.n; ++i) out[s.particle_id[i]] = i;
  return out;
}

size_t state_bytes(const State& s) {
  size_t b = sizeof(State);
  for_each_field(s, [&](const FieldInfo&, const auto& v) {
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) b += v.capacity() * sizeof(v[0]);
  });
  return b;
}

}  // namespace silt

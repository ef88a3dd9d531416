// The State's field list drives its hash and its checkpoints: one bit of any field changes the
// hash (equal hashes mean bitwise equal states), and a checkpoint gives back every field.
#include <doctest/doctest.h>

#include <cstdio>
#include <cstring>

#include "silt/io.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

// One bit of field `id` flipped (or, for an empty array, one entry added).
void flip(State& s, FieldId id) {
  for_each_field(s, [&](const FieldInfo& f, auto& v) {
    if (f.id != id) return;
    using V = std::remove_cvref_t<decltype(v)>;
    if constexpr (kIsArray<V>) {
      if (v.empty()) {
        v.emplace_back();
        return;
      }
      unsigned char* p = reinterpret_cast<unsigned char*>(v.data());
      p[0] ^= 1;
    } else if constexpr (std::is_same_v<V, Box>) {
      v.le_offset = std::nextafter(v.le_offset, 1.0);
    } else if constexpr (std::is_same_v<V, bool>) {
      v = !v;
    } else {
      unsigned char* p = reinterpret_cast<unsigned char*>(&v);
      p[0] ^= 1;
    }
  });
}

}  // namespace

TEST_CASE("one bit of any field of the list changes the state hash") {
  // A sheared frictional gas: every built-in field holds something.
  auto sim = test::simulation_from(test::frictional_gas(3, 0.5, 0.0, 0.0), 1);
  for (int k = 0; k < 50; ++k) REQUIRE(sim->step());
  const State& s = sim->state();
  const uint64_t h = state_hash(s);
  int fields = 0;
  for (const FieldInfo& f : field_infos()) {
    INFO(f.name);
    State c = s;
    flip(c, f.id);
    CHECK(state_hash(c) != h);
    CHECK(field_hash(c, f.id) != field_hash(s, f.id));
    ++fields;
  }
  CHECK(fields >= fid::kBuiltinCount);
}

TEST_CASE("a checkpoint gives back every field, bit for bit") {
  auto sim = test::simulation_from(test::frictional_gas(2, 0.5, 0.1, 0.0), 1);
  for (int k = 0; k < 50; ++k) REQUIRE(sim->step());
  write_checkpoint("state_test.ckpt", sim->model(), sim->state());
  const State back = read_checkpoint("state_test.ckpt", sim->model());
  const auto want = field_hashes(sim->state()), got = field_hashes(back);
  REQUIRE(want.size() == got.size());
  for (size_t f = 0; f < want.size(); ++f) {
    INFO(field_info(static_cast<FieldId>(f)).name);
    CHECK(got[f] == want[f]);
  }
  CHECK(state_hash(back) == state_hash(sim->state()));
  std::remove("state_test.ckpt");
}

TEST_CASE("make_state allocates every field at its extent") {
  const Model m = compile(load_scene_file(test::scene_path("silo")));
  const State s = make_state(m);
  for_each_field(s, [&](const FieldInfo& f, const auto& v) {
    if constexpr (kIsArray<std::remove_cvref_t<decltype(v)>>) {
      INFO(f.name);
      const bool on = f.id < fid::kBuiltinCount || m.module_on(f.module);
      CHECK(static_cast<int64_t>(v.size()) == (on ? extent_size(s, f.extent) : 0));
    }
  });
  CHECK(extent_size(s, Extent::kGrainWallVec) == m.n_grains * 5 * 3);
}

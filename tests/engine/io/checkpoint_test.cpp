// Checkpoints: round trip, bitwise continuation, refusal of corrupt or foreign files.
#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>

#include "silt/io.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

const char* kScene = R"(
[scene]
dimension = 3
seed = 3
[domain]
lo = [0, 0, 0]
hi = [6, 6, 10]
periodic = [true, true, false]
[gravity]
magnitude = 9.81
[contact]
model = "spring_dashpot"
restitution = 0.7
contact_time = 2e-3
friction = 0.5
[[walls]]
point = [0, 0, 0]
normal = [0, 0, 1]
[[grains]]
count = 200
radius_min = 0.3
radius_max = 0.4
placement = "random"
[run]
dt_over_tc = 0.05
)";

}  // namespace

TEST_CASE("restoring a checkpoint and running N steps equals running without interruption") {
  const std::string path = "checkpoint_test.ckpt";
  auto a = test::simulation_from(kScene, 2);
  for (int k = 0; k < 700; ++k) REQUIRE(a->step());
  write_checkpoint(path, a->model(), a->state());
  for (int k = 0; k < 500; ++k) REQUIRE(a->step());

  auto b = test::simulation_from(kScene, 1);
  b->restore(read_checkpoint(path, b->model()));
  CHECK(b->state().step == 700);
  for (int k = 0; k < 500; ++k) REQUIRE(b->step());
  CHECK(state_hash(b->state()) == state_hash(a->state()));
  std::remove(path.c_str());
}

TEST_CASE("corrupt, truncated and foreign checkpoints are refused") {
  const std::string path = "checkpoint_test2.ckpt";
  auto a = test::simulation_from(kScene, 1);
  for (int k = 0; k < 10; ++k) REQUIRE(a->step());
  write_checkpoint(path, a->model(), a->state());
  {  // flip one byte in the middle
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x55');
  }
  CHECK_THROWS_WITH_AS(read_checkpoint(path, a->model()), doctest::Contains("corrupt"), IoError);
  write_checkpoint(path, a->model(), a->state());
  std::string other = kScene;
  other.replace(other.find("count = 200"), 11, "count = 201");
  auto c = test::simulation_from(other, 1);
  CHECK_THROWS_WITH_AS(read_checkpoint(path, c->model()), doctest::Contains("different system"), IoError);
  // Run parameters are not part of the system: a packing restores under another friction.
  std::string steered = kScene;
  steered.replace(steered.find("friction = 0.5"), 14, "friction = 0.1");
  auto d = test::simulation_from(steered, 1);
  CHECK_NOTHROW(read_checkpoint(path, d->model()));
  CHECK_THROWS_AS(read_checkpoint("no_such_file.ckpt", a->model()), IoError);
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f << "not a checkpoint";
  }
  CHECK_THROWS_WITH_AS(read_checkpoint(path, a->model()), doctest::Contains("not a silt checkpoint"), IoError);
  std::remove(path.c_str());
}

TEST_CASE("a checkpoint write never leaves a half file in place of the previous one") {
  const std::string path = "checkpoint_test3.ckpt";
  auto a = test::simulation_from(kScene, 1);
  write_checkpoint(path, a->model(), a->state());
  // Writing into a directory that does not exist fails cleanly and leaves nothing behind.
  CHECK_THROWS_AS(write_checkpoint("no_dir/x.ckpt", a->model(), a->state()), IoError);
  // The temporary name is the only file written before the rename.
  std::FILE* f = std::fopen((path + ".tmp").c_str(), "r");
  CHECK(f == nullptr);
  CHECK_NOTHROW(read_checkpoint(path, a->model()));
  std::remove(path.c_str());
}

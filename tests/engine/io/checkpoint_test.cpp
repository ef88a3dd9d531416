// Checkpoints: round trip, bitwise continuation, refusal of corrupt or foreign files.
#include <doctest/doctest.h>

#include <sys/resource.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "core/rng.hpp"
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

TEST_CASE("a checkpoint of another system is refused, naming what differs, and other parameters are reported") {
  const std::string path = "checkpoint_test3.ckpt";
  auto a = test::simulation_from(kScene, 1);
  write_checkpoint(path, a->model(), a->state());
  auto refused = [&](std::string scene, const std::string& from, const std::string& to) {
    scene.replace(scene.find(from), from.size(), to);
    const Model m = test::model_from(scene);
    std::string message;
    try {
      read_checkpoint(path, m);
    } catch (const IoError& e) {
      message = e.what();
    }
    return message;
  };
  // A wall elsewhere: same grains, same count of walls, another system.
  CHECK(refused(kScene, "point = [0, 0, 0]", "point = [0, 0, -0.5]") ==
        "checkpoint 'checkpoint_test3.ckpt' was written for a different system: wall 0: point (0, 0, 0), normal (0, 0, "
        "1) "
        "in the checkpoint, point (0, 0, -0.5), normal (0, 0, 1) in the scene");
  CHECK(refused(kScene, "periodic = [true, true, false]", "periodic = [true, false, false]")
            .find("periodic along x y in the checkpoint, x in the scene") != std::string::npos);
  CHECK(refused(kScene, "radius_max = 0.4", "radius_max = 0.41").find("the grains differ") != std::string::npos);
  // Other run parameters restore, and are reported.
  std::string steered = kScene;
  steered.replace(steered.find("friction = 0.5"), 14, "friction = 0.1");
  steered.replace(steered.find("dt_over_tc = 0.05"), 17, "dt = 1e-4");
  const Model d = test::model_from(steered);
  std::vector<std::string> differences;
  const State s = read_checkpoint(path, d, &differences);
  CHECK(state_hash(s) == state_hash(a->state()));
  REQUIRE(differences.size() == 3);
  CHECK(differences[0] == "contact.friction = 0.5 in the checkpoint, 0.1 in the scene");
  CHECK(differences[1] == "run.dt = (not set) in the checkpoint, 0.0001 in the scene");
  CHECK(differences[2] == "run.dt_over_tc = 0.05 in the checkpoint, (not set) in the scene");
  std::remove(path.c_str());
}

TEST_CASE("a checkpoint of another format version is refused with both versions") {
  const std::string path = "checkpoint_test4.ckpt";
  auto a = test::simulation_from(kScene, 1);
  write_checkpoint(path, a->model(), a->state());
  std::vector<char> bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  uint32_t version;
  std::memcpy(&version, bytes.data() + 8, 4);
  CHECK(version == 5);
  version = 4;  // an older silt's file, whole and with a right checksum
  std::memcpy(bytes.data() + 8, &version, 4);
  const uint64_t sum = fnv1a(bytes.data(), bytes.size() - 8);
  std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  CHECK_THROWS_WITH_AS(read_checkpoint(path, a->model()),
                       doctest::Contains("has format version 4; this silt reads version 5"), IoError);
  std::remove(path.c_str());
}

TEST_CASE("a checkpoint write that fails halfway leaves the previous file and no temporary one") {
  // The file size limit makes the write of the new checkpoint fail after its first bytes.
  const std::string path = "checkpoint_test5.ckpt";
  auto a = test::simulation_from(kScene, 1);
  write_checkpoint(path, a->model(), a->state());
  const uint64_t before = state_hash(read_checkpoint(path, a->model()));
  for (int k = 0; k < 10; ++k) REQUIRE(a->step());
  rlimit old{};
  REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG
  rlimit small = old;
  small.rlim_cur = 4096;
  REQUIRE(setrlimit(RLIMIT_FSIZE, &small) == 0);
  CHECK_THROWS_WITH_AS(write_checkpoint(path, a->model(), a->state()), doctest::Contains("cannot write checkpoint"),
                       IoError);
  REQUIRE(setrlimit(RLIMIT_FSIZE, &old) == 0);
  std::signal(SIGXFSZ, previous);
  CHECK(state_hash(read_checkpoint(path, a->model())) == before);
  // Nor a temporary file beside it.
  const std::string base = std::filesystem::path(path).filename().string() + ".tmp";
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::absolute(path).parent_path()))
    CHECK(e.path().filename().string().rfind(base, 0) == std::string::npos);
  // Not into a directory either, and a directory is not read as one.
  CHECK_THROWS_WITH_AS(write_checkpoint(".", a->model(), a->state()), doctest::Contains("is a directory"), IoError);
  CHECK_THROWS_WITH_AS(read_checkpoint(".", a->model()), doctest::Contains("'.' is a directory"), IoError);
  std::remove(path.c_str());
}

TEST_CASE("a checkpoint edited with its checksum recomputed is refused as corrupt, naming what is wrong") {
  auto a = test::simulation_from(kScene, 1);
  for (int k = 0; k < 30; ++k) REQUIRE(a->step());
  REQUIRE(a->state().n_pairs() > 0);
  const std::string path = "checkpoint_test_edit.ckpt";
  // write_checkpoint writes whatever the state holds, with a right checksum: an edited file.
  auto refused = [&](const std::function<void(State&)>& edit) {
    State s = a->state();
    edit(s);
    write_checkpoint(path, a->model(), s);
    try {
      read_checkpoint(path, a->model());
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK(refused([](State& s) { s.pair_j[0] = 1000000; }).find("corrupt: pair 0") != std::string::npos);
  CHECK(refused([](State& s) { s.particle_x.clear(); }).find("corrupt: particle_x has 0 entries") != std::string::npos);
  CHECK(refused([](State& s) { s.particle_v[4] = std::nan(""); }).find("particle_v[4] is not finite") !=
        std::string::npos);
  CHECK(refused([](State& s) { s.particle_id[3] = s.particle_id[4]; }).find("particle_id") != std::string::npos);
  CHECK(refused([](State& s) { s.nbr_start[5] = -3; }).find("corrupt") != std::string::npos);
  CHECK(refused([](State& s) { s.box.len[0] = 0; }).find("the box") != std::string::npos);
  CHECK(refused([](State& s) { s.pair_hist.pop_back(); }).find("pair_hist has") != std::string::npos);
  CHECK(refused([](State&) {}).empty());  // the unedited state is fine
  std::remove(path.c_str());
}

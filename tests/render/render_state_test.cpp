// Drawing frames never changes a run: the states with and without frames are the same, bit for
// bit, in process and through the command line. Frames fall at odd steps (every 7), where a run
// without them would not store its pair forces (Simulation::run, State::boundary_seen).
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "render/render_support.hpp"
#include "support/scenes.hpp"

using namespace silt;
using namespace silt::render;

namespace {

constexpr int64_t kFrameSteps = 100;
constexpr int64_t kEvery = 7;

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST_CASE("frames every 7 steps leave the run bitwise unchanged (3D gas, 2D gas under Lees-Edwards shear)") {
  for (const auto& dim_rate : {std::pair{3, 0.0}, std::pair{2, 0.5}}) {
    const auto [dim, rate] = dim_rate;
    CAPTURE(dim_rate.first);
    const std::string scene = test::frictional_gas(dim, rate, 0.0, 0.06);
    RunOptions opt;
    opt.steps = kFrameSteps;
    auto plain = test::simulation_from(scene);
    REQUIRE(plain->run(opt).end == RunEnd::kDone);
    // The states at the frame steps, seen by a hook that only looks.
    auto looked = test::simulation_from(scene);
    std::vector<uint64_t> seen;
    opt.hooks = {{kEvery, [&](const State& s) { seen.push_back(state_hash(s)); }}};
    REQUIRE(looked->run(opt).end == RunEnd::kDone);
    // With frames, drawn and written by the frame writer while the run goes on.
    auto framed = test::simulation_from(scene);
    View v = framed->model().render;
    v.width = 96;
    v.height = 64;
    v.draw = {"grains", "chains", "colorbar", "time", "scalebar", "box"};
    v.periodic_images = true;
    std::filesystem::remove_all("render_state_frames");
    std::vector<uint64_t> before, after;
    {
      FrameWriter frames("render_state_frames", 1);
      opt.hooks = {{kEvery, [&](const State& s) {
                      before.push_back(state_hash(s));
                      frames.submit(build_render_scene(framed->model(), s, v));
                      after.push_back(state_hash(s));
                    }}};
      REQUIRE(framed->run(opt).end == RunEnd::kDone);
      frames.finish();
      CHECK(frames.error().empty());
      CHECK(frames.written() == kFrameSteps / kEvery + 1);
    }
    CHECK(seen.size() == static_cast<size_t>(kFrameSteps / kEvery + 1));
    CHECK(before == seen);
    CHECK(after == seen);
    CHECK(state_hash(looked->state()) == state_hash(plain->state()));
    CHECK(state_hash(framed->state()) == state_hash(plain->state()));
    std::filesystem::remove_all("render_state_frames");
  }
}

TEST_CASE("silt run with and without --frames saves the same state, byte for byte") {
  // The same scene text in both (a checkpoint keeps it): only --frames differs.
  const std::string base = test::silt_binary() + " run " + test::scene_path("pack_2d") +
                           " --quiet --steps 301 --set render.width=160 --set render.height=90"
                           " --set 'render.draw=[\"grains\",\"chains\",\"colorbar\",\"time\",\"box\"]'";
  std::filesystem::remove_all("render_state_cli");
  CHECK(std::system((base + " --save render_state_plain.ckpt > /dev/null 2>&1").c_str()) == 0);
  const int framed = std::system(
      (base + " --frames render_state_cli --frame-every 7 --save render_state_framed.ckpt > /dev/null 2>&1").c_str());
  CHECK(WIFEXITED(framed));
  CHECK(WEXITSTATUS(framed) == 0);
  CHECK(std::filesystem::exists("render_state_cli/frame_000043.png"));  // steps 0, 7, ..., 301
  const std::string a = bytes_of("render_state_plain.ckpt"), b = bytes_of("render_state_framed.ckpt");
  CHECK(a.size() > 1000);
  CHECK(a == b);
  std::filesystem::remove_all("render_state_cli");
  std::filesystem::remove("render_state_plain.ckpt");
  std::filesystem::remove("render_state_framed.ckpt");
}

// libFuzzer target for scene files: the input is a scene's text, read and compiled as `silt check`
// does (compile, describe, the neighbour lists and forces of the first state). A SceneError, an
// IoError (a frozen_from checkpoint that cannot be read) or std::invalid_argument is silt
// reporting a bad scene; any other exception, a crash, a sanitizer report, a timeout or an
// allocation beyond libFuzzer's limits is a bug. Seeds: scenes/*.toml, tests/fuzz/seeds/*.toml.
#include <cstdint>
#include <string>
#include <typeinfo>
#include <vector>

#include "fuzz_support.hpp"
#include "silt/io.hpp"
#include "silt/simulation.hpp"

namespace {

// Checkpoints a scene's frozen_from may name, in the scratch directory: a 3D base (the chute's,
// 4 x 4 grains a layer) and a 2D packing.
void write_bases() {
  using silt::Override;
  const auto base = [](const std::string& scene, const std::vector<Override>& sets, const std::string& out) {
    const silt::Model m = silt::compile(silt::load_scene_file(silt::fuzz::source_path(scene), sets));
    silt::write_checkpoint(out, m, silt::make_state(m));
  };
  base("scenes/chute.toml",
       {{"domain.hi", "[4.0, 4.0, 30.0]"},
        {"grains[0].region_hi", "[4.0, 4.0, 0.25]"},
        {"grains[1].region_hi", "[4.0, 4.0, 3.25]"}},
       "base3d.ckpt");
  base("scenes/pack_2d.toml", {}, "base2d.ckpt");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  silt::fuzz::enter_scratch_dir(argc, argv);
  // Some hundreds of grains: larger scenes (the chute's 17,600, the silo's 1,600) are refused at
  // their count, so that an input takes milliseconds; seeds.sh adds small versions of them.
  silt::fuzz::set_available_memory(1 << 20);
  write_bases();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace silt;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    Model m = compile(parse_scene(text, "fuzz.toml"));
    (void)describe(m);
    Simulation sim(std::move(m), 1);
    sim.prepare();
    (void)sim.describe_graph();
    (void)estimated_memory_bytes(sim.model());
  } catch (const SceneError&) {
  } catch (const IoError&) {
  } catch (const std::invalid_argument&) {
  } catch (const std::exception& e) {
    fuzz::bug(std::string("a scene threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}

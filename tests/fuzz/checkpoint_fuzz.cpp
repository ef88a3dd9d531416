// libFuzzer target for checkpoint files (read_checkpoint): the input is a file's bytes, read
// against the model of the scene it was written for (found by the fingerprint in its header; any
// other fingerprint is read against one of the models, which refuses it). A bad file must throw
// IoError; one that passes the reader's checks must be a state a simulation of the model can
// step. Seeds: fuzz_seeds writes checkpoints of checkpoint_scenes(). The custom mutator keeps the
// checksum valid (checkpoint_mutator.hpp).
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <typeinfo>
#include <vector>

#include "checkpoint_mutator.hpp"
#include "checkpoint_scenes.hpp"
#include "fuzz_support.hpp"
#include "silt/io.hpp"
#include "silt/simulation.hpp"

namespace {

std::vector<silt::Model>* g_models = nullptr;

const silt::Model& model_for(const uint8_t* data, size_t size) {
  uint64_t fingerprint = 0;
  if (size >= 20) std::memcpy(&fingerprint, data + 12, 8);  // after the magic and the version
  for (const silt::Model& m : *g_models)
    if (m.scene_hash == fingerprint) return m;
  return (*g_models)[fingerprint % g_models->size()];
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  silt::fuzz::enter_scratch_dir(argc, argv);
  g_models = new std::vector<silt::Model>;
  for (const auto& s : silt::fuzz::checkpoint_scenes()) g_models->push_back(silt::fuzz::compile_scene(s));
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
  return silt::fuzz::mutate_checkpoint(data, size, max_size, seed);
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace silt;
  const Model& m = model_for(data, size);
  const char* path = "input.ckpt";
  std::FILE* f = std::fopen(path, "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) fuzz::bug("cannot write input.ckpt");
  State s;
  try {
    std::vector<std::string> differences;
    s = read_checkpoint(path, m, &differences);
  } catch (const IoError&) {
    return 0;  // refused, as a bad file must be
  } catch (const std::exception& e) {
    fuzz::bug(std::string("read_checkpoint threw ") + typeid(e).name() + ": " + e.what());
  }
  // Accepted: a simulation of the model continues from it (a numerical failure is a fine end).
  try {
    Simulation sim(m, 1);
    sim.restore(std::move(s));
    for (int k = 0; k < 3 && sim.step(); ++k) {
    }
    if (sim.state().failure.internal) fuzz::bug("a restored checkpoint fails a step: " + sim.state().failure.message);
  } catch (const std::exception& e) {
    fuzz::bug(std::string("stepping a restored checkpoint threw ") + typeid(e).name() + ": " + e.what());
  }
  return 0;
}

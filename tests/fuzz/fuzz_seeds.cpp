// Seeds of the fuzz targets that cannot be shipped as text: checkpoints of checkpoint_scenes()
// after a few steps, and dictionaries of the words the scene language and the shell know.
// Usage: fuzz_seeds DIR   (writes DIR/checkpoint/*.ckpt, DIR/scene.dict, DIR/session.dict)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "checkpoint_scenes.hpp"
#include "shell/command_parser.hpp"
#include "silt/io.hpp"
#include "silt/observables.hpp"
#include "silt/simulation.hpp"

namespace {

void write_dict(const std::string& path, const std::set<std::string>& words) {
  std::ofstream out(path);
  for (const std::string& w : words) {
    std::string q;
    for (const char c : w) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(c));
      q += c == '"' || c == '\\' || c < ' ' ? std::string(hex) : std::string(1, c);
    }
    out << '"' << q << "\"\n";
  }
}

// Every word of the scene language: table and key names, choices, and TOML's own.
std::set<std::string> scene_words() {
  std::set<std::string> words = {"true", "false", " = ",   "[",      "]",   "[[",        "]]",         "\"",
                                 "#",    "\n",    "1e308", "-0.0",   "nan", "inf",       "[[grains]]", "[[walls]]",
                                 "{",    "}",     "'",     "\"\"\"", "0x",  "1979-05-27"};
  for (const silt::KeySpec& k : silt::scene_schema()) {
    std::string path = k.path;
    for (size_t at; (at = path.find("[]")) != std::string::npos;) path.erase(at, 2);
    std::istringstream parts(path);
    std::string part, table;
    while (std::getline(parts, part, '.')) {
      words.insert(part);
      if (!table.empty()) words.insert("[" + table + "]");
      table = table.empty() ? part : table + "." + part;
    }
    words.insert(path);
    for (const std::string& c : k.choices) words.insert("\"" + c + "\"");
  }
  return words;
}

// Every word of the shell: commands, keys, observables, and the files of its scratch directory.
std::set<std::string> session_words(const std::vector<silt::Model>& models) {
  std::set<std::string> words = {"every",
                                 "until",
                                 "and",
                                 "or",
                                 "off",
                                 "<",
                                 ">",
                                 ">=",
                                 "<=",
                                 "==",
                                 "!=",
                                 "s",
                                 "1e3",
                                 "0.5s",
                                 "\"",
                                 "#",
                                 "\n",
                                 "pack_2d.toml",
                                 "bounce_dry.toml",
                                 "collision_normal.toml",
                                 "tiny.silt",
                                 "loop.silt",
                                 "a.ckpt",
                                 "a.png",
                                 "frames"};
  for (const auto& c : silt::shell::command_specs()) words.insert(c.name);
  for (const silt::KeySpec& k : silt::scene_schema()) words.insert(k.path);
  for (const silt::Model& m : models)
    for (const std::string& o : silt::observable_names(m)) words.insert(o);
  for (const silt::FieldInfo& f : silt::field_infos()) words.insert(f.name);
  return words;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds DIR\n");
    return 1;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir / "checkpoint");
  std::vector<silt::Model> models;
  for (const auto& s : silt::fuzz::checkpoint_scenes()) {
    silt::Simulation sim(silt::fuzz::compile_scene(s), 1);
    if (sim.model().prepare.compress) {  // procedure O first, as silt run does (a paste needs touching grains)
      silt::PreparationReport prep;
      silt::State packed = silt::prepare_packing(sim.model(), 1, &prep);
      if (prep.end == silt::RunEnd::kFailed) {
        std::fprintf(stderr, "fuzz_seeds: %s: the preparation failed: %s\n", s.name.c_str(), prep.failure.c_str());
        return 1;
      }
      sim.restore(std::move(packed));
    }
    sim.prepare();
    for (const int64_t steps : s.steps) {
      while (sim.state().step < steps)
        if (!sim.step()) {
          std::fprintf(stderr, "fuzz_seeds: %s failed: %s\n", s.name.c_str(), sim.state().failure.message.c_str());
          return 1;
        }
      const std::string name = s.name + "_" + std::to_string(steps) + ".ckpt";
      silt::write_checkpoint((dir / "checkpoint" / name).string(), sim.model(), sim.state());
    }
    models.push_back(sim.model());
  }
  write_dict((dir / "scene.dict").string(), scene_words());
  write_dict((dir / "session.dict").string(), session_words(models));
  return 0;
}

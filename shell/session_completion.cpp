// Tab completion for the shell: what the word being typed can be, by what the command expects.
#include "shell/session.hpp"

namespace silt::shell {

std::optional<std::vector<std::string>> Session::complete(const std::string& before, const std::string& word) const {
  std::vector<std::string> pool;
  std::optional<Command> c;
  try {
    c = parse_line(before);
  } catch (const ParseError&) {
    return pool;
  }
  if (!c) {
    for (const CommandSpec& s : command_specs()) pool.push_back(s.name);
  } else {
    const CommandSpec* s = find_command(c->name);
    if (!s) return pool;
    switch (s->completes) {
      case ArgKind::kKey:
        // "grains[0].radius": the keys, with the loaded scene's tables (set's later pairs too)
        if (!(c->args.empty() || (c->name == "set" && c->args.size() % 2 == 0))) break;
        for (const auto& [key, value] : scene_parameters(sim_ ? sim_->model().desc : kNoScene)) pool.push_back(key);
        break;
      case ArgKind::kObservable:
        if (sim_) pool = observable_names(sim_->model());
        for (const char* w : {"until", "every", "off", "and", "or"}) pool.push_back(w);
        break;
      case ArgKind::kCommand:
        for (const CommandSpec& x : command_specs()) pool.push_back(x.name);
        break;
      case ArgKind::kFile:
        if (c->args.empty()) return std::nullopt;  // the file: the line editor completes its name
        if (c->name == "render") pool = find_key_spec("render.draw")->choices;
        if (c->name == "frames" && c->args.size() == 1) pool = {"every"};
        break;
      default: break;  // nothing to offer (and no file names: the command takes none)
    }
  }
  std::vector<std::string> out;
  for (const std::string& p : pool)
    if (p.rfind(word, 0) == 0) out.push_back(p);
  return out;
}

}  // namespace silt::shell

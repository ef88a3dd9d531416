// The list of modules: each with its spec (keys, observables, fields, events, compile) and the
// adder that puts its stages into a step. Adding a module adds its files and one line here.
#include <stdexcept>

#include "dem/module.hpp"
#include "graph/adders.hpp"
#include "scene/core_module.hpp"
#include "shear/module.hpp"
#include "silt/module.hpp"

namespace silt {
namespace {

std::vector<Module>& list() {
  static std::vector<Module> l = {
      {&scene::core_module(), graph::add_core_stages},
      {&dem::module(), graph::add_dem_stages},
      {&shear::module(), graph::add_shear_stages},
      {&scene::render_module(), nullptr},
  };
  return l;
}

}  // namespace

const std::vector<Module>& modules() { return list(); }

const Module* find_module(std::string_view name) {
  for (const Module& m : list())
    if (m.spec->name == name) return &m;
  return nullptr;
}

void register_module(const ModuleSpec* spec, StageAdder add_stages) {
  if (find_module(spec->name)) throw std::logic_error("module " + spec->name + " is already registered");
  for (const ModuleField& f : spec->fields) register_module_field(f.name, spec->name, f.extent, f.unit, f.doc);
  for (const std::string& e : spec->events) register_module_event(e);
  list().push_back({spec, std::move(add_stages)});
}

}  // namespace silt

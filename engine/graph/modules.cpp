// The list of modules: each with its spec (keys, observables, fields, events, compile steps) and
// the adder that puts its stages into a step. Adding a module adds its files and one line to
// SILT_MODULES: (namespace of its spec, function returning it, its adder in silt::graph).
#include <stdexcept>

#include "graph/graph_builder.hpp"
#include "silt/module.hpp"

// clang-format off
#define SILT_MODULES(X)                                 \
  X(scene, core_module,   add_core_stages)              \
  X(dem,   module,        add_dem_stages)               \
  X(shear, module,        add_shear_stages)             \
  X(drag,  module,        add_drag_stages)              \
  X(paste, module,        add_paste_stages)             \
  X(fluid, module,        add_fluid_stages)             \
  X(scene, render_module, add_no_stages)
// clang-format on

#define SILT_DECLARE_MODULE(ns, spec, adder) \
  namespace silt::ns {                       \
  const ModuleSpec& spec();                  \
  }                                          \
  namespace silt::graph {                    \
  void adder(GraphBuilder& b);               \
  }
SILT_MODULES(SILT_DECLARE_MODULE)
#undef SILT_DECLARE_MODULE

namespace silt {

namespace graph {
// A module with keys but no stages (the render settings).
void add_no_stages(GraphBuilder&) {}
}  // namespace graph

namespace {

void register_parts(const ModuleSpec& spec) {
  for (const ModuleField& f : spec.fields) register_module_field(f.name, spec.name, f.extent, f.unit, f.doc);
  for (const std::string& e : spec.events) register_module_event(e);
}

std::vector<Module>& list() {
  static std::vector<Module> l = [] {
    std::vector<Module> out = {
#define SILT_LIST_MODULE(ns, spec, adder) {&ns::spec(), graph::adder},
        SILT_MODULES(SILT_LIST_MODULE)
#undef SILT_LIST_MODULE
    };
    for (const Module& m : out) register_parts(*m.spec);
    return out;
  }();
  return l;
}

}  // namespace

const std::vector<Module>& modules() { return list(); }

const Module* find_module(std::string_view name) {
  for (const Module& m : list())
    if (m.spec->name == name) return &m;
  return nullptr;
}

std::vector<GridField> module_grid_fields(const Model& m, const State& s, std::string_view only) {
  std::vector<GridField> out;
  for (const Module& mod : list())
    if (mod.spec->grid_fields && m.module_on(mod.spec->name))
      for (GridField& f : mod.spec->grid_fields(m, s, only)) out.push_back(std::move(f));
  return out;
}

std::vector<LineSample> module_lines(const Model& m, const State& s) {
  std::vector<LineSample> out;
  for (const Module& mod : list())
    if (mod.spec->lines && m.module_on(mod.spec->name))
      for (LineSample& l : mod.spec->lines(m, s)) out.push_back(std::move(l));
  return out;
}

bool carry_running(Model& fresh, const Model& m) {
  if (fresh.scene_hash == m.scene_hash) return true;
  Model carried = fresh;
  for (const Module& mod : list())
    if (mod.spec->carry && m.module_on(mod.spec->name)) mod.spec->carry(carried, m);
  if (carried.scene_hash != m.scene_hash) return false;
  fresh = std::move(carried);
  return true;
}

std::string inert_key_note(const Model& m, const std::string& key) {
  for (const Module& mod : list())
    if (mod.spec->inert && m.module_on(mod.spec->name))
      if (std::string note = mod.spec->inert(m, key); !note.empty()) return note;
  return "";
}

bool has_steady_test(const Model& m) {
  for (const Module& mod : list())
    if (mod.spec->steady && m.module_on(mod.spec->name)) return true;
  return false;
}

void register_module(const ModuleSpec* spec, StageAdder add_stages) {
  if (find_module(spec->name)) throw std::logic_error("module " + spec->name + " is already registered");
  register_parts(*spec);
  list().push_back({spec, std::move(add_stages)});
}

}  // namespace silt

#include "graph/graph_builder.hpp"

#include <algorithm>
#include <stdexcept>

#include "silt/module.hpp"
#include "silt/text.hpp"

namespace silt::graph {

GraphBuilder::GraphBuilder(const Model& m, Workspaces& ws, Phase phase)
    : model_(&m),
      ws_(&ws),
      phase_(phase),
      forces_(std::make_shared<ForceSources>()),
      diagnoses_(std::make_shared<std::vector<Diagnosis>>()) {}

GraphBuilder::GraphBuilder(const GraphBuilder& parent, bool)
    : model_(parent.model_),
      ws_(parent.ws_),
      phase_(parent.phase_),
      module_(parent.module_),
      forces_(parent.forces_),
      diagnoses_(parent.diagnoses_) {}

int GraphBuilder::add(std::string name, StageFn fn, Access reads, Access writes) {
  Stage st;
  st.name = std::move(name);
  st.module = module_;
  st.fn = std::move(fn);
  st.reads = std::move(reads);
  st.writes = std::move(writes);
  stages_.push_back(std::move(st));
  return static_cast<int>(stages_.size()) - 1;
}

void GraphBuilder::after(int stage, int on, std::string why) {
  const int n = static_cast<int>(stages_.size());
  if (stage < 0 || on < 0 || stage >= n || on >= n || stage == on)
    throw std::logic_error("step graph: a dependency between stages that do not exist (" + why + ")");
  stages_[stage].deps.push_back(on);
  stages_[stage].why.push_back(std::move(why));
}

int GraphBuilder::add_last(std::string name, StageFn fn, Access reads, Access writes) {
  std::vector<bool> has_successor(stages_.size(), false);
  for (const Stage& st : stages_)
    for (int d : st.deps) has_successor[d] = true;
  const int k = add(std::move(name), std::move(fn), std::move(reads), std::move(writes));
  for (int j = 0; j < k; ++j)
    if (!has_successor[j]) after(k, j, "comes after every stage: " + stages_[j].name + " is done");
  return k;
}

int GraphBuilder::find(std::string_view name) const {
  for (size_t k = 0; k < stages_.size(); ++k)
    if (stages_[k].name == name) return static_cast<int>(k);
  return -1;
}

int GraphBuilder::loop(std::string name, int times, const std::function<void(GraphBuilder&)>& body) {
  GraphBuilder sub(*this, true);
  body(sub);
  auto list = std::make_shared<StageList>(sub.take());
  Access reads, writes;
  for (const Stage& st : list->stages) {
    reads = join(std::move(reads), st.reads);
    writes = join(std::move(writes), st.writes);
  }
  const int k = add(std::move(name), nullptr, std::move(reads), std::move(writes));
  stages_[k].body = std::move(list);
  stages_[k].times = times;
  return k;
}

void GraphBuilder::add_force(ForceSource source, int writer) {
  for (const Module& mod : modules())
    if (mod.spec->name == module_ && !mod.spec->force_parameters)
      throw std::logic_error("step graph: module " + module_ + " adds a force on the grains (" +
                             stages_.at(writer).name + ") but names no parameters it depends on (force_parameters)");
  forces_->push_back(source);
  force_writers_.emplace_back(source, writer);
  for (int s : summers_) reads_force(s, source, writer);
  for (int s : last_summers_) reads_force(s, source, -1);
}

void GraphBuilder::sums_forces(int stage) {
  summers_.push_back(stage);
  for (const auto& [source, writer] : force_writers_) reads_force(stage, source, writer);
}

void GraphBuilder::sums_last_forces(int stage) {
  last_summers_.push_back(stage);
  for (const auto& [source, writer] : force_writers_) reads_force(stage, source, -1);
}

void GraphBuilder::reads_force(int summer, const ForceSource& source, int writer) {
  Stage& st = stages_.at(summer);
  st.reads = join(std::move(st.reads), {source.force});
  if (source.torque != kNoField) st.reads = join(std::move(st.reads), {source.torque});
  if (writer >= 0) after(summer, writer, "adds the force of " + stages_.at(writer).name);
}

StageList GraphBuilder::take() {
  // Topological order, stable: among the stages whose dependencies are done, the one added
  // first (a module's adder may make an earlier module's stage wait for one of its own).
  const size_t n = stages_.size();
  std::vector<int> order, new_index(n, -1);
  std::vector<bool> done(n, false);
  while (order.size() < n) {
    bool progress = false;
    for (size_t k = 0; k < n; ++k) {
      if (done[k]) continue;
      bool ready = true;
      for (int d : stages_[k].deps) ready = ready && done[d];
      if (!ready) continue;
      done[k] = true;
      new_index[k] = static_cast<int>(order.size());
      order.push_back(static_cast<int>(k));
      progress = true;
      break;
    }
    if (!progress) throw std::logic_error("step graph: the dependencies of its stages form a cycle");
  }
  std::vector<Stage> sorted;
  for (int k : order) {
    Stage st = std::move(stages_[k]);
    for (int& d : st.deps) d = new_index[d];
    sorted.push_back(std::move(st));
  }
  stages_.clear();
  if (const std::string err = check_access(sorted); !err.empty()) throw std::logic_error("step graph: " + err);
  return StageList{std::move(sorted)};
}

Access join(Access a, const Access& b) {
  for (FieldId f : b)
    if (std::find(a.begin(), a.end(), f) == a.end()) a.push_back(f);
  return a;
}

Access grain_fields() {
  Access out;
  for (const FieldInfo& f : field_infos())
    if (follows_grains(f.extent)) out.push_back(f.id);
  return out;
}

std::string check_access(const std::vector<Stage>& stages) {
  const size_t n = stages.size();
  // before[a][b]: a finishes before b starts (transitive closure of the dependencies, which point
  // to earlier stages).
  std::vector<std::vector<bool>> before(n, std::vector<bool>(n, false));
  for (size_t b = 0; b < n; ++b)
    for (int d : stages[b].deps) {
      before[d][b] = true;
      for (size_t a = 0; a < n; ++a)
        if (before[a][d]) before[a][b] = true;
    }
  auto touches = [](const Access& writes, const Stage& other) -> int {
    for (FieldId w : writes) {
      if (std::find(other.reads.begin(), other.reads.end(), w) != other.reads.end()) return w;
      if (std::find(other.writes.begin(), other.writes.end(), w) != other.writes.end()) return w;
    }
    return -1;
  };
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      if (before[a][b] || before[b][a]) continue;
      int what = touches(stages[a].writes, stages[b]);
      if (what < 0) what = touches(stages[b].writes, stages[a]);
      if (what >= 0)
        return stages[a].name + " and " + stages[b].name + " may run at the same time and both use " +
               field_info(static_cast<FieldId>(what)).name + ", one of them writing it";
    }
  for (const Stage& st : stages)
    if (st.is_loop())
      if (std::string err = check_access(st.body->stages); !err.empty()) return "in " + st.name + ": " + err;
  return "";
}

StageList build_stage_list(const Model& m, Workspaces& ws, Phase phase, std::vector<Diagnosis>* diagnoses) {
  GraphBuilder b(m, ws, phase);
  for (const Module& mod : modules()) {
    if (!mod.add_stages || !m.module_on(mod.spec->name)) continue;
    const bool forces = mod.spec->force_parameters || mod.spec->follows_forces;
    if (phase == Phase::kResolve && !mod.spec->stale && !forces) continue;
    if (phase == Phase::kRefresh && !forces) continue;
    b.set_module(mod.spec->name);
    mod.add_stages(b);
  }
  // The clock ends the step: after every other stage, it advances t by the step's dt.
  if (phase == Phase::kStep) {
    b.set_module("core");
    const int clock = b.add_last("advance_clock",
                                 [](const Model&, State& s) {
                                   // (dt, t, step) => (t, step, events.clock_stalled)
                                   if (s.dt > 0 && s.t + s.dt == s.t) s.events[event::kClockStalled].raise(0, s.dt);
                                   s.t += s.dt;
                                   ++s.step;
                                 },
                                 {fid::dt, fid::t, fid::step}, {fid::t, fid::step});
    b.light(clock);
    b.diagnose(event::kClockStalled, [](const Model& mm, const State& s, const EventSlot& e, StepFailure& f) {
      f.stage = "advance_clock";
      f.parameter = mm.dt_key;
      f.message = "the time step " + format_number(e.value(), 4) +
                  " s is lost in the rounding of the time t = " + format_number(s.t, 6) +
                  " s: the clock no longer advances; the step is set by " + mm.dt_key +
                  " and the scene's time scales (a viscosity, a velocity or a stiffness many orders of magnitude " +
                  "from the others)";
    });
  }
  StageList list = b.take();
  if (diagnoses) *diagnoses = b.take_diagnoses();
  return list;
}

}  // namespace silt::graph

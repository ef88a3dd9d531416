// All wiring of a step lives here. Each edge says why it exists. A scene without walls has no
// wall node; a fixed box has no box node.
//
//   kick_drift -> update_neighbors -> contact_forces --> gather_kick -> box_kick
//        \-----------------------> wall_forces ---/
#include "graph/step_graph.hpp"

#include <chrono>
#include <sstream>

#include "dem/stages.hpp"

namespace silt::graph {

std::vector<Stage> build_stages(const Model& m) {
  std::vector<Stage> st;
  auto add = [&](const char* name, StageFn fn) {
    st.push_back(Stage{name, fn, {}, {}});
    return static_cast<int>(st.size()) - 1;
  };
  auto dep = [&](int stage, int on, const char* why) {
    st[stage].deps.push_back(on);
    st[stage].why.push_back(why);
  };
  const int kick = add("kick_drift", &dem::kick_drift);
  const int nbr = add("update_neighbors", &dem::update_neighbors);
  // depends on: the displacement since the last build, known after the drift.
  dep(nbr, kick, "rebuild decision needs the drifted positions");
  const int pairs = add("contact_forces", &dem::contact_forces);
  dep(pairs, nbr, "iterates the (possibly rebuilt) pair list");
  int walls = -1;
  if (!m.walls.empty()) {
    walls = add("wall_forces", &dem::wall_forces);
    // Independent of the pair list: runs concurrently with update_neighbors and contact_forces.
    dep(walls, kick, "needs the drifted positions and half-kicked velocities");
  }
  const int gather = add("gather_kick", &dem::gather_kick);
  dep(gather, pairs, "sums the pair forces of this step");
  if (walls >= 0) dep(gather, walls, "adds the wall forces of this step");
  if (m.box_control.on) {
    const int box = add("box_kick", &dem::box_kick);
    dep(box, gather, "kinetic stress uses the full-step velocities; contact stress the new pair forces");
  }
  return st;
}

StepGraph::StepGraph(const Model& m) : stages_(build_stages(m)) {
  using namespace tbb::flow;
  graph_ = std::make_unique<tbb::flow::graph>();
  start_ = std::make_unique<broadcast_node<continue_msg>>(*graph_);
  for (size_t k = 0; k < stages_.size(); ++k)
    nodes_.push_back(std::make_unique<continue_node<continue_msg>>(
        *graph_, [this, k](const continue_msg&) { run_stage(k); }));
  for (size_t k = 0; k < stages_.size(); ++k) {
    if (stages_[k].deps.empty()) make_edge(*start_, *nodes_[k]);
    for (int d : stages_[k].deps) make_edge(*nodes_[d], *nodes_[k]);
  }
  timers_.resize(stages_.size(), nullptr);
}

void StepGraph::bind(const Model& m, State& s) {
  model_ = &m;
  state_ = &s;
  // Insert the profile entries before any stage runs, so that concurrent stages only look up.
  for (size_t k = 0; k < stages_.size(); ++k) timers_[k] = &s.profile[stages_[k].name];
}

void StepGraph::run_stage(size_t k) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    stages_[k].fn(*model_, *state_);
  } catch (const std::exception& e) {
    // No exception may escape a task: record it as a failure of this step.
    state_->alarm_nonfinite.raise(0, 0);
    state_->failure.stage = stages_[k].name;
    state_->failure.message = std::string("internal error in stage ") + stages_[k].name + ": " + e.what();
  }
  const auto t1 = std::chrono::steady_clock::now();
  timers_[k]->seconds += std::chrono::duration<double>(t1 - t0).count();
  ++timers_[k]->calls;
}

void StepGraph::run_serial(const Model& m, State& s) {
  bind(m, s);
  for (size_t k = 0; k < stages_.size(); ++k) run_stage(k);
}

void StepGraph::run_flow(const Model& m, State& s) {
  bind(m, s);
  start_->try_put(tbb::flow::continue_msg());
  graph_->wait_for_all();
}

std::string StepGraph::describe() const {
  std::ostringstream o;
  for (const Stage& st : stages_) {
    o << "  " << st.name << "\n";
    for (size_t d = 0; d < st.deps.size(); ++d)
      o << "    after " << stages_[st.deps[d]].name << ": " << st.why[d] << "\n";
  }
  return o.str();
}

}  // namespace silt::graph

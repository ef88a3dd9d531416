// All wiring of a step lives here. Each edge says why it exists. A scene without walls has no
// wall node; a fixed box has no box node.
//
//   kick_drift -> update_neighbors -> contact_forces --> kick -> box_kick
//                           \------> wall_forces ---/
//
// Every stage declares what it reads and writes; build_stages() refuses a graph in which two
// stages that may run concurrently touch the same data with one of them writing it.
#include "graph/step_graph.hpp"

#include <chrono>
#include <sstream>

#include "dem/stages.hpp"
#include "shear/stages.hpp"

namespace silt::graph {

std::vector<Stage> build_stages(const Model& m) {
  using Names = std::vector<std::string>;
  std::vector<Stage> st;
  auto add = [&](const char* name, StageFn fn, Names reads, Names writes) {
    st.push_back(Stage{name, fn, {}, {}, std::move(reads), std::move(writes)});
    return static_cast<int>(st.size()) - 1;
  };
  auto dep = [&](int stage, int on, const char* why) {
    st[stage].deps.push_back(on);
    st[stage].why.push_back(why);
  };
  const Names grain = {"grain_order", "particle_r", "particle_inv_m", "particle_inv_i", "particle_frozen"};
  auto with = [](Names a, const Names& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  const int kick = add("kick_drift", &dem::kick_drift,
                       with(grain, {"particle_f", "particle_t", "box_stress", "shear_stress"}),
                       {"particle_v", "particle_w", "particle_x", "particle_disp", "box", "shear_rate", "nbr_max_disp", "nbr_step_disp",
                        "nbr_strain"});
  const int nbr = add("update_neighbors", &dem::update_neighbors, with(grain, {"particle_x", "nbr_max_disp", "nbr_step_disp", "box"}),
                      {"grain_order", "nbr_start", "pair_i", "pair_j", "pair_hist", "particle_disp",
                       "nbr_strain", "pair_f", "pair_touch"});
  // depends on: the displacement since the last build, known after the drift.
  dep(nbr, kick, "rebuild decision needs the drifted positions");
  const int pairs = add("contact_forces", &dem::contact_forces,
                        with(grain, {"particle_x", "particle_v", "particle_w", "nbr_start", "pair_i", "pair_j", "box"}),
                        {"pair_f", "pair_hist", "pair_touch", "particle_f", "particle_t"});
  dep(pairs, nbr, "iterates the (possibly rebuilt) pair list");
  int walls = -1;
  if (!m.walls.empty()) {
    walls = add("wall_forces", &dem::wall_forces, with(grain, {"particle_x", "particle_v", "particle_w"}),
                {"wall_f", "wall_hist", "particle_t_wall"});
    // Runs concurrently with contact_forces; not with update_neighbors, which may renumber grains.
    dep(walls, nbr, "a rebuild may renumber the grains (cell order)");
  }
  const int second_kick = add("kick", &dem::kick, with(grain, {"wall_f", "particle_t_wall"}),
                              {"particle_f", "particle_t", "particle_v", "particle_w"});
  dep(second_kick, pairs, "kicks with the pair forces of this step");
  if (walls >= 0) dep(second_kick, walls, "adds the wall forces of this step");
  if (shear::box_stage_on(m)) {
    const int box = add("box_kick", &shear::box_kick,
                        with(grain, {"pair_f", "particle_v", "particle_x", "nbr_start", "pair_j", "box"}),
                        {"box_stress", "box_rate", "shear_stress", "shear_rate"});
    dep(box, second_kick, "kinetic stress uses the full-step velocities; contact stress the new pair forces");
  }
  if (const std::string err = check_access(st); !err.empty()) throw std::logic_error("step graph: " + err);
  return st;
}

std::string check_access(const std::vector<Stage>& stages) {
  const size_t n = stages.size();
  // before[a][b]: a finishes before b starts (transitive closure of the dependencies).
  std::vector<std::vector<bool>> before(n, std::vector<bool>(n, false));
  for (size_t b = 0; b < n; ++b)
    for (int d : stages[b].deps) {
      before[d][b] = true;
      for (size_t a = 0; a < n; ++a)
        if (before[a][d]) before[a][b] = true;
    }
  auto touches = [](const std::vector<std::string>& writes, const Stage& other) -> std::string {
    for (const std::string& w : writes) {
      for (const std::string& r : other.reads)
        if (r == w) return w;
      for (const std::string& x : other.writes)
        if (x == w) return w;
    }
    return "";
  };
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b) {
      if (before[a][b] || before[b][a]) continue;
      std::string what = touches(stages[a].writes, stages[b]);
      if (what.empty()) what = touches(stages[b].writes, stages[a]);
      if (!what.empty())
        return stages[a].name + " and " + stages[b].name + " may run at the same time and both use " + what +
               ", one of them writing it";
    }
  return "";
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

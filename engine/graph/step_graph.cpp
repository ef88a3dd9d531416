// The serial and flow-graph executors of a stage list, loop nodes included, and the step's
// diagnosis. The stages and why each depends on another are in the modules' adders
// (graph/*_stages.cpp); this file only runs them.
#include "graph/step_graph.hpp"

#include <cstdlib>
#include <sstream>
#include <string_view>

#include "graph/access_check.hpp"
#include "silt/text.hpp"

namespace silt::graph {

// One stage list and its flow graph; a loop node's body has its own Runner.
struct StepGraph::Runner {
  explicit Runner(StageList l) : list(std::move(l)) {
    using namespace tbb::flow;
    const size_t n = list.stages.size();
    bodies.resize(n);
    checks.resize(n, 0);
    for (size_t k = 0; k < n; ++k)
      if (list.stages[k].is_loop()) bodies[k] = std::make_unique<Runner>(*list.stages[k].body);
    // Light stages that only light stages precede run before the graph (choose_dt), those that
    // only light stages follow after it (energy_check, advance_clock); the others are its nodes.
    role.assign(n, kNode);
    for (size_t k = 0; k < n; ++k) {
      bool head = list.stages[k].light;
      for (int d : list.stages[k].deps) head = head && role[d] == kHead;
      if (head) role[k] = kHead;
    }
    std::vector<std::vector<int>> dependents(n);
    for (size_t k = 0; k < n; ++k)
      for (int d : list.stages[k].deps) dependents[d].push_back(static_cast<int>(k));
    for (size_t k = n; k-- > 0;) {
      if (!list.stages[k].light || role[k] == kHead) continue;
      bool tail = true;
      for (int c : dependents[k]) tail = tail && role[c] == kTail;
      if (tail) role[k] = kTail;
    }
    graph = std::make_unique<tbb::flow::graph>();
    start = std::make_unique<broadcast_node<continue_msg>>(*graph);
    nodes.resize(n);
    for (size_t k = 0; k < n; ++k)
      if (role[k] == kNode)
        nodes[k] = std::make_unique<continue_node<continue_msg>>(
            *graph, [this, k](const continue_msg&) { run_stage(k, false); });
    for (size_t k = 0; k < n; ++k) {
      if (role[k] != kNode) continue;
      bool from_start = true;
      for (int d : list.stages[k].deps)
        if (role[d] == kNode) {
          make_edge(*nodes[d], *nodes[k]);
          from_start = false;
        }
      if (from_start) make_edge(*start, *nodes[k]);
      has_nodes = true;
    }
    timers.resize(n, nullptr);
  }

  void bind(const Model& m, State& s) {
    model = &m;
    state = &s;
    // Insert the profile entries before any stage runs, so that concurrent stages only look up;
    // again only for another profile (the entries of a map stay where they are).
    if (s.profile.id() != profile_id) {
      profile_id = s.profile.id();
      for (size_t k = 0; k < list.stages.size(); ++k) timers[k] = &s.profile[list.stages[k].name];
    }
    for (auto& b : bodies)
      if (b) b->bind(m, s);
  }

  void run_stage(size_t k, bool serial) {
    const Stage& st = list.stages[k];
    const uint64_t t0 = stage_ticks();
    try {
      if (st.is_loop()) {
        for (int i = 0; i < st.times; ++i) serial ? bodies[k]->run_serial() : bodies[k]->run_flow();
      } else if (serial && access_check && sampled(k)) {
        run_checked(st, *model, *state);
      } else {
        st.fn(*model, *state);
      }
    } catch (const std::exception& e) {
      // No exception may escape a task: it is the step's internal error.
      state->internal.raise(st.name, std::string("internal error in stage ") + st.name + ": " + e.what());
    }
    timers[k]->ticks += stage_ticks() - t0;
    ++timers[k]->calls;
  }

  // The access check runs on the first calls of a stage, then on one call in 64.
  bool sampled(size_t k) {
    const int64_t c = checks[k]++;
    return c < 16 || c % 64 == 0;
  }

  void run_serial() {
    for (size_t k = 0; k < list.stages.size(); ++k) run_stage(k, true);
  }

  void run_flow() {
    for (size_t k = 0; k < list.stages.size(); ++k)
      if (role[k] == kHead) run_stage(k, false);
    if (has_nodes) {
      start->try_put(tbb::flow::continue_msg());
      graph->wait_for_all();
    }
    for (size_t k = 0; k < list.stages.size(); ++k)
      if (role[k] == kTail) run_stage(k, false);
  }

  void set_check(bool on) {
    access_check = on;
    for (auto& b : bodies)
      if (b) b->set_check(on);
  }

  void describe(std::ostringstream& o, int depth) const {
    const std::string pad(2 * depth + 2, ' ');
    for (const Stage& st : list.stages) {
      std::string head = st.name + (st.is_loop() ? " x " + std::to_string(st.times) : "");
      o << pad << head << std::string(head.size() + pad.size() < 34 ? 34 - head.size() - pad.size() : 1, ' ') << "["
        << st.module << "]\n";
      for (size_t d = 0; d < st.deps.size(); ++d)
        o << pad << "  after " << list.stages[st.deps[d]].name << ": " << st.why[d] << "\n";
      if (st.is_loop()) {
        const size_t k = static_cast<size_t>(&st - list.stages.data());
        bodies[k]->describe(o, depth + 2);
      }
    }
  }

  StageList list;
  enum Role { kHead, kNode, kTail };
  std::vector<Role> role;
  bool has_nodes = false;
  std::vector<std::unique_ptr<Runner>> bodies;
  std::vector<int64_t> checks;
  std::vector<StageTime*> timers;
  const Model* model = nullptr;
  State* state = nullptr;
  uint64_t profile_id = 0;  // of the profile the timers point into
  bool access_check = false;
  std::unique_ptr<tbb::flow::graph> graph;
  std::unique_ptr<tbb::flow::broadcast_node<tbb::flow::continue_msg>> start;
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes;
};

namespace {

// The sanitizer build's default: the access check on, unless the environment sets
// SILT_ACCESS_CHECK=0 (the test script's short fuzz runs, which look for memory errors: a check
// that long runs may find, bench/fuzz_all.sh, is not theirs to stop on).
[[maybe_unused]] bool access_check_by_default() {
  const char* v = std::getenv("SILT_ACCESS_CHECK");
  return v == nullptr || std::string_view(v) != "0";
}

}  // namespace

StepGraph::StepGraph(const Model& m, Workspaces& ws, Phase phase) {
  StageList list = build_stage_list(m, ws, phase, &diagnoses_);
  root_ = std::make_unique<Runner>(std::move(list));
#ifdef SILT_CHECK_ACCESS
  set_access_check(access_check_by_default());
#endif
}

StepGraph::StepGraph(StageList list, std::vector<Diagnosis> diagnoses)
    : root_(std::make_unique<Runner>(std::move(list))), diagnoses_(std::move(diagnoses)) {
#ifdef SILT_CHECK_ACCESS
  set_access_check(access_check_by_default());
#endif
}

StepGraph::~StepGraph() = default;

void StepGraph::set_access_check(bool on) { root_->set_check(on); }

const std::vector<Stage>& StepGraph::stages() const { return root_->list.stages; }

void StepGraph::run_serial(const Model& m, State& s) {
  root_->bind(m, s);
  root_->run_serial();
}

void StepGraph::run_flow(const Model& m, State& s) {
  root_->bind(m, s);
  root_->run_flow();
}

std::string StepGraph::describe() const {
  std::ostringstream o;
  root_->describe(o, 0);
  return o.str();
}

bool StepGraph::diagnose(const Model& m, State& s, int64_t step) const {
  StepFailure& f = s.failure;
  if (step < 0) step = s.step;
  if (s.internal.raised()) {
    f.failed = true;
    f.internal = true;
    f.step = step;
    f.stage = s.internal.stage();
    f.particle = -1;
    f.parameter.clear();
    f.message = "step " + std::to_string(step) + ": " + s.internal.message();
    return false;
  }
  if (!s.events.any()) return true;
  // The first event by id: the order of the event table is the order of precedence.
  for (EventId e = 0; e < kMaxEvents; ++e) {
    const EventSlot& slot = s.events[e];
    if (!slot.raised()) continue;
    f = StepFailure{};
    f.failed = true;
    f.event = e;
    f.step = step;
    for (const Diagnosis& d : diagnoses_)
      if (d.event == e) d.fn(m, s, slot, f);
    if (f.message.empty())
      f.message = "event " + event_name(e) + " raised " + std::to_string(slot.count()) + " time(s), first at index " +
                  std::to_string(slot.first()) + " (value " + format_number(slot.value()) + ")";
    f.message = "step " + std::to_string(f.step) + (f.stage.empty() ? "" : ", stage " + f.stage) + ": " + f.message;
    return false;
  }
  return true;
}

}  // namespace silt::graph

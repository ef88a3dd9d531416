// The step as a graph of named stages, built once per Model from the modules it enables.
#pragma once

#include <tbb/flow_graph.h>

#include <memory>
#include <string>
#include <vector>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt::graph {

using StageFn = void (*)(const Model&, State&);

struct Stage {
  std::string name;
  StageFn fn = nullptr;
  std::vector<int> deps;          // indices of stages that must finish first
  std::vector<std::string> why;   // one reason per dependency
  // State the stage reads and writes (array names, or "grain_order" for the numbering of the
  // grains, which a neighbour rebuild may change). Checked by check_access().
  std::vector<std::string> reads, writes;
};

// Two stages that the graph may run at the same time must not touch the same data with at least
// one of them writing it. Returns "" or a description of the first conflict.
std::string check_access(const std::vector<Stage>& stages);

class StepGraph {
 public:
  // Must be constructed inside the task arena that will run it.
  explicit StepGraph(const Model& m);
  StepGraph(const StepGraph&) = delete;
  StepGraph& operator=(const StepGraph&) = delete;

  // The reference executor: stages one after the other in topological order.
  void run_serial(const Model& m, State& s);
  // The same stages on the TBB flow graph: independent stages run concurrently.
  void run_flow(const Model& m, State& s);

  const std::vector<Stage>& stages() const { return stages_; }
  // "a -> b  (why)" lines, for `silt check`.
  std::string describe() const;

 private:
  void run_stage(size_t k);
  void bind(const Model& m, State& s);

  std::vector<Stage> stages_;
  std::vector<StageTime*> timers_;
  const Model* model_ = nullptr;
  State* state_ = nullptr;
  std::unique_ptr<tbb::flow::graph> graph_;
  std::unique_ptr<tbb::flow::broadcast_node<tbb::flow::continue_msg>> start_;
  std::vector<std::unique_ptr<tbb::flow::continue_node<tbb::flow::continue_msg>>> nodes_;
};

// The stage list of a Model, in topological order (used by the graph and by `silt check`).
std::vector<Stage> build_stages(const Model& m);

}  // namespace silt::graph

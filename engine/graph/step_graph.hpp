// The executors of a stage list: a serial one, the reference (stages one after the other in
// topological order, loop bodies `times` times), and a oneTBB flow graph on which independent
// stages run at the same time. Both time every stage into State::profile, and neither lets an
// exception escape a stage: it becomes the step's internal error.
#pragma once

#include <tbb/flow_graph.h>

#include <memory>
#include <string>
#include <vector>

#include "graph/graph_builder.hpp"

namespace silt::graph {

class StepGraph {
 public:
  // The graph of the modules `m` enables, for a step or for the forces of the first state. Must
  // be constructed inside the task arena that will run it.
  StepGraph(const Model& m, Workspaces& ws, Phase phase = Phase::kStep);
  // Any stage list (tests build their own).
  explicit StepGraph(StageList list, std::vector<Diagnosis> diagnoses = {});
  ~StepGraph();
  StepGraph(const StepGraph&) = delete;
  StepGraph& operator=(const StepGraph&) = delete;

  void run_serial(const Model& m, State& s);
  void run_flow(const Model& m, State& s);

  const std::vector<Stage>& stages() const;
  // The stages with their modules, loop nodes with their bodies, and why each runs after
  // another, for `silt check`.
  std::string describe() const;
  // After a step: the failure the events it raised make (the modules' diagnoses), an internal
  // error first. Fills s.failure; false when the step failed.
  // `step`: the step the failure is reported at (default: the state's, which the step's clock has
  // advanced; a graph run before a step, the resolve graph, reports the step it runs for).
  bool diagnose(const Model& m, State& s, int64_t step = -1) const;

  // Whether the serial executor checks that each stage writes and reads only the fields it
  // declares (graph/access_check.hpp). On by default in the sanitizer build (SILT_CHECK_ACCESS),
  // unless the environment sets SILT_ACCESS_CHECK=0.
  void set_access_check(bool on);

 private:
  struct Runner;
  std::unique_ptr<Runner> root_;
  std::vector<Diagnosis> diagnoses_;
};

}  // namespace silt::graph

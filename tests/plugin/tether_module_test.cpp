// A module registered at run time (register_module), as a user's build would add one: a tether
// pulling each grain back to where it started, F = -k (x - x0). It brings a key, a per-grain
// field of its own that must follow the grains when they are renumbered, a force the kick adds,
// an observable and a loop node. It lives in its own test program: once registered, a module
// stays, and the other tests see silt's own modules only.
#include <doctest/doctest.h>

#include <array>
#include <span>
#include <utility>

#include "graph/graph_builder.hpp"
#include "silt/module.hpp"
#include "support/scenes.hpp"

using namespace silt;

namespace {

struct TetherParams {
  double k = 0;
};

FieldId field(const char* name) { return find_field(name)->id; }

// The grain's displacement from its anchor, the nearest periodic image.
std::array<double, 3> stretch(const State& s, std::span<const double> x0, int64_t i) {
  std::array<double, 3> d{0, 0, 0};
  for (int c = 0; c < s.dim; ++c) d[c] = s.particle_x[s.dim * i + c] - x0[s.dim * i + c];
  s.box.nearest(d.data(), s.dim);
  return d;
}

// (box, particle_x, particle_x0) => (particle_f_tether)
void tether_forces(const Model& m, State& s) {
  const double k = m.params.get<TetherParams>().k;
  auto f = double_field(s, field("particle_f_tether"));
  const auto x0 = double_field(std::as_const(s), field("particle_x0"));
  for (int64_t i = 0; i < s.n; ++i) {
    const auto d = stretch(s, x0, i);
    for (int c = 0; c < s.dim; ++c) f[s.dim * i + c] = -k * d[c];
  }
}

const ModuleSpec& tether() {
  static const ModuleSpec spec = [] {
    ModuleSpec s;
    s.name = "tether";
    s.doc = "each grain tied to where it started";
    s.keys = {
        {"tether.stiffness", KeyType::kReal, std::nullopt, Range::positive(), "N/m", true, {}, "Tether stiffness."}};
    s.fields = {{"particle_x0", Extent::kGrainVec, "m", "where the grain started; compile"},
                {"particle_f_tether", Extent::kGrainVec, "N", "tether force; tether_forces"}};
    s.observables = {
        {"tether.energy", "J", "energy stored in the tethers", [](const ObservableContext& c, const ObservableArgs&) {
           const double k = c.m.params.get<TetherParams>().k;
           const auto x0 = double_field(c.s, field("particle_x0"));
           double e = 0;
           for (int64_t i = 0; i < c.s.n; ++i) {
             const auto d = stretch(c.s, x0, i);
             e += 0.5 * k * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
           }
           return e;
         }}};
    s.enabled = [](const SceneDesc& d) { return d.has("tether.stiffness"); };
    s.compile = [](const SceneDesc& d, Model& m) { m.params.get<TetherParams>().k = d.real("tether.stiffness"); };
    s.force_parameters = [](const Model& m) { return std::vector<double>{m.params.get<TetherParams>().k}; };
    return s;
  }();
  return spec;
}

void add_tether_stages(graph::GraphBuilder& b) {
  const FieldId x0 = field("particle_x0"), f = field("particle_f_tether");
  if (b.phase() == graph::Phase::kSetup) {
    // The anchors: the positions of the first state.
    const int anchor = b.add("tether_anchor",
                             [x0](const Model&, State& s) {
                               auto a = double_field(s, x0);
                               std::copy(s.particle_x.begin(), s.particle_x.end(), a.begin());
                             },
                             {fid::particle_x}, {x0});
    b.after(anchor, b.find("update_neighbors"), "anchors in the grains' numbering of the first state");
  }
  // A loop of one cycle: a module's sub-graph, visible in silt check.
  const int loop = b.loop("tether_cycle", 1, [&](graph::GraphBuilder& body) {
    body.add("tether_forces", &tether_forces, {fid::box, fid::particle_x, x0}, {f});
  });
  if (const int nbr = b.find("update_neighbors"); nbr >= 0) b.after(loop, nbr, "a rebuild may renumber the grains");
  if (b.phase() == graph::Phase::kSetup) b.after(loop, b.find("tether_anchor"), "pulls toward the anchors");
  b.add_force({f, kNoField}, loop);
}

// 1,100 frictional disks in a periodic box, more than 1,024 so that grains are renumbered in cell
// order at list builds.
const char* kGas = R"(
[scene]
dimension = 2
seed = 5
[domain]
lo = [0, 0]
hi = [50, 50]
periodic = [true, true]
[contact]
model = "linear"
k_n = 1e4
damping = 0.5
friction = 0.3
[[grains]]
count = 1100
radius_min = 0.35
radius_max = 0.5
placement = "random"
velocity = "gaussian"
temperature = 0.5
[run]
dt_over_tc = 0.05
)";

std::string scene(double k) { return std::string(kGas) + "[tether]\nstiffness = " + std::to_string(k) + "\n"; }

}  // namespace

TEST_CASE("a module registered at run time enters the schema, the graph, the kick and the observables") {
  register_module(&tether(), add_tether_stages);
  CHECK(find_key_spec("tether.stiffness")->module == "tether");
  auto sim = test::simulation_from(scene(50.0), 1);
  CHECK(sim->describe_graph().find("tether_cycle x 1") != std::string::npos);
  CHECK(sim->describe_graph().find("after tether_cycle: adds the force of tether_cycle") != std::string::npos);
  sim->set_access_check(true);
  const Observer obs(sim->model(), {"tether.energy", "ke"});
  double e_max = 0;
  for (int k = 0; k < 400; ++k) {
    const bool ok = sim->step();
    INFO(sim->state().failure.message);
    REQUIRE(ok);
    e_max = std::max(e_max, obs.sample(sim->model(), sim->state())[0]);
  }
  CHECK(e_max > 0);
  // The anchors followed the grains through the renumberings: each grain's tether is short.
  const State& s = sim->state();
  const auto x0 = double_field(s, find_field("particle_x0")->id);
  double worst = 0;
  for (int64_t i = 0; i < s.n; ++i)
    for (double d : stretch(s, x0, i)) worst = std::max(worst, std::abs(d));
  CHECK(worst < 1.0);
  CHECK(s.nbr_builds > 1);
  // Without the key, the module is off: no stage, no field.
  auto plain = test::simulation_from(kGas, 1);
  CHECK(plain->describe_graph().find("tether") == std::string::npos);
  CHECK(plain->state().module_field(find_field("particle_x0")->id).empty());
}

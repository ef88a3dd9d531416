// The step graph: stages per enabled module, and the access check that keeps concurrent stages
// from touching the same data.
#include <doctest/doctest.h>

#include "graph/step_graph.hpp"
#include "support/scenes.hpp"

using namespace silt;

TEST_CASE("stages follow the modules a scene enables") {
  auto names = [](const Model& m) {
    std::vector<std::string> out;
    for (const auto& s : graph::build_stages(m)) out.push_back(s.name);
    return out;
  };
  const Model chute = compile(load_scene_file(test::scene_path("chute")));
  CHECK(names(chute) == std::vector<std::string>{"kick_drift", "update_neighbors", "contact_forces", "kick"});
  const Model silo = compile(load_scene_file(test::scene_path("silo")));
  CHECK(names(silo) ==
        std::vector<std::string>{"kick_drift", "update_neighbors", "contact_forces", "wall_forces", "kick"});
  const Model pack = compile(load_scene_file(test::scene_path("pack_2d")));
  CHECK(names(pack).back() == "box_kick");
}

TEST_CASE("the access check finds stages that may race") {
  std::vector<graph::Stage> st(3);
  st[0] = {"a", nullptr, {}, {}, {"x"}, {"y"}};
  st[1] = {"b", nullptr, {0}, {"needs y"}, {"y"}, {"z"}};
  st[2] = {"c", nullptr, {0}, {"needs y"}, {"z"}, {"w"}};  // reads z while b writes it, unordered
  CHECK(graph::check_access(st).find("b and c may run at the same time and both use z") != std::string::npos);
  st[2].deps.push_back(1);
  CHECK(graph::check_access(st).empty());
  st[0].writes.push_back("w");  // a is before c: no conflict
  CHECK(graph::check_access(st).empty());
}

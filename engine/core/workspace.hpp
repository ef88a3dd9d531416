// Per-module workspaces: what a module's stages keep between steps that is not state (cell lists,
// pair schedules, factorisations, multigrid hierarchies, solver vectors). The Simulation owns
// them, one per module, and invalidates them whenever the state they were made for is replaced
// (a restore, a replay) or renumbered; a stage rebuilds what it finds invalid.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "silt/fields.hpp"

namespace silt {

class Workspace {
 public:
  virtual ~Workspace() = default;
  virtual void invalidate() = 0;
  // The grains were renumbered (dem::update_neighbors sorts them in cell order): what was made for
  // their former order is stale. A workspace that follows the renumbering itself overrides this.
  virtual void renumbered() { invalidate(); }
  virtual size_t bytes() const = 0;  // held, for memory reports
};

class Workspaces {
 public:
  // The workspace of type W, made on first use.
  template <class W>
  W& get() {
    for (auto& [key, w] : items_)
      if (key == tag<W>()) return static_cast<W&>(*w);
    items_.emplace_back(tag<W>(), std::make_unique<W>());
    return static_cast<W&>(*items_.back().second);
  }
  void invalidate() {
    for (auto& item : items_) item.second->invalidate();
  }
  // Tells every workspace but `by`, the one that renumbered the grains.
  void renumbered(const Workspace* by) {
    for (auto& item : items_)
      if (item.second.get() != by) item.second->renumbered();
  }
  size_t bytes() const {
    size_t b = 0;
    for (const auto& item : items_) b += item.second->bytes();
    return b;
  }

 private:
  template <class W>
  static const void* tag() {
    static const char k = 0;
    return &k;
  }
  std::vector<std::pair<const void*, std::unique_ptr<Workspace>>> items_;
};

// A force (and torque) that a module adds to the grains: a per-grain array (N*D) or one per grain
// and wall (N*W*D, summed over the walls in wall order), and a per-grain torque (N*R) or none.
// dem::kick adds them, in the order they were registered, to the pair forces.
inline constexpr FieldId kNoField = 0xffff;
struct ForceSource {
  FieldId force = kNoField;
  FieldId torque = kNoField;
};
using ForceSources = std::vector<ForceSource>;

}  // namespace silt

// The fields of a State: what each one is indexed by (its extent), its identity (a FieldId), and
// the table that describes them. The built-in fields are declared once in state.hpp
// (SILT_STATE_FIELDS); a module may add fields of its own (double arrays) through its
// ModuleSpec (silt/module.hpp), which registers them here. Allocation, hashing, checkpoints,
// grain renumbering, access sets and the shell's `fields` command all read this table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

namespace silt {

// What a field is indexed by. N grains, D = dimension, R = rotational degrees of freedom (1 in
// 2D), W walls, P listed pairs; grid fields follow the cells or the faces of a staggered grid.
enum class Extent : uint8_t {
  kScalar,         // one value
  kGrain,          // N
  kGrainVec,       // N*D
  kGrainRot,       // N*R
  kGrainRotWalls,  // N*R when the scene has walls, else nothing (what walls alone write)
  kGrainWallVec,   // N*W*D
  kRowStart,       // N+1: first pair of each row of the pair list
  kPair,           // P
  kPairVec,        // P*D
  kCell,           // grid cells
  kFaceX,          // grid faces normal to x
  kFaceY,          // ... to y
  kFaceZ,          // ... to z
  kFree,           // any length, kept by its module (a stored matrix); empty in a new state
};
const char* extent_name(
    Extent e);  // "1", "N", "N*D", "N*R", "N*W*D", "N+1", "P", "P*D", "cells", "x faces", ..., "any"
// Whether a field moves with the grains when they are renumbered (grid and pair fields do not:
// the pair list is rebuilt, and grid fields are indexed by space, not by grain).
bool follows_grains(Extent e);
// Whether a field is indexed by the cells or faces of a grid.
bool on_grid(Extent e);

using FieldId = uint16_t;

struct FieldInfo {
  FieldId id = 0;
  std::string name;    // <entity>_<quantity>
  std::string module;  // core, dem, shear, or the module that registered it
  Extent extent = Extent::kScalar;
  std::string type;  // C++ element type, for reports
  size_t elem_size = 0;
  std::string unit;
  std::string doc;  // meaning; the stage that writes it
};

// Every field: the built-in ones in the order of SILT_STATE_FIELDS, then those registered (a
// deque: registering keeps references to the others valid).
const std::deque<FieldInfo>& field_infos();
const FieldInfo& field_info(FieldId id);
const FieldInfo* find_field(std::string_view name);
// A module's own field (a double array of the given extent); returns its id. Registering the same
// name twice returns the first id. Not thread-safe: modules register before simulations start.
FieldId register_module_field(const std::string& name, const std::string& module, Extent extent,
                              const std::string& unit, const std::string& doc);

}  // namespace silt

// The field table: the built-in fields of SILT_STATE_FIELDS, then the fields modules register.
#include <stdexcept>

#include "silt/module.hpp"
#include "silt/state.hpp"

namespace silt {
namespace {

std::deque<FieldInfo>& table() {
  static std::deque<FieldInfo> t = [] {
    std::deque<FieldInfo> out;
#define SILT_FIELD_INFO(module, type, name, extent, unit, doc) \
  out.push_back({fid::name, #name, #module, Extent::extent, #type, sizeof(type), unit, doc});
    SILT_STATE_FIELDS(SILT_FIELD_INFO)
#undef SILT_FIELD_INFO
    return out;
  }();
  return t;
}

}  // namespace

const char* extent_name(Extent e) {
  switch (e) {
    case Extent::kScalar: return "1";
    case Extent::kGrain: return "N";
    case Extent::kGrainVec: return "N*D";
    case Extent::kGrainRot: return "N*R";
    case Extent::kGrainRotWalls: return "N*R if walls";
    case Extent::kGrainWallVec: return "N*W*D";
    case Extent::kRowStart: return "N+1";
    case Extent::kPair: return "P";
    case Extent::kPairVec: return "P*D";
    case Extent::kCell: return "cells";
    case Extent::kFaceX: return "x faces";
    case Extent::kFaceY: return "y faces";
    case Extent::kFaceZ: return "z faces";
    case Extent::kFree: return "any";
  }
  return "?";
}

bool follows_grains(Extent e) {
  return e == Extent::kGrain || e == Extent::kGrainVec || e == Extent::kGrainRot || e == Extent::kGrainRotWalls ||
         e == Extent::kGrainWallVec;
}

bool on_grid(Extent e) {
  return e == Extent::kCell || e == Extent::kFaceX || e == Extent::kFaceY || e == Extent::kFaceZ;
}

// The modules' fields are registered when the module list is made: make it first.
const std::deque<FieldInfo>& field_infos() {
  (void)modules();
  return table();
}

const FieldInfo& field_info(FieldId id) {
  const auto& t = table();
  if (id >= t.size()) throw std::out_of_range("no field with id " + std::to_string(id));
  return t[id];
}

namespace {
const FieldInfo* find_in_table(std::string_view name) {
  for (const FieldInfo& f : table())
    if (f.name == name) return &f;
  return nullptr;
}
}  // namespace

const FieldInfo* find_field(std::string_view name) {
  (void)modules();
  return find_in_table(name);
}

FieldId register_module_field(const std::string& name, const std::string& module, Extent extent,
                              const std::string& unit, const std::string& doc) {
  if (const FieldInfo* f = find_in_table(name)) {
    if (f->module != module) throw std::logic_error("field '" + name + "' is registered by module " + f->module);
    return f->id;
  }
  auto& t = table();
  const auto id = static_cast<FieldId>(t.size());
  t.push_back({id, name, module, extent, "double", sizeof(double), unit, doc});
  return id;
}

}  // namespace silt

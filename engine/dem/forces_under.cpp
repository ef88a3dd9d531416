#include "dem/forces_under.hpp"

#include <algorithm>

#include "silt/module.hpp"

namespace silt::dem {
namespace {

void append(std::vector<double>& v, const ContactParams& c) {
  v.insert(v.end(), {static_cast<double>(c.law), c.k0, c.k1, c.c1, c.zeta, c.e_tilde, c.clip_attractive ? 1.0 : 0.0,
                     c.friction, c.kt_ratio, c.zeta_t});
}

}  // namespace

std::vector<double> contact_parameters(const Model& m) {
  std::vector<double> v;
  append(v, m.contact);
  for (const ContactParams& c : m.pair_contact) append(v, c);
  for (const ContactParams& c : m.wall_contact) append(v, c);
  for (const Material& mat : m.materials) v.insert(v.end(), {mat.compliance, mat.k_n, mat.friction});
  for (const Wall& w : m.walls) v.push_back(w.friction);
  return v;
}

std::vector<double> force_parameters(const Model& m) {
  std::vector<double> v;
  for (const Module& mod : modules()) {
    if (!mod.spec->force_parameters || !m.module_on(mod.spec->name)) continue;
    const std::vector<double> own = mod.spec->force_parameters(m);
    v.insert(v.end(), own.begin(), own.end());
  }
  return v;
}

FieldId forces_under_field() {
  static const FieldId id = find_field("dem_forces_under")->id;
  return id;
}

bool forces_under_other(const Model& m, const State& s) {
  const std::vector<double>& under = s.module_field(forces_under_field());
  if (under.empty()) return false;
  const std::vector<double> now = force_parameters(m);
  return !std::equal(under.begin(), under.end(), now.begin(), now.end());
}

void record_forces_under(const Model& m, State& s) { s.module_field(forces_under_field()) = force_parameters(m); }

}  // namespace silt::dem

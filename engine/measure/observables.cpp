// Observable names (INTERFACE.md) -> values.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "core/text.hpp"
#include "silt/observables.hpp"

namespace silt {
namespace {

enum Kind { kT, kStep, kDt, kKe, kKeRot, kPhi, kZ, kZStar, kNContacts, kStress, kPressure, kMu, kBoxL, kGrainX, kGrainV, kGrainW, kGrainF, kNBuilds, kNPairs, kWallF, kShearRate, kStrain, kInertial, kKeFluct, kFabric, kKappa, kZeta, kZMech, kP0, kPn };

// Every kind of observable with its name, its unit ("" for dimensionless numbers and counts) and
// whether it needs measure() (a pass over the grains and contacts). Names with a pattern are
// families parsed in parse(): A, B an axis, K a grain or wall index.
struct KindInfo {
  Kind kind;
  const char* name;
  const char* unit;
  bool measured;
};
constexpr KindInfo kKinds[] = {
    {kT, "t", "s", false},          {kStep, "step", "", false},        {kDt, "dt", "s", false},
    {kKe, "ke", "J", true},         {kKeRot, "ke_rot", "J", true},     {kKeFluct, "ke_fluct", "J", true},
    {kPhi, "phi", "", true},        {kZ, "z", "", true},               {kZStar, "z_star", "", true},
    {kNContacts, "n_contacts", "", true}, {kPressure, "pressure", "Pa", true}, {kMu, "mu", "", true},
    {kNBuilds, "n_builds", "", false}, {kNPairs, "n_pairs", "", false}, {kStrain, "gamma", "", false},
    {kShearRate, "gammadot", "1/s", false}, {kInertial, "I", "", false}, {kKappa, "kappa", "", false},
    {kZeta, "zeta", "", false},     {kZMech, "z_mech", "", true},      {kP0, "p0", "", true},
    {kPn, "pn.K", "", true},
    {kStress, "stress.AB", "Pa", true}, {kFabric, "fabric.AB", "", true}, {kBoxL, "box.LA", "m", false},
    {kGrainX, "p[K].A", "m", false}, {kGrainV, "p[K].vA", "m/s", false}, {kGrainW, "p[K].wA", "rad/s", false},
    {kGrainF, "p[K].fA", "N", false}, {kWallF, "wall[K].fA", "N", false},
};

bool is_family(const KindInfo& k) { return std::strpbrk(k.name, ".[") != nullptr; }

const KindInfo& info_of(int kind) {
  for (const KindInfo& k : kKinds)
    if (k.kind == kind) return k;
  throw std::logic_error("observable kind without an entry in kKinds");
}

const char* kAxes = "xyz";

struct Parsed {
  int kind = -1, component = 0;
  int64_t grain = -1;
  std::string error;
};

// Names that exist in the contract but need a module this engine version does not have yet.
bool needs_other_module(const std::string& name) {
  static const char* later[] = {"Vi", "fluid.ke", "fluid.div_max", "solver.iters", "solver.residual"};
  return std::any_of(std::begin(later), std::end(later), [&](const char* s) { return name == s; });
}

// "stress.xy" with prefix "stress." -> 3 * 0 + 1; -1 when the name is not a component of the
// dimension's tensor.
int tensor_component(const std::string& name, const char* prefix, int dim) {
  const size_t n = std::strlen(prefix);
  if (name.size() != n + 2 || name.compare(0, n, prefix) != 0) return -1;
  const char* a = std::strchr(kAxes, name[n]);
  const char* b = std::strchr(kAxes, name[n + 1]);
  if (!a || !b || !*a || !*b || a - kAxes >= dim || b - kAxes >= dim) return -1;
  return static_cast<int>((a - kAxes) * 3 + (b - kAxes));
}

Parsed parse(const std::string& name, const Model& m) {
  Parsed p;
  const int D = m.dim;
  for (const KindInfo& info : kKinds)
    if (!is_family(info) && name == info.name) {
      const Kind k = info.kind;
      if ((k == kStrain || k == kShearRate || k == kInertial) && !m.shear.on) {
        p.error = "observable '" + name + "' applies where the scene shears (shear.rate, shear.inertial_number or shear.stress)";
        return p;
      }
      p.kind = k;
      return p;
    }
  for (auto [prefix, kind] : {std::pair{"stress.", kStress}, std::pair{"fabric.", kFabric}})
    if (const int c = tensor_component(name, prefix, D); c >= 0) {
      p.kind = kind;
      p.component = c;
      return p;
    }
  // pn.K: the fraction of grains with exactly K contacts (Peyneau 2009 Table 3.14).
  if (name.rfind("pn.", 0) == 0 && name.size() > 3 && name.size() <= 6 &&
      name.find_first_not_of("0123456789", 3) == std::string::npos) {
    p.kind = kPn;
    p.component = std::stoi(name.substr(3));
    return p;
  }
  if (name.rfind("box.L", 0) == 0 && name.size() == 6) {
    const char* a = std::strchr(kAxes, name[5]);
    if (a && *a && a - kAxes < D) {
      p.kind = kBoxL;
      p.component = static_cast<int>(a - kAxes);
      return p;
    }
  }
  if (name.rfind("p[", 0) == 0) {
    const auto rb = name.find(']');
    if (rb != std::string::npos && rb > 2 && rb + 2 < name.size() && name[rb + 1] == '.') {
      const std::string idx = name.substr(2, rb - 2);
      const std::string field = name.substr(rb + 2);
      if (idx.find_first_not_of("0123456789") == std::string::npos && idx.size() < 12) {
        p.grain = std::stoll(idx);
        if (p.grain >= m.n_grains) {
          p.error = "'" + name + "': there is no grain " + idx + " (the scene has " + std::to_string(m.n_grains) + ")";
          return p;
        }
        const char* ax = field.size() >= 1 ? std::strchr(kAxes, field.back()) : nullptr;
        const std::string head = field.substr(0, field.size() - 1);
        if (ax && *ax) {
          const int c = static_cast<int>(ax - kAxes);
          if (head.empty() && c < D) p.kind = kGrainX;
          else if (head == "v" && c < D) p.kind = kGrainV;
          else if (head == "f" && c < D) p.kind = kGrainF;
          else if (head == "w" && (D == 3 || c == 2)) p.kind = kGrainW;
          p.component = (p.kind == kGrainW && D == 2) ? 0 : c;
          if (p.kind >= 0) return p;
        }
      }
    }
  }
  if (name.rfind("wall[", 0) == 0) {
    const auto rb = name.find(']');
    if (rb != std::string::npos && rb > 5 && name.size() == rb + 4 && name.substr(rb + 1, 2) == ".f") {
      const std::string idx = name.substr(5, rb - 5);
      const char* ax = std::strchr(kAxes, name.back());
      if (idx.find_first_not_of("0123456789") == std::string::npos && idx.size() < 6 && ax && *ax && ax - kAxes < D) {
        p.grain = std::stoll(idx);  // the wall index
        if (p.grain >= static_cast<int64_t>(m.walls.size())) {
          p.error = "'" + name + "': there is no wall " + idx + " (the scene has " + std::to_string(m.walls.size()) + ")";
          return p;
        }
        p.kind = kWallF;
        p.component = static_cast<int>(ax - kAxes);
        return p;
      }
    }
  }
  if (needs_other_module(name)) {
    p.error = "observable '" + name + "' does not apply to this scene (it needs a module the scene does not enable)";
    return p;
  }
  p.error = "unknown observable '" + name + "'";
  // Suggest the closest valid name.
  std::string best;
  size_t best_d = 3;
  for (const std::string& c : observable_names(m)) {
    const size_t dist = edit_distance(name, c);
    if (dist < best_d) {
      best_d = dist;
      best = c;
    }
  }
  if (!best.empty()) p.error += "; did you mean '" + best + "'?";
  return p;
}

}  // namespace

double inertial_number(const Model& m, double shear_rate, double pressure) {
  if (!(pressure > 0)) return 0;
  return std::abs(shear_rate) * std::sqrt(m.m_a / (std::pow(m.a_max, m.dim - 2) * pressure));
}

double stiffness_number(const Model& m, double pressure) {
  if (!(pressure > 0)) return 0;
  if (m.contact.law == NormalLaw::kHertz) return std::pow(m.contact.e_tilde / pressure, 2.0 / 3.0);
  return m.k_max / (pressure * std::pow(m.a_max, m.dim - 2));
}

std::vector<std::string> observable_names(const Model& m) {
  std::vector<std::string> out;
  for (const KindInfo& k : kKinds)
    if (!is_family(k) && (m.shear.on || (k.kind != kStrain && k.kind != kShearRate && k.kind != kInertial)))
      out.push_back(k.name);
  for (int a = 0; a < m.dim; ++a)
    for (int b = 0; b < m.dim; ++b) out.push_back(std::string("stress.") + kAxes[a] + kAxes[b]);
  for (int a = 0; a < m.dim; ++a)
    for (int b = 0; b < m.dim; ++b) out.push_back(std::string("fabric.") + kAxes[a] + kAxes[b]);
  for (int a = 0; a < m.dim; ++a) out.push_back(std::string("box.L") + kAxes[a]);
  for (int k = 0; k <= 12; ++k) out.push_back("pn." + std::to_string(k));  // any K is accepted
  for (const char* f : {"", "v", "f"})
    for (int a = 0; a < m.dim; ++a) out.push_back(std::string("p[0].") + f + kAxes[a]);
  if (m.dim == 3)
    for (int a = 0; a < 3; ++a) out.push_back(std::string("p[0].w") + kAxes[a]);
  else
    out.push_back("p[0].wz");
  for (size_t w = 0; w < m.walls.size(); ++w)
    for (int a = 0; a < m.dim; ++a) out.push_back("wall[" + std::to_string(w) + "].f" + kAxes[a]);
  return out;
}

std::string check_observable(const std::string& name, const Model& m) { return parse(name, m).error; }

Observer::Observer(const Model& m, std::vector<std::string> names) : names_(std::move(names)) {
  for (const std::string& n : names_) {
    Parsed p = parse(n, m);
    if (!p.error.empty()) throw std::invalid_argument(p.error);
    items_.push_back({p.kind, p.component, p.grain});
    const KindInfo& info = info_of(p.kind);
    units_.push_back(info.unit);
    // I and kappa take the measured pressure when no pressure is imposed.
    if (info.measured || ((p.kind == kInertial || p.kind == kKappa) && !m.box_control.on)) needs_measure_ = true;
  }
}

std::vector<double> Observer::sample(const Model& m, const State& s) const {
  Measurements meas;
  if (needs_measure_) meas = measure(m, s);
  const int D = m.dim, R = m.rot;
  std::vector<double> out;
  out.reserve(items_.size());
  std::vector<int64_t> index;  // grain id -> index, built once if a p[K] observable is asked
  for (const Item& it : items_)
    if (it.grain >= 0 && it.kind != kWallF && index.empty()) index = index_of_ids(s);
  for (const Item& it : items_) {
    double v = 0;
    switch (it.kind) {
      case kT: v = s.t; break;
      case kStep: v = static_cast<double>(s.step); break;
      case kDt: v = s.dt; break;
      case kKe: v = meas.ke; break;
      case kKeRot: v = meas.ke_rot; break;
      case kPhi: v = meas.phi; break;
      case kZ: v = meas.z; break;
      case kZStar: v = meas.z_star; break;
      case kZMech: v = meas.z_mech; break;
      case kP0: v = meas.p0; break;
      case kPn: v = it.component < static_cast<int>(meas.pn.size()) ? meas.pn[it.component] : 0; break;
      case kNContacts: v = static_cast<double>(meas.n_contacts); break;
      case kStress: v = meas.stress[it.component / 3][it.component % 3]; break;
      case kPressure: v = meas.pressure; break;
      case kMu: v = meas.stress[1][1] != 0 ? std::abs(meas.stress[0][1]) / meas.stress[1][1] : 0; break;
      case kBoxL: v = s.box.len[it.component]; break;
      case kKeFluct: v = meas.ke_fluct; break;
      case kFabric: v = meas.fabric[it.component / 3][it.component % 3]; break;
      case kShearRate: v = s.shear_rate; break;
      case kStrain: v = s.shear_strain; break;
      case kInertial: v = inertial_number(m, s.shear_rate, m.box_control.on ? m.box_control.pressure : meas.stress[1][1]); break;
      case kKappa: v = stiffness_number(m, m.box_control.on ? m.box_control.pressure : meas.pressure); break;
      case kZeta: v = m.zeta_max; break;
      case kNBuilds: v = static_cast<double>(s.nbr_builds); break;
      case kNPairs: v = static_cast<double>(s.n_pairs()); break;
      case kWallF: {  // force of the grains on the wall: minus the wall's force on them
        const int nw = s.n_walls;
        for (int64_t i = 0; i < s.n; ++i) v -= s.wall_f[(i * nw + it.grain) * D + it.component];
        break;
      }
      case kGrainX: v = s.particle_x[D * index[it.grain] + it.component]; break;
      case kGrainV: v = s.particle_v[D * index[it.grain] + it.component]; break;
      case kGrainW: v = s.particle_w[R * index[it.grain] + it.component]; break;
      case kGrainF: {
        const int64_t i = index[it.grain];
        const double g = s.particle_frozen[i] ? 0 : m.gravity[it.component] / s.particle_inv_m[i];
        v = s.particle_f[D * i + it.component] + g;
        break;
      }
    }
    out.push_back(v);
  }
  return out;
}

}  // namespace silt

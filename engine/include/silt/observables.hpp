// Observables of INTERFACE.md: names, validation against a Model, and sampling from a State.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "silt/model.hpp"
#include "silt/state.hpp"

namespace silt {

// Bulk measurements of one configuration. Sums run serially in grain and pair order, so the
// values do not depend on the number of threads.
struct Measurements {
  double ke = 0;  // translational + rotational kinetic energy of free grains [J]
  double ke_rot = 0;
  double phi = 0;              // grain volume / box volume
  double volume = 0;           // box volume (area in 2D)
  int64_t n_contacts = 0;      // touching pairs (grain-grain) + grain-wall contacts
  double z = 0;                // contacts per free grain
  double z_star = 0;           // z / (1 - p0): contacts per free grain that has one (Peyneau 2009 sec. 3.4)
  double p0 = 0;               // fraction of free grains with no contact (Peyneau's rattlers)
  std::vector<double> pn;      // pn[n]: fraction of free grains with exactly n contacts, n = 0 .. the largest
  double z_mech = 0;           // contacts per grain of the mechanical skeleton: grains with fewer than 2
                               // contacts with friction, D+1 without, removed repeatedly
  int64_t n_off_skeleton = 0;  // free grains outside that skeleton
  std::array<std::array<double, 3>, 3> stress{};        // contact + kinetic + stress_pairs, compression positive [Pa]
  std::array<std::array<double, 3>, 3> stress_pairs{};  // of the modules' pair forces (lubrication) [Pa]
  double pressure = 0;                                  // trace / D
  double max_net_force = 0;                             // largest |contact + wall + gravity force| on a free grain [N]
  double ke_fluct = 0;  // (1/2N) sum m |v - v_affine|^2: fluctuating translational energy per grain [J]
  std::array<std::array<double, 3>, 3> fabric{};  // <n (x) n> over grain-grain contacts (Peyneau 3.4.2)
  Vec3a momentum{0, 0, 0};                        // sum m v over free grains, the affine flow included [kg m/s]
  double e_contact = 0;  // elastic energy stored in the contacts (normal and tangential springs) [J]
};
// The parts of the measurements, each a pass of its own made only when asked: the fields of a
// part not asked stay at their defaults (the skeleton's pass over the contacts measures the
// contacts too). A sample of the 17,600-grain chute asking for every part costs 4 to 4.6 of its
// steps (one thread), the parts its stats ask for 2.6: ask for what is read.
namespace measure_part {
constexpr unsigned kGrains = 1;    // ke, ke_rot, ke_fluct, phi, volume, momentum, max_net_force
constexpr unsigned kStress = 2;    // stress, stress_pairs, pressure
constexpr unsigned kContacts = 4;  // n_contacts, fabric, z, z_star, p0, pn
constexpr unsigned kSkeleton = 8;  // z_mech, n_off_skeleton
constexpr unsigned kEnergy = 16;   // e_contact
constexpr unsigned kAll = 31;
}  // namespace measure_part
Measurements measure(const Model& m, const State& s, unsigned parts = measure_part::kAll);
// The fields of `parts` computed again into out (the others left as they are).
void measure_into(const Model& m, const State& s, unsigned parts, Measurements& out);

// Mean velocity component `component` (the shear flow included) in n_slabs slabs across `axis`;
// a grain counts in every slab it overlaps (Peyneau 2009 sec. 3.2.1). y: slab centres as a
// fraction of the box length along the axis, from its lower end; vx: the mean velocity.
struct VelocityProfile {
  std::vector<double> y, vx;
  std::vector<int64_t> count;
};
VelocityProfile velocity_profile(const Model& m, const State& s, int n_slabs, int axis = 1, int component = 0);

// Inertial number I = |gammadot| sqrt(m / (a^(d-2) P)) (Peyneau 2009 eq. 1.30), a the largest
// diameter and m the mass of a grain of diameter a (Model::m_a; Peyneau sec. 5.3.3); 0 when P <= 0.
double inertial_number(const Model& m, double shear_rate, double pressure);
// Stiffness number kappa: (E~/P)^(2/3) for Hertz contacts (Peyneau eq. 1.31), k_n / (a^(d-2) P)
// for the linear laws (eq. 1.33; k_n of the lightest pair for the damping-ratio laws); 0 when P <= 0.
// Where groups have laws of their own, the softest pair's (the stiffest's with `stiffest`).
double stiffness_number(const Model& m, double pressure, bool stiffest = false);
// kappa as `silt check` prints it: one number, or "K1 to K2 by pair of groups" (the softest pair's
// to the stiffest's) where the groups' laws differ.
std::string stiffness_number_text(const Model& m, double pressure);
// The viscous time eta a^(3-d) / P of lubricated grains: the time unit of a paste (Peyneau 2009
// Table 2.2 reports T P / eta). The resistances are the spheres' in 2D too (the thesis applies
// them to disks), of order eta a, while P is a force per length in 2D: there it is eta a / P, and
// eta / P in 3D; a the largest diameter. 0 when P <= 0.
double viscous_time(const Model& m, double eta, double pressure);
// The viscous stress eta |rate| a^(3-d) of lubricated grains (a force per length in 2D), the
// stress scale of an imposed rate: viscous_number times P.
double viscous_stress(const Model& m, double eta, double rate);
// Viscous number Vi = |rate| times the viscous time: eta gammadot / P (Peyneau 2009 eq. 1.34) in
// 3D, eta gammadot a / P in 2D (the thesis, in units of a, writes eta gammadot / P for both).
double viscous_number(const Model& m, double eta, double rate, double pressure);

// Observables are declared by the modules (ModuleSpec::observables), one spec per name or per
// family of names. A pattern names a family with placeholders: {a} and {b} an axis below the
// dimension (x, y, z), {w} an axis of rotation (z only in 2D), {k} an index (a grain id, a wall,
// a count): "stress.{a}{b}", "p[{k}].v{a}", "wall[{k}].f{a}", "pn.{k}".
struct ObservableArgs {
  int a = 0, b = 0;  // axes of {a} and {b}
  int w = 0;         // component of {w} in the rotation arrays (0 for z in 2D)
  int64_t k = -1;    // index of {k}
};

// What an observable's value is computed from: the state, and the measurements of it (passes
// over grains and contacts), each part made once per sample and only when an observable asks
// for it.
class ObservableContext {
 public:
  ObservableContext(const Model& model, const State& state) : m(model), s(state) {}
  const Model& m;
  const State& s;
  // The measurements, with at least `parts` (measure_part) computed.
  const Measurements& meas(unsigned parts) const;
  // Index of the grain with this id (grains are renumbered, ids are not).
  int64_t index_of(int64_t id) const;

 private:
  mutable Measurements meas_;
  mutable unsigned measured_ = 0;  // the parts in meas_
  mutable std::vector<int64_t> index_;
};

struct ObservableSpec {
  using ValueFn = std::function<double(const ObservableContext&, const ObservableArgs&)>;
  ObservableSpec() = default;
  ObservableSpec(std::string pattern_, std::string unit_, std::string doc_, ValueFn value_)
      : pattern(std::move(pattern_)), unit(std::move(unit_)), doc(std::move(doc_)), value(std::move(value_)) {}
  std::string pattern;
  std::string unit;  // "" for dimensionless numbers and counts
  std::string doc;
  ValueFn value;
  // "" when it applies to this model (with these arguments), else why not; empty: always.
  std::function<std::string(const Model&, const ObservableArgs&)> check;
  // {k}: how many indices exist (an index at or past it is refused, naming `k_what`), and how many
  // of them `help` and completion list.
  std::function<int64_t(const Model&)> k_count;
  std::string k_what = "grain";
  int64_t k_listed = 1;
  std::string module;  // set when the table is assembled
  // A value of the last step (a solve's iterations, a CFL number): none before the first, where it
  // reads 0 (`run until fluid.change_rate < 1e-3` held at once).
  bool of_last_step = false;
};

// A value of grain K, by id (p[K]...): f(context, the grain's index, args).
template <class F>
ObservableSpec grain_observable(std::string pattern, std::string unit, std::string doc, F f) {
  ObservableSpec o{std::move(pattern), std::move(unit), std::move(doc),
                   [f](const ObservableContext& c, const ObservableArgs& a) { return f(c, c.index_of(a.k), a); }};
  o.k_count = [](const Model& m) { return m.n_grains; };
  o.k_what = "grain";
  return o;
}

// Returns "" when `name` is an observable of this model, else the reason (with a suggestion).
std::string check_observable(const std::string& name, const Model& m);
// Whether `name` (an observable of this model) is a value of the last step (ObservableSpec::of_last_step).
bool observable_of_last_step(const std::string& name, const Model& m);
// Every observable name that applies to this model (families listed with their first indices),
// and its unit: for help and completion.
std::vector<std::string> observable_names(const Model& m);
std::vector<std::pair<std::string, std::string>> observable_units(const Model& m);
// The observables as a person reads them in `help`: one row per family, its pattern written with
// A, B for an axis (x, y, z), W for a rotation axis, K for an index ("stress.AB",
// "p[K].vA"), its unit, what it is and its module; only the modules this model uses (every
// module without a model). Reduced units: no unit.
struct ObservableDoc {
  std::string name, unit, doc, module;
};
std::vector<ObservableDoc> observable_docs(const Model* m);

// A compiled list of observables.
class Observer {
 public:
  // Throws std::invalid_argument naming the first bad observable.
  Observer(const Model& m, std::vector<std::string> names);
  const std::vector<std::string>& names() const { return names_; }
  // Their units ("s", "J", "Pa", "m/s", ...; "" for dimensionless numbers and counts).
  const std::vector<std::string>& units() const { return units_; }
  // Values in the order of names().
  std::vector<double> sample(const Model& m, const State& s) const;

 private:
  struct Item {
    const ObservableSpec* spec;
    ObservableArgs args;
  };
  std::vector<std::string> names_, units_;
  std::vector<Item> items_;
};

}  // namespace silt

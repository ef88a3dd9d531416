// Bulk measurements: kinetic energy, solid fraction, coordination, stress tensor, fabric.
//
// Under a deforming box (stress control, Lees-Edwards shear) particle_v is the velocity relative
// to the affine flow, so the kinetic stress and ke_fluct are those of the fluctuations
// (Peyneau 2009 eq. 3.11 and 3.13).
//
// Stress: dem/stress.hpp, the sums a controlled box is driven by.
#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/parallel.hpp"
#include "dem/stages.hpp"
#include "dem/stress.hpp"
#include "silt/contacts.hpp"
#include "silt/observables.hpp"

namespace silt {
namespace {

// Coordination of the contact network, from the contacts of each grain (grain-grain and
// grain-wall; frozen grains are not counted, their contacts count for the free grains).
//   z = 2 N_c / N (per free grain);
//   p_n = fraction of free grains with exactly n contacts (Peyneau 2009 Table 3.14);
//   z* = z / (1 - p0): the rattlers are the grains with no contact (Peyneau 2009 sec. 2.3.1,
//        "floating grains", and sec. 3.4, z* = z/(1 - p0), 6 for rigid frictionless spheres).
void coordination(const State& s, const std::vector<int32_t>& contacts, int64_t n_free, Measurements& out) {
  int64_t sum = 0;
  std::vector<int64_t> with(1, 0);  // with[k]: free grains with k contacts
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    sum += contacts[i];
    if (contacts[i] >= static_cast<int32_t>(with.size())) with.resize(contacts[i] + 1, 0);
    ++with[contacts[i]];
  }
  out.z = out.z_star = out.p0 = 0;
  out.pn.clear();
  if (n_free == 0) return;
  out.z = static_cast<double>(sum) / n_free;
  out.pn.resize(with.size());
  for (size_t k = 0; k < with.size(); ++k) out.pn[k] = static_cast<double>(with[k]) / n_free;
  out.p0 = out.pn[0];
  out.z_star = with[0] < n_free ? static_cast<double>(sum) / (n_free - with[0]) : 0;
}

// z_mech: the mechanically stable skeleton of the jamming literature: grains with fewer than 2
// contacts with friction, D + 1 without, removed repeatedly (a removal can leave a neighbour
// under the bound), then contacts per remaining grain. In a frictionless flow with z < D + 1 it
// removes every grain and gives 0. `contacts` is consumed.
void skeleton(const Model& m, const State& s, const std::vector<std::pair<int32_t, int32_t>>& touching,
              std::vector<int32_t>& contacts, int64_t n_free, Measurements& out) {
  const int64_t n = s.n;
  out.z_mech = 0;
  out.n_off_skeleton = 0;
  if (n_free == 0) return;
  // Peel the grains under the bound until none is left. Each grain's neighbours in one array
  // (adj[start[i] .. start[i + 1])), in the order of the touching pairs.
  const int need = m.pair_friction() ? 2 : m.dim + 1;
  std::vector<int64_t> start(n + 1, 0);
  for (auto [i, j] : touching) {
    ++start[i + 1];
    ++start[j + 1];
  }
  for (int64_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int32_t> adj(start[n]);
  std::vector<int64_t> fill(start.begin(), start.end() - 1);
  for (auto [i, j] : touching) {
    adj[fill[i]++] = j;
    adj[fill[j]++] = i;
  }
  std::vector<uint8_t> rattler(n, 0);
  std::vector<int32_t> stack;
  for (int64_t i = 0; i < n; ++i)
    if (!s.particle_frozen[i] && contacts[i] < need) stack.push_back(static_cast<int32_t>(i));
  while (!stack.empty()) {
    const int32_t i = stack.back();
    stack.pop_back();
    if (rattler[i]) continue;
    rattler[i] = 1;
    for (int64_t k = start[i]; k < start[i + 1]; ++k) {
      const int32_t j = adj[k];
      if (rattler[j]) continue;
      if (--contacts[j] < need && !s.particle_frozen[j]) stack.push_back(j);
    }
    contacts[i] = 0;
  }
  int64_t kept = 0, ksum = 0;
  for (int64_t i = 0; i < n; ++i) {
    if (s.particle_frozen[i]) continue;
    if (rattler[i]) {
      ++out.n_off_skeleton;
    } else {
      ++kept;
      ksum += contacts[i];
    }
  }
  out.z_mech = kept ? static_cast<double>(ksum) / kept : 0;
}

// Grains a block of the contacts' walk takes (measure_dim): fixed, so that the fabric's sums do
// not depend on the threads.
constexpr int64_t kContactBlock = 2048;

int64_t free_grains(const State& s) {
  int64_t n_free = 0;
  for (int64_t i = 0; i < s.n; ++i) n_free += s.particle_frozen[i] ? 0 : 1;
  return n_free;
}

template <int D>
void measure_dim(const Model& m, const State& s, unsigned parts, Measurements& out) {
  using namespace measure_part;
  const int64_t n = s.n;
  double vol = 1;
  for (int k = 0; k < D; ++k) vol *= s.box.len[k];
  out.volume = vol;
  int64_t n_free_counted = 0;  // (the grains' part counts them)
  if (parts & kGrains) {
    const dem::KineticEnergy ke = dem::kinetic_energy(s);
    out.ke = ke.total;
    out.ke_rot = ke.rot;
    out.max_net_force = 0;
    out.momentum = Vec3a{0, 0, 0};
    double solid = 0;
    int64_t& n_free = n_free_counted;
    for (int64_t i = 0; i < n; ++i) {
      const double r = s.particle_r[i];
      solid += grain_volume(D, r);
      if (s.particle_frozen[i]) continue;
      ++n_free;
      const double mass = 1.0 / s.particle_inv_m[i];
      Vec<D> f = at<D>(s.particle_f.data(), i) + mass * m.gravity.head<D>();
      out.max_net_force = std::max(out.max_net_force, f.norm());
      // Momentum in the lab frame: the velocity relative to the affine flow, plus the flow.
      for (int k = 0; k < D; ++k) {
        double v = s.particle_v[D * i + k];
        if (m.box_control.on) v += s.box_rate[k] / s.box.len[k] * (s.particle_x[D * i + k] - s.box.lo[k]);
        if (k == 0 && m.shear.on) v += s.shear_rate * (s.particle_x[D * i + 1] - s.box.lo[1]);
        out.momentum[k] += mass * v;
      }
    }
    out.phi = solid / vol;
    out.ke_fluct = n_free ? (out.ke - out.ke_rot) / n_free : 0;
  }
  if (parts & kStress) {
    // Stress: the virial sums the controlled box uses (dem/stress.hpp).
    const std::array<double, 9> sigma =
        m.kinetic_stress ? dem::virial_sums<true>(s) : dem::pair_virial_sums(s, s.pair_f.data());
    out.stress = {};
    out.stress_pairs = {};
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) out.stress[a][b] = sigma[3 * a + b] / vol;
    // The modules' pair forces (lubrication), where there are.
    for (const FieldId f : m.pair_stress_fields) {
      const auto pf = double_field(s, f);
      if (pf.size() != static_cast<size_t>(D * s.n_pairs())) continue;  // not computed yet
      const std::array<double, 9> extra = dem::pair_virial_sums(s, pf.data());
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          out.stress_pairs[a][b] += extra[3 * a + b] / vol;
          out.stress[a][b] += extra[3 * a + b] / vol;
        }
    }
    out.pressure = 0;
    for (int a = 0; a < D; ++a) out.pressure += out.stress[a][a] / D;
  }
  if (parts & (kContacts | kSkeleton)) {
    // Grain-grain contacts; and grain-wall contacts, which count for coordination (not a frozen
    // grain's: the walls exert no force on it).
    // Blocks of kContactBlock grains walk their listed pairs at the same time, whatever the
    // threads: the counts are integers, the fabric's sums are added block after block, and the
    // touching pairs come in pair order, as one walk gives them (the same values on any number of
    // threads; the fabric's last bits are those of the blocks' sums).
    const bool pairs = (parts & kSkeleton) != 0;
    std::vector<int32_t> contacts(n, 0);
    auto count = [&](int64_t i) { std::atomic_ref<int32_t>(contacts[i]).fetch_add(1, std::memory_order_relaxed); };
    std::vector<std::vector<std::pair<int32_t, int32_t>>> block_touching(
        pairs ? static_cast<size_t>((n + kContactBlock - 1) / kContactBlock) : 0);
    // (grain-grain contacts, grain-wall contacts, the fabric's 9 sums)
    const std::array<double, 11> sums = deterministic_sums<11>(n, kContactBlock, [&](int64_t i0, int64_t i1) {
      std::array<double, 11> acc{};
      auto* touching = pairs ? &block_touching[i0 / kContactBlock] : nullptr;
      for_each_contact_of(s, i0, i1, [&](const Contact& c) {
        acc[0] += 1;
        count(c.i);
        count(c.j);
        if (touching) touching->push_back({static_cast<int32_t>(c.i), static_cast<int32_t>(c.j)});
        const double dn = c.dist;
        for (int a = 0; a < D; ++a)
          for (int b = 0; b < D; ++b) acc[2 + 3 * a + b] += c.d[a] * c.d[b] / (dn * dn);
      });
      for (int64_t i = i0; i < i1; ++i)
        for (int w = 0; w < s.n_walls && !s.particle_frozen[i]; ++w)
          if (m.walls[w].gap<D>(at<D>(s.particle_x.data(), i), s.particle_r[i]) < 0) {
            acc[1] += 1;
            count(i);
          }
      return acc;
    });
    const auto n_grain_pairs = static_cast<int64_t>(sums[0]);
    const int64_t n_contacts = n_grain_pairs + static_cast<int64_t>(sums[1]);
    std::array<std::array<double, 3>, 3> fabric{};
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) fabric[a][b] = sums[2 + 3 * a + b];
    std::vector<std::pair<int32_t, int32_t>> touching;
    for (const auto& t : block_touching) touching.insert(touching.end(), t.begin(), t.end());
    // (the contacts' part too when only the skeleton was asked for: the same pass)
    const int64_t n_free = (parts & kGrains) ? n_free_counted : free_grains(s);
    out.n_contacts = n_contacts;
    if (n_grain_pairs > 0)
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) fabric[a][b] /= static_cast<double>(n_grain_pairs);
    out.fabric = fabric;
    coordination(s, contacts, n_free, out);
    if (pairs) skeleton(m, s, touching, contacts, n_free, out);
  }
  if (parts & kEnergy) out.e_contact = dem::contact_energy(m, s);
}

}  // namespace

void measure_into(const Model& m, const State& s, unsigned parts, Measurements& out) {
  if (m.dim == 2) measure_dim<2>(m, s, parts, out);
  else measure_dim<3>(m, s, parts, out);
}

Measurements measure(const Model& m, const State& s, unsigned parts) {
  Measurements out;
  measure_into(m, s, parts, out);
  return out;
}

}  // namespace silt

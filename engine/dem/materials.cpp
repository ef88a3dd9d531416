#include "dem/materials.hpp"

#include "dem/contact_laws.hpp"

namespace silt::dem {
namespace {

// The material the scene's [contact] describes (what a group or a wall is unless it says).
Material scene_material(const SceneDesc& d, const Model& m) {
  Material s;
  const ContactParams& c = m.contact;
  if (c.law == NormalLaw::kHertz) s.compliance = 1.0 / c.e_tilde;  // (1 - nu^2) / E: E~ = 2 / (c + c)
  if (c.law == NormalLaw::kHooke || c.law == NormalLaw::kLinear) s.k_n = c.k0;
  s.friction = c.friction;
  (void)d;
  return s;
}

// A group's or a wall's own values of the keys under `prefix` ("grains[2]." or "walls[0].").
Material material_of(const SceneDesc& d, const Model& m, const std::string& prefix, const Material& base, bool wall) {
  Material mat = base;
  const bool hertz = m.contact.law == NormalLaw::kHertz;
  const bool springs = m.contact.law == NormalLaw::kHooke || m.contact.law == NormalLaw::kLinear;
  if (hertz && (d.has(prefix + "young_modulus") || d.has(prefix + "poisson_ratio"))) {
    const double e = d.has(prefix + "young_modulus") ? d.real(prefix + "young_modulus") : 0.0;
    if (!d.has(prefix + "young_modulus"))
      d.fail(prefix + "poisson_ratio", prefix + "poisson_ratio needs " + prefix + "young_modulus");
    const double nu =
        d.has(prefix + "poisson_ratio") ? d.real(prefix + "poisson_ratio") : d.real("contact.poisson_ratio");
    mat.compliance = (1.0 - nu * nu) / e;
  }
  if (wall && d.has(prefix + "rigid") && d.boolean(prefix + "rigid")) {
    if (!hertz && !springs)
      d.fail(prefix + "rigid",
             "a rigid wall changes a Hertz or spring law; spring_dashpot takes its e and t_c per pair");
    if (d.has(prefix + "young_modulus") || d.has(prefix + "k_n"))
      d.fail(prefix + "rigid", "a rigid wall has no modulus or stiffness of its own");
    mat.compliance = 0;
    mat.k_n = 0;  // springs in series with a rigid one: the limit of the series rule (below)
  }
  if (springs && d.has(prefix + "k_n")) mat.k_n = d.real(prefix + "k_n");
  if (d.has(prefix + "friction")) mat.friction = d.real(prefix + "friction");
  return mat;
}

}  // namespace

ContactParams mix(const ContactParams& scene, const Material& a, const Material& b) {
  ContactParams c = scene;
  if (c.law == NormalLaw::kHertz) c.e_tilde = hertz_pair_modulus(a.compliance, b.compliance);
  // A rigid wall (k = 0 marks it): the series rule's limit as the wall stiffens, k_ij = 2 k_grain
  // (the grain's half of a contact of two like grains, as E~ doubles for Hertz; it was k_grain,
  // softer than a wall of k_n = 1e12).
  if (c.law == NormalLaw::kHooke || c.law == NormalLaw::kLinear)
    c.k0 = (a.k_n == 0 || b.k_n == 0) ? 2 * std::max(a.k_n, b.k_n) : series_stiffness(a.k_n, b.k_n);
  c.friction = pair_friction(a.friction, b.friction);
  return c;
}

void setup_materials(const SceneDesc& d, Model& m) {
  const Material base = scene_material(d, m);
  const int G = d.group_count("grains");
  m.materials.clear();
  bool varies = false;
  for (int g = 0; g < G; ++g) {
    const std::string prefix = "grains[" + std::to_string(g) + "].";
    m.materials.push_back(material_of(d, m, prefix, base, false));
    const Material& mg = m.materials.back();
    varies = varies || mg.compliance != base.compliance || mg.k_n != base.k_n || mg.friction != base.friction;
  }
  m.pair_contact.clear();
  if (varies)
    for (int gi = 0; gi < G; ++gi)
      for (int gj = 0; gj < G; ++gj) m.pair_contact.push_back(mix(m.contact, m.materials[gi], m.materials[gj]));
  // Walls: a wall of the scene's material against a grain of it has the scene's law exactly (the
  // bits of a scene without materials do not change). A wall's friction, when it gives one, is
  // that of every contact with it (the grains' otherwise).
  m.wall_contact.clear();
  for (size_t w = 0; w < m.walls.size(); ++w) {
    const std::string prefix = "walls[" + std::to_string(w) + "].";
    Material wall_mat = material_of(d, m, prefix, base, true);
    for (int g = 0; g < G; ++g) {
      const Material& grain = m.materials[g];
      ContactParams c = (wall_mat.compliance == base.compliance && wall_mat.k_n == base.k_n &&
                         grain.compliance == base.compliance && grain.k_n == base.k_n)
                            ? m.contact
                            : mix(m.contact, grain, wall_mat);
      c.friction = d.has(prefix + "friction") ? wall_mat.friction : grain.friction;
      m.wall_contact.push_back(c);
    }
    m.walls[w].friction = m.wall_contact[w * G].friction;
  }
}

}  // namespace silt::dem

namespace silt {

bool Model::pair_friction() const {
  if (pair_contact.empty()) return contact.friction > 0;
  for (const ContactParams& c : pair_contact)
    if (c.friction > 0) return true;
  return false;
}

}  // namespace silt

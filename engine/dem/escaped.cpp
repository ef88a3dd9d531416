#include "dem/escaped.hpp"

#include "silt/text.hpp"

namespace silt::dem {

std::string escaped_grain(const Model& m, const State& s) {
  for (int64_t i = 0; i < s.n; ++i) {
    if (s.particle_frozen[i]) continue;
    for (int a = 0; a < m.dim; ++a) {
      if (m.box.periodic[a]) continue;
      const double x = s.particle_x[m.dim * i + a], r = s.particle_r[i];
      const double lo = s.box.lo[a], hi = s.box.lo[a] + s.box.len[a];
      if (!(x < lo - r || x > hi + r)) continue;
      const std::string face = std::string(1, "xyz"[a]) + (x < lo - r ? "_lo" : "_hi");
      return "grain " + std::to_string(s.particle_id[i]) + " left the domain through its " + face + " face (" +
             std::string(1, "xyz"[a]) + " = " + format_number(x, 4) + m.unit("m") +
             "), which neither a wall nor periodicity closes";
    }
  }
  return "";
}

}  // namespace silt::dem

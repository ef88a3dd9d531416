#include "silt/contacts.hpp"

#include <cmath>

namespace silt {

std::vector<Contact> touching_contacts(const State& s) {
  const int D = s.dim;
  std::vector<Contact> out;
  for (int64_t i = 0; i < s.n; ++i)
    for (int32_t p = s.nbr_start[i]; p < s.nbr_start[i + 1]; ++p) {
      Contact c;
      c.i = i;
      c.j = s.pair_j[p];
      c.pair = p;
      double d2 = 0;
      for (int k = 0; k < D; ++k) c.d[k] = s.particle_x[D * i + k] - s.particle_x[D * c.j + k];
      s.box.nearest(c.d.data(), D);
      for (int k = 0; k < D; ++k) d2 += c.d[k] * c.d[k];
      c.dist = std::sqrt(d2);
      if (!(c.dist < s.particle_r[i] + s.particle_r[c.j]) || c.dist == 0) continue;
      for (int k = 0; k < D; ++k) {
        c.f[k] = s.pair_f[D * p + k];
        c.fn += c.f[k] * c.d[k] / c.dist;
      }
      out.push_back(c);
    }
  return out;
}

}  // namespace silt

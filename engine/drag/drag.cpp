#include "drag/drag.hpp"

#include "core/parallel.hpp"

namespace silt::drag {

void drag_forces(const Model& m, State& s, FieldId force, FieldId torque) {
  const double eta = m.params.get<DragParams>().viscosity;
  const int D = s.dim, R = s.rot;
  double* f = double_field(s, force).data();
  double* t = double_field(s, torque).data();
  parallel_for(s.n, 4096, [&](int64_t b, int64_t e) {
    for (int64_t i = b; i < e; ++i) {
      const double r = s.particle_r[i];
      const double ct = s.particle_frozen[i] ? 0.0 : translational_coefficient(eta, r);
      const double cr = s.particle_frozen[i] ? 0.0 : rotational_coefficient(eta, r);
      for (int k = 0; k < D; ++k) f[D * i + k] = -ct * s.particle_v[D * i + k];
      for (int k = 0; k < R; ++k) t[R * i + k] = -cr * s.particle_w[R * i + k];
    }
  });
}

}  // namespace silt::drag

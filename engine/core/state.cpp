#include "silt/state.hpp"

#include "core/rng.hpp"

namespace silt {

void Alarm::raise(int64_t index, double v) {
  int64_t cur = first.load();
  while (index < cur) {
    if (first.compare_exchange_weak(cur, index)) {
      value.store(v);
      return;
    }
  }
}

State make_state(const Model& m) {
  State s;
  const int64_t n = m.n_grains;
  const int D = m.dim, R = m.rot;
  s.dim = D;
  s.rot = R;
  s.n = n;
  s.n_walls = static_cast<int>(m.walls.size());
  s.dt = m.dt;
  s.box = m.box;
  s.particle_x = m.init.x;
  s.particle_v = m.init.v;
  s.particle_w = m.init.w;
  s.particle_f.assign(n * D, 0);
  s.particle_t.assign(n * R, 0);
  s.particle_r = m.init.radius;
  s.particle_inv_m.resize(n);
  s.particle_inv_i.resize(n);
  for (int64_t i = 0; i < n; ++i) {
    const bool frozen = m.init.frozen[i];
    s.particle_inv_m[i] = frozen ? 0.0 : 1.0 / m.init.mass[i];
    s.particle_inv_i[i] = frozen ? 0.0 : 1.0 / m.init.inertia[i];
  }
  s.particle_disp.assign(n * D, 0.0);
  s.shear_rate = m.shear.rate;
  s.wall_f.assign(n * s.n_walls * D, 0);
  s.particle_t_wall.assign(s.n_walls ? n * R : 0, 0);
  s.wall_hist.assign(n * s.n_walls * D, 0);
  s.nbr_start.assign(n + 1, 0);
  s.particle_frozen = m.init.frozen;
  s.particle_id.resize(n);
  for (int64_t i = 0; i < n; ++i) s.particle_id[i] = static_cast<int32_t>(i);
  s.particle_group = m.init.group;
  s.nbr_valid = false;
  return s;
}

uint64_t state_hash(const State& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  for_each_array(s, [&](const char*, const auto& v) {
    const size_t n = v.size();
    h = fnv1a(&n, sizeof n, h);
    if (n) h = fnv1a(v.data(), n * sizeof(v[0]), h);
  });
  h = fnv1a(&s.t, sizeof s.t, h);
  h = fnv1a(&s.step, sizeof s.step, h);
  h = fnv1a(&s.dt, sizeof s.dt, h);
  h = fnv1a(s.box.len.data(), sizeof(double) * 3, h);
  h = fnv1a(s.box_rate.data(), sizeof(double) * 3, h);
  h = fnv1a(&s.shear_rate, sizeof s.shear_rate, h);
  h = fnv1a(&s.le_displacement, sizeof s.le_displacement, h);
  h = fnv1a(&s.shear_strain, sizeof s.shear_strain, h);
  return h;
}

std::vector<int64_t> index_of_ids(const State& s) {
  std::vector<int64_t> out(s.n, -1);
  for (int64_t i = 0; i < s.n; ++i) out[s.particle_id[i]] = i;
  return out;
}

size_t state_bytes(const State& s) {
  size_t b = sizeof(State);
  for_each_array(s, [&](const char*, const auto& v) { b += v.capacity() * sizeof(v[0]); });
  return b;
}

}  // namespace silt

#include "shear/cycle_origin.hpp"

#include "silt/fields.hpp"

namespace silt::shear {

FieldId cycle_origin_field() {
  static const FieldId id = find_field("box_cycle_origin")->id;
  return id;
}

CycleOrigin cycle_origin(const Model& m, const State& s) {
  const std::vector<double>& f = s.module_field(cycle_origin_field());
  if (f.size() != 3) return CycleOrigin{0, 0, m.box_control.cycle_omega};
  return CycleOrigin{f[0], f[1], f[2]};
}

void cycle_origin_stage(const Model& m, State& s) {
  CycleOrigin o = cycle_origin(m, s);
  const double w = m.box_control.cycle_omega;
  if (o.omega != w) o = CycleOrigin{s.t, o.phase(s.t), w};
  s.module_field(cycle_origin_field()).assign({o.t0, o.phase0, o.omega});
}

}  // namespace silt::shear

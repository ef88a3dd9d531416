// The stages of a deforming box. In a step, box_drift before the grains' drift and box_kick
// after their kick:
//
//   choose_dt -> box_drift -> kick_drift ... kick -> box_kick
//
// and for the forces of the first state, box_stress after the pair forces. Under an imposed rate
// (steerable), impose_shear_rate writes it into the state at the start of both, before anything
// reads it: the one place the model's rate becomes the state's while stepping.
#include <cmath>

#include "dem/escaped.hpp"
#include "graph/adders.hpp"
#include "shear/cycle_origin.hpp"
#include "shear/stages.hpp"
#include "silt/text.hpp"

namespace silt::graph {
namespace {

const Access kStressReads = {fid::box,        fid::pair_f,         fid::particle_v,
                             fid::particle_x, fid::particle_inv_m, fid::particle_frozen,
                             fid::nbr_start,  fid::pair_j};

// The contact and kinetic stresses of the state (it leaves those of the axes it does not measure
// as they were: it reads them).
int add_box_stress(GraphBuilder& b) {
  Access reads = kStressReads;
  reads.push_back(fid::box_stress);
  reads.push_back(fid::shear_stress);
  return b.add("box_stress", &shear::box_stress, reads, {fid::box_stress, fid::shear_stress});
}

}  // namespace

void add_shear_stages(GraphBuilder& b) {
  const Model& m = b.model();
  // With solved velocities (a paste), the box's strain rates are solved too: no box kick.
  const bool box_stage = shear::box_stage_on(m) && !m.velocities_solved;
  if (b.phase() == Phase::kRefresh || b.phase() == Phase::kResolve) {
    // The stresses the box's next half kick uses, from the forces made again (the same values for
    // forces left as they were: the state's own pair forces and velocities).
    if (!box_stage) return;
    const int st = add_box_stress(b);
    b.after(st, b.find("contact_forces"), "the contact stress of the pair forces made again");
    return;
  }
  int rate = -1;
  if (m.shear.on && !m.shear.stress_controlled) {
    rate = b.add("impose_shear_rate", &shear::impose_shear_rate, {}, {fid::shear_rate});
    b.light(rate);
  }
  if (b.phase() == Phase::kSetup) {
    if (rate >= 0) b.after(b.find("contact_forces"), rate, "the relative velocities at contact under the imposed rate");
    if (!box_stage) return;
    const int st = add_box_stress(b);
    b.after(st, b.find("contact_forces"), "the contact stress of the first state's pair forces");
    return;
  }
  // The cycles' phase under a new w goes on from where it was, before anything imposes it.
  const FieldId origin_field = shear::cycle_origin_field();
  int origin = -1;
  if (m.box_control.on && m.box_control.cycle != StressCycle::kNone) {
    origin = b.add("cycle_origin", &shear::cycle_origin_stage, {fid::t, origin_field}, {origin_field});
    b.light(origin);
  }
  const int drift = b.add("box_drift", &shear::box_drift,
                          {fid::t, fid::dt, fid::box, fid::box_rate, fid::box_stress, fid::shear_stress,
                           fid::shear_rate, fid::le_displacement, fid::shear_strain, fid::nbr_strain, origin_field},
                          {fid::box, fid::box_rate, fid::shear_rate, fid::box_stretch, fid::le_displacement,
                           fid::shear_strain, fid::nbr_strain});
  b.after(drift, b.find("choose_dt"), "moves the box by this step's dt");
  if (rate >= 0) b.after(drift, rate, "shears the box at the imposed rate");
  if (origin >= 0) b.after(drift, origin, "its half kick imposes the stresses of the cycles' phase");
  // depends on: the new lengths (box_stretch) and shear rate, which the grains follow.
  const int grains = b.find(m.velocities_solved ? "drift" : "kick_drift");
  b.after(grains, drift, "the grains follow the affine flow of the box's drift");
  b.diagnose(event::kBoxCollapse, [](const Model& mm, const State& s, const EventSlot& e, StepFailure& f) {
    f.stage = "box_drift";
    f.parameter = "box.pressure";
    const std::string axis(1, "xyz"[e.first()]);
    if (!std::isfinite(e.value()) || e.value() > 2 * mm.interaction_range()) {
      // Not a collapse: the box's rate (or the Lees-Edwards shift) overflowed.
      f.parameter = "box.mass_factor";
      f.message = "the box along " + axis + " is no longer finite (" + format_number(e.value(), 4) +
                  "): the stresses on it overflowed; reduce the loads or raise box.mass_factor";
      return;
    }
    f.message = "the box length along " + axis + " fell to " + format_number(e.value(), 4) +
                ", below twice the interaction range " + format_number(2 * mm.interaction_range(), 4);
    // (grains that left through an open face let the box close on nothing: not the pressure's fault)
    if (const std::string out = dem::escaped_grain(mm, s); !out.empty()) {
      f.parameter = "walls";
      f.message += ": " + out + "; " + dem::kEscapeAdvice;
      return;
    }
    f.message += ": use more grains or a lower box.pressure";
  });
  if (!box_stage) return;
  const int kick =
      b.add("box_kick", &shear::box_kick,
            [&] {
              Access r = kStressReads;
              for (FieldId f : std::initializer_list<FieldId>{fid::t, fid::dt, fid::box_rate, fid::shear_rate,
                                                              fid::box_stress, fid::shear_stress, origin_field})
                r.push_back(f);
              return r;
            }(),
            {fid::box_stress, fid::shear_stress, fid::box_rate, fid::shear_rate});
  b.after(kick, b.find("kick"), "kinetic stress uses the full-step velocities; contact stress the new pair forces");
  if (origin >= 0) b.after(kick, origin, "its half kick imposes the stresses of the cycles' phase");
}

}  // namespace silt::graph

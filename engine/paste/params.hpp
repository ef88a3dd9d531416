// The parameters of a lubricated paste (Peyneau 2009 sec. 1.5 and 2.2), compiled from the
// [lubrication] table of a scene by the paste module (paste/module.cpp).
#pragma once

#include <vector>

#include "paste/lubrication_laws.hpp"
#include "paste/memory.hpp"
#include "silt/linalg.hpp"
#include "silt/model.hpp"

namespace silt::paste {

// How the grains' velocities follow from the forces each step.
enum class Stepper {
  kQuasiStatic,  // Xi V = F_cont + F_ext (eq. 2.19): no inertia
  kInertial,     // (M/dt + Xi) V(t + dt) = M V(t) / dt + F: the grains' inertia kept
};

struct PasteParams {
  double eta = 0;           // liquid viscosity [Pa s] (steerable)
  double h_min_over_a = 0;  // roughness cutoff / largest diameter (steerable)
  double h_max_over_a = 0;  // connection range / largest diameter
  double a = 0;             // largest diameter [m]
  Cutoff cutoff = Cutoff::kLinear;
  Stepper stepper = Stepper::kQuasiStatic;
  linalg::SolverSettings solver;
  // factor_pcg: connections with a gap below this (in units of a) enter the preconditioner's
  // factor whole, the others by their diagonal blocks only (ResistanceSystem::sparsified);
  // h_max / a or more: the whole matrix.
  double factor_gap_over_a = 0.5;
  // factor_pcg: the factor leaves out every coupling of a grain's rotation (to the translations,
  // the box and the other rotations) but its own diagonal block (ResistanceSystem::sparsified):
  // in 3D a factor a quarter the size, for more CG iterations (lubrication.factor_rotations).
  bool own_rotations = false;
  // factor_pcg: the rows of G along which a connection resists more than this times its xi_T
  // form the coarse space of a linalg::CoarseCorrection around the factor (stiff_directions); 0: none.
  double coarse_ratio = 0;
  // The grains' stress (contacts and lubrication) to this relative accuracy: a solve whose
  // velocities leave it less accurate is taken further (lubrication.stress_tolerance; 0: the
  // residual's tolerance alone).
  double stress_tolerance = 0;
  // A Stokes drag 6 pi eta r on every grain's translation and 8 pi eta r^3 on its rotation
  // (LF_DEM's choice): makes Xi definite without pinning; off by default (the thesis has none).
  bool stokes_drag = false;
  // Contact forces linearised into the solve, (Xi + dt K) V = F (paste/contact_stiffness.hpp);
  // off: explicit, from the configuration (eq. 2.19).
  bool implicit_contacts = false;
  // The adaptive step of sec. 2.2.4 [s]: from dt_initial, multiplied by dt_growth each step
  // while no diagonal entry of Xi and no entry of the right-hand side changed by more than
  // dt_change (relative to its largest entry), else shrunk by dt_change / change (at least
  // 1/10); always within [dt_min, dt_max]. And at most drift_max times r_i / |V_i| for every
  // grain (V relative to the affine flow): no grain moves more than that fraction of its radius in
  // a step (0: no such bound).
  double time_unit = 0;  // eta / P, or 1 / |gammadot| without a pressure [s]
  // The fastest of the time unit, 1 / |gammadot| and the cycles' 1 / w [s] (0 without any): the
  // adaptive step is chosen under it, and a steered viscosity, pressure or rate that lowers it cuts
  // the step in proportion (paste_dt).
  double step_scale = 0;
  double dt_initial = 0, dt_min = 0, dt_max = 0, dt_growth = 1.2, dt_change = 0.01, drift_max = 0.05;
  bool fixed_dt = false;  // lubrication.dt: dt_initial always
  // The dry contact laws, restored for the dry compression of procedure O (the paste's own have
  // no dashpots: the liquid dissipates).
  ContactParams dry_contact;
  std::vector<ContactParams> dry_pair_contact;
  // What the run will take beyond the grains (paste/memory.hpp), estimated once compiled.
  PasteMemory memory;

  LubricationLaw law() const { return {eta, h_min_over_a * a, h_max_over_a * a, cutoff}; }
};

}  // namespace silt::paste

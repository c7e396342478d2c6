// Where the energy of a swimming stroke goes (docs/ENERGY.md).
//
// Over every step of length h the meter adds h times each power, with the
// velocities the step moved the body with (qvel after the step) and the
// forces it moved it against:
//   active moments  P_q = sum over link q's hinges of qfrc_actuator . qdot;
//                   in the Stokes mode with the moments' trapezoid over
//                   the step, (f_n + f_(n+1)) / 2: the active moments
//                   follow the link models' deflections, continuous in
//                   time, and the step's backward Euler, which takes them
//                   at the step's end, would otherwise book as the
//                   actuators' work the k dtheta0^2 / 2 per step that a
//                   jump of the rest angle dissipates
//   fluid           P_f = -sum over the drag segments of (F . v_c + T_c . w)
//                   (ipmc::StepFluidPower_W: the fluid model itself)
//   hinge damping   P_c = sum over the dofs of c qdot^2 (the joints'
//                   `damping`, not the paper's plant: docs/ENERGY.md); in
//                   the inertial mode (MuJoCo's Euler or implicit step,
//                   spring at the step's start, damping c_eff at its end,
//                   ipmc::StepDamping) (c_eff - k h / 2) qdot^2 per
//                   joint, what the step dissipates: the explicit spring
//                   puts in k dq^2 / 2 per step
//   time stepping   what the step leaves of the balance. Inertial: the
//                   kinetic energy's step error dv^T M dv / 2 per step
//                   (M (v_(n+1) - v_n) = h F, booked with v_(n+1)). The
//                   Stokes step's backward Euler takes the springs and the
//                   moments at the step's end: P_h = sum over the joints of
//                   k h qdot^2 / 2 - sum over the links' hinges of
//                   qdot (f_(n+1) - f_n) / 2 = qdot k (dq - dtheta0) / 2,
//                   which vanishes for rest angles that change smoothly
//                   (docs/ENERGY.md gives its size).
//   inertial, flexible links (the IPMC actuators' first-order hold,
//                   ipmc::LinkMomentHold: the step applies
//                   f = f_n + w (f_(n+1) - f_n)): the moments' trapezoid
//                   (f_n + f_(n+1)) / 2 . qdot as the active moments,
//                   the physical c qdot^2 as the damping, and as stepping
//                   dv^T M dv / 2 plus, per joint,
//                   h [(c_eff - c - k h / 2) qdot^2 - (w - 1/2) (f_(n+1)
//                   - f_n) qdot] = h (c_eff - c - k h / 2) qdot (qdot -
//                   dtheta0 / h), which vanishes as the hinges' lag
//                   changes smoothly, as the Stokes step's does.
// and at every cycle boundary the stored energy, the hinges' elastic
// energy sum 1/2 k (q - q_spring)^2 plus, with inertia, the kinetic
// energy 1/2 qdot^T M qdot. Over a cycle
//   W_actuators = W_fluid + W_damping + W_stepping
//                 + (stored energy at its end - at its start)
// (up to the drag's power taken with the step's end velocity), which over a steady
// (periodic) cycle is W_fluid + W_damping + W_stepping.
//
// From the means over the chosen cycles (metrics.from_cycle):
//   Lighthill's efficiency  eta = D_tow(U) U / P_f, D_tow the drag of the
//                           straightened body towed along its axis at the
//                           mean speed U, from the same drag model
//                           (ipmc::FluidFacts::towing_drag_N_s_m; Lighthill 1975,
//                           "Mathematical Biofluiddynamics", ch. 3)
//   cost of transport       P_actuators / |U| [J/m], the actuators' work
//                           per distance swum
// With the electrical model on (MeasureElectrical, sim/core/electrical.h),
// also each link's electrical power <V I>, the voltage the step held (the
// controller's clamped output) integrated exactly over the step through
// the link's R_s + (R_p || C), and
//   electromechanical efficiency  P_actuators / P_electrical
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

#include "sim/core/electrical.h"
#include "sim/core/swim_meter.h"

namespace ipmc {

// Mean powers over one cycle or over several [W].
struct EnergyPowers {
  std::vector<double> actuator_power_W;  // per link
  double actuator_power_W_total = 0.0;
  double fluid_power_W = 0.0;
  double hinge_damping_power_W = 0.0;
  double stepping_power_W = 0.0;
  // With the electrical model (else empty and 0).
  std::vector<double> electrical_power_W;  // per link
  double electrical_power_W_total = 0.0;
};

struct EnergyCycle : EnergyPowers {
  double elastic_energy_J = 0.0;         // the hinges', mean over the cycle
  double stored_energy_change_J = 0.0;   // elastic and kinetic, end minus start
  double lighthill_efficiency = 0.0;     // with the cycle's own speed
  double cost_of_transport_J_m = 0.0;    // the cycle's work over its displacement
  double electromechanical_efficiency = 0.0;  // actuator over electrical power; 0 without
};

struct EnergyMetrics : EnergyPowers {
  std::vector<EnergyCycle> per_cycle;    // every cycle
  int from_cycle = 1;                    // the means below are over cycles >= this
  double elastic_energy_J = 0.0;
  double towing_drag_N = 0.0;            // the straightened body at the mean speed
  double lighthill_efficiency = 0.0;
  double cost_of_transport_J_m = 0.0;
  bool electrical = false;               // the electrical model was on
  double electromechanical_efficiency = 0.0;
};

class EnergyMeter {
 public:
  // The links' hinges from d's IPMC actuators, the drag from its RFT model
  // (no drag: no fluid power, efficiencies 0), which must outlive the
  // meter (the coupling attached to d). Marks the start of the run.
  EnergyMeter(const mjModel* m, const mjData* d);

  // Turns the electrical model on (when config.enabled): link q's electrode
  // area is link_lengths_mm[q] x config.electrode_width_mm. Throws
  // FieldError for a bad config.
  void MeasureElectrical(const ElectricalConfig& config, const std::vector<double>& link_lengths_mm);

  // After every step.
  void Observe(const mjModel* m, const mjData* d);
  // At the end of each cycle.
  void EndCycle(const mjModel* m, const mjData* d);
  // Efficiency and cost of transport with the swim's per-cycle
  // displacements and its mean speed over the cycles from `from_cycle`
  // (1-based), over which the means are taken.
  EnergyMetrics Finish(const SwimMetrics& swim, double period_s, int from_cycle) const;
  // The dofs of each link's hinges, root hinge first; none without the
  // IPMC coupling.
  const std::vector<std::vector<int>>& LinkDofs() const { return link_dofs_; }

 private:
  double StoredEnergy_J(const mjModel* m, const mjData* d);
  static double ElasticEnergy_J(const mjModel* m, const mjData* d);
  // The inertial step's kinetic-energy error dv^T M dv / 2 over the step
  // just taken; moves the step's start to its end.
  double KineticStepError_J(const mjModel* m, const mjData* d);
  // Observe for an inertial step with the actuators' first-order hold:
  // books the active moments' trapezoid and the physical damping, returns
  // the step's stepping energy [J] (above).
  double FirstOrderHoldStep(const mjModel* m, const mjData* d);
  // Observe's fluid, elastic and electrical shares and the time.
  void ObserveFluidAndElectrical(const mjModel* m, const mjData* d);

  bool attached_ = false;  // d has the coupling
  bool drag_ = false;      // and a fluid
  std::vector<std::vector<int>> link_dofs_;
  bool inertial_ = true;
  // Inertial with MuJoCo's Euler or implicit integrator: the damping the
  // step dissipates is c_eff - k h / 2 (ipmc::StepDamping).
  bool implicit_damping_ = true;
  // Inertial with the IPMC actuators' first-order hold (flexible links,
  // ipmc::LinkMomentHold): the physical c per dof.
  bool first_order_hold_ = false;
  std::vector<double> physical_damping_;
  std::vector<double> step_damping_;  // per dof, as the step takes it [N m s/rad]
  std::vector<double> step_start_velocity_;  // qvel at the step's start
  double towing_drag_N_per_m_s_ = 0.0;  // the drag is linear in the speed
  // The running cycle's energies [J] and time [s].
  std::vector<double> actuator_J_;
  double fluid_J_ = 0.0, damping_J_ = 0.0, stepping_J_ = 0.0, elastic_J_s_ = 0.0, time_s_ = 0.0;
  double cycle_start_stored_J_ = 0.0;
  std::vector<EnergyCycle> cycles_;
  std::vector<double> scratch_;
  // Stokes: each dof's active moment at the step's start (the last step's
  // end) [N m].
  std::vector<double> step_start_moment_N_m_;
  // The electrical model: per link its network and the running cycle's
  // electrical energy [J]; empty when off.
  std::vector<IpmcImpedance> impedances_;
  std::vector<double> electrical_J_;
};

}  // namespace ipmc

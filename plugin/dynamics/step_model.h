// The model Step steps: the user's model with the integrator and the
// hinges' damping the coupling chooses for it (docs/ENERGY.md, RUNS.md).
//
// MuJoCo's Euler step (and its implicit one) takes a joint's spring at the
// step's start and its damping at the step's end:
//   M (v_(n+1) - v_n) = h (f - k (q_n - q_0) - c v_(n+1)),
//   q_(n+1) = q_n + h v_(n+1).
// In the massless limit (M -> 0, the relaxation of a hinge of lag c / k)
// with the input f held over the step, with e = q - q_0 - f / k,
//   e_(n+1) = (1 - k h / c) e_n,
// a decay that is only first-order right, rings for k h / c > 1 and grows
// for k h / c > 2. Giving the step the damping
//   c_eff = k h / (1 - exp(-k h / c))
// makes it e_(n+1) = exp(-k h / c) e_n: the exact solution of
// c de/dt = -k e over the step. For k h / c << 1, c_eff = c + k h / 2
// + O(k^2 h^2 / c) (the trapezoid); for k h / c >> 1, c_eff -> k h
// (backward Euler: the hinge reaches its rest angle in one step,
// L-stable). With the mass, the step of a hinge of inertia J is stable
// for h^2 k < 4 J + 2 h c_eff, which c_eff >= k h makes hold for every h.
//
// The energy: the explicit spring's work over the step is the elastic
// energy's loss plus k dq^2 / 2, so the step dissipates
// (c_eff - k h / 2) v_(n+1)^2 h at the hinge (with r = exp(-k h / c),
// (k h / 2) (1 + r) / (1 - r) v^2 h is the elastic energy k e_n^2 (1 - r^2)
// / 2 that the exact relaxation loses). EnergyMeter books that as the
// hinges' damping; it tends to c v^2 for k h / c << 1.
//
// With the input held, the step of a stiff hinge (k h / c >> 1, the
// flexible links' sub-segments) relaxes the jump of the rest angle that
// each step's new input makes, and (c_eff - k h / 2) v^2 ~ k h v^2 / 2 is
// that jump's dissipation, first order in h. For flexible links the IPMC
// actuators therefore apply the moment of a rest angle moving linearly
// over the step (IpmcActuators::Update, with the physical c that
// MakeStepModel returns), with which the same c_eff relaxes the massless
// hinge exactly, and EnergyMeter books c v^2.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <vector>

#include "ipmc_swim/fields.h"

namespace ipmc {

// c_eff above [N m s/rad] (or [N s/m] for a slide joint) for the physical
// damping c >= 0, stiffness k >= 0 and step h > 0; c for k = 0 (no spring),
// k h for c = 0.
double EulerHingeDamping(double damping, double stiffness, double timestep_s);

// The damping the step dissipates at a joint whose step damping is
// `step_damping` (c_eff): step_damping - k h / 2.
double EulerDissipatedDamping(double step_damping, double stiffness, double timestep_s);

// Whether m's step takes its joints' damping as c_eff: Euler or implicit
// integrator.
bool StepDampsImplicitly(const mjModel* m);

// Switches m from MuJoCo's implicit integrator to its Euler integrator
// where the two treat the same forces implicitly: MuJoCo 2.2's implicit
// step differs from Euler only in the velocity derivatives of the
// actuator forces (velocity gains and biases), of tendon damping and of
// its own fluid model, while Euler too integrates the joints' damping
// implicitly; the callback forces are explicit in both. So with none of
// those three in the model Euler gives the same stability at 0.4 of the
// cost of a step (docs/RUNS.md, "Time step and integrator"); a gait's
// servos have velocity gains and keep implicit. Returns true if it
// switched.
bool UseEulerWhereImplicitAddsNothing(mjModel* m);

struct ModelCopyDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};

// The model Step steps d with.
struct StepModel {
  std::unique_ptr<mjModel, ModelCopyDeleter> model;
  // The joints' physical damping c per dof (the user's model's) when the
  // step's dof_damping holds c_eff, else empty.
  std::vector<double> physical_damping;
};

// A copy of m that, stepped in `dynamics` by mj_step (inertial) or the
// Stokes stepper, gives each spring hinge and slide joint c_eff for the
// Euler or implicit integrator at m->opt.timestep (inertial dynamics
// only), then uses Euler where implicit adds nothing.
StepModel MakeStepModel(const mjModel* m, Dynamics dynamics);

// Makes step's model that copy of m again, from m's fields as they are
// now (Step calls it before every step, so a host that changes m between
// steps, e.g. its actuators' gains or its timestep, steps with the change,
// as under mj_step). m must be the model step was made from (same sizes).
void RefreshStepModel(StepModel* step, const mjModel* m, Dynamics dynamics);

}  // namespace ipmc

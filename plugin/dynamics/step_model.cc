#include "plugin/dynamics/step_model.h"

#include <cmath>
#include <cstring>

namespace ipmc {

double EulerHingeDamping(double damping, double stiffness, double timestep_s) {
  if (!(stiffness > 0)) return damping;
  const double spring_step = stiffness * timestep_s;  // k h
  // 1 - exp(-k h / c) without cancellation for k h / c << 1; 1 for c = 0.
  const double decayed = damping > 0 ? -std::expm1(-spring_step / damping) : 1.0;
  return spring_step / decayed;
}

double EulerDissipatedDamping(double step_damping, double stiffness, double timestep_s) {
  return step_damping - 0.5 * stiffness * timestep_s;
}

bool StepDampsImplicitly(const mjModel* m) {
  return m->opt.integrator == mjINT_EULER || m->opt.integrator == mjINT_IMPLICIT;
}

bool UseEulerWhereImplicitAddsNothing(mjModel* m) {
  if (m->opt.integrator != mjINT_IMPLICIT) return false;
  if (m->opt.density > 0 || m->opt.viscosity > 0) return false;
  for (int t = 0; t < m->ntendon; ++t) {
    if (m->tendon_damping[t] != 0) return false;
  }
  for (int a = 0; a < m->nu; ++a) {
    // gain = gainprm[0] + gainprm[1] length + gainprm[2] velocity (affine),
    // bias = biasprm[0] + biasprm[1] length + biasprm[2] velocity.
    const bool gain_velocity =
        m->actuator_gaintype[a] == mjGAIN_AFFINE && m->actuator_gainprm[mjNGAIN * a + 2] != 0;
    const bool bias_velocity =
        m->actuator_biastype[a] == mjBIAS_AFFINE && m->actuator_biasprm[mjNBIAS * a + 2] != 0;
    if (gain_velocity || bias_velocity) return false;
  }
  m->opt.integrator = mjINT_EULER;
  return true;
}

void RefreshStepModel(StepModel* step, const mjModel* m, Dynamics dynamics) {
  mjModel* copy = step->model.get();
  // mj_copyModel(copy, m) without its pointer set-up, which costs twice a
  // bare step of the paper's model: both models have the same sizes, so
  // every array sits at the same offset of their buffers.
  std::memcpy(copy->buffer, m->buffer, m->nbuffer);
  copy->opt = m->opt;
  copy->vis = m->vis;
  copy->stat = m->stat;
  step->physical_damping.clear();
  if (dynamics == Dynamics::kInertial && StepDampsImplicitly(copy)) {
    step->physical_damping.assign(m->dof_damping, m->dof_damping + m->nv);
    for (int j = 0; j < copy->njnt; ++j) {
      if (copy->jnt_type[j] != mjJNT_HINGE && copy->jnt_type[j] != mjJNT_SLIDE) continue;
      mjtNum& damping = copy->dof_damping[copy->jnt_dofadr[j]];
      damping = EulerHingeDamping(damping, copy->jnt_stiffness[j], copy->opt.timestep);
    }
  }
  UseEulerWhereImplicitAddsNothing(copy);
}

StepModel MakeStepModel(const mjModel* m, Dynamics dynamics) {
  StepModel step;
  step.model.reset(mj_copyModel(nullptr, m));
  RefreshStepModel(&step, m, dynamics);  // the coupling's choices
  return step;
}

}  // namespace ipmc

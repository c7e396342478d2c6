#include "sim/core/hinge_damping.h"

#include <cmath>
#include <string>

#include "plugin/mjcf/custom_fields.h"

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

std::vector<double> SetHingeDamping(mjModel* m, double scale, std::optional<Dynamics> dynamics) {
  for (int dof = 0; dof < m->nv; ++dof) m->dof_damping[dof] *= scale;
  if (!dynamics) {
    const std::optional<std::string> text = FindCustomText(m, kAttrDynamics);
    dynamics = text ? ParseDynamics(*text) : Dynamics::kInertial;
  }
  if (*dynamics != Dynamics::kInertial || !StepDampsImplicitly(m)) return {};
  std::vector<double> physical_damping(m->dof_damping, m->dof_damping + m->nv);
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    mjtNum& damping = m->dof_damping[m->jnt_dofadr[j]];
    damping = EulerHingeDamping(damping, m->jnt_stiffness[j], m->opt.timestep);
  }
  return physical_damping;
}

}  // namespace ipmc

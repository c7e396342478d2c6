#include "ipmc_swim/resistance.h"

#include <Eigen/Core>
#include <memory>
#include <stdexcept>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

RftDragOverrides OverridesOf(const ResistanceSettings& settings) {
  RftDragOverrides overrides;
  if (!settings.fluid_model.empty()) overrides.fluid_model = settings.fluid_model;
  if (!settings.coefficients.empty()) {
    overrides.model = ParseCoefficientModel(settings.coefficients);
  }
  for (const auto& [field, value] : settings.fluid_parameters) {
    overrides.fluid_parameters[field] = value;
  }
  return overrides;
}

// T_b, the motion [w; v] about body b's reference point c (the subtree
// centre of mass of its root, where the fluid gives its resistance) of
// the rigid motion [w; v_0] about the origin: v_c = v_0 + w x c.
Matrix6 FromOrigin(const mjModel* m, const mjData* d, int body) {
  const Eigen::Vector3d c(d->subtree_com + 3 * m->body_rootid[body]);
  Matrix6 t = Matrix6::Identity();
  t.bottomLeftCorner<3, 3>() = -CrossMatrix(c);
  return t;
}

}  // namespace

std::array<double, 36> RigidBodyResistance(const mjModel* m, const mjData* d,
                                           const ResistanceSettings& settings) {
  const RftDragOverrides overrides = OverridesOf(settings);
  const std::optional<RftDragConfig> config = RftDragConfig::FromModel(m, overrides);
  if (!config) {
    throw std::invalid_argument(std::string("resistance: the model has no ") + kAttrViscosity +
                                " (> 0 Pa s): no fluid acts on it");
  }
  const RftDrag segments(m, *config);
  const std::unique_ptr<Fluid> fluid = MakeFluid(m, segments, overrides);
  mjData* pose = mj_makeData(m);
  mju_copy(pose->qpos, d->qpos, m->nq);
  mj_kinematics(m, pose);
  mj_comPos(m, pose);
  // R_0 = sum over body pairs of T_a^T S_ab T_b, in [w; v] about the origin:
  // the drag wrench [torque; force] is -R_0 [w; v_0].
  Matrix6 r0 = Matrix6::Zero();
  BodyResistanceBlocks<6> blocks;
  fluid->LocalResistances(m, pose, &blocks);
  for (const BodyResistanceBlock<6>& block : blocks) {
    const Matrix6 t = FromOrigin(m, pose, block.body);
    r0 += t.transpose() * block.resistance * t;
  }
  if (const Eigen::MatrixXd* dense = fluid->InteractionResistance(m, pose)) {
    const std::vector<int>& bodies = fluid->InteractingBodies();
    for (size_t a = 0; a < bodies.size(); ++a) {
      for (size_t b = 0; b < bodies.size(); ++b) {
        r0 += FromOrigin(m, pose, bodies[a]).transpose() * dense->block<6, 6>(6 * a, 6 * b) *
              FromOrigin(m, pose, bodies[b]);
      }
    }
  }
  mj_deleteData(pose);
  // Rows [F; T], columns [v; w], the fluid's force: -P R_0 P, P swapping halves.
  std::array<double, 36> out{};
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) out[6 * i + j] = -r0((i + 3) % 6, (j + 3) % 6);
  }
  return out;
}

PropulsionMatrix Propulsion(const std::array<double, 36>& resistance, int axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("propulsion: axis must be 0, 1 or 2");
  const auto at = [&](int row, int column) { return resistance[6 * row + column]; };
  return {-at(axis, axis), -at(axis, 3 + axis), -at(3 + axis, 3 + axis)};
}

}  // namespace ipmc

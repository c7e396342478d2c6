#include "plugin/fluid/ribbon_coefficients.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "plugin/fluid/plate_fluid.h"

namespace ipmc {
namespace {

constexpr int kCoarseAcross = 4, kFineAcross = 6;  // force points across the width
constexpr int kQuadratureRefinement = 4;
constexpr double kBlobOverSpacing = 0.5;

// The plates' resistance over the segments of `reference`, each a plate of
// its own length and `width_m` wide at its reference placement and its own
// rigid body, about the origin.
Eigen::MatrixXd SegmentPlatesResistance(double viscosity_Pa_s,
                                        const std::vector<Segment>& reference, double width_m,
                                        int across) {
  std::vector<SurfaceMesh> meshes;
  meshes.reserve(reference.size());
  for (const Segment& s : reference) {
    meshes.push_back(RectangleMesh(s.length_m, width_m, across, kQuadratureRefinement));
  }
  std::vector<PlacedSurface> plates(reference.size());
  for (size_t i = 0; i < reference.size(); ++i) {
    plates[i] = PlateOnSegment(reference[i], &meshes[i], static_cast<int>(i));
  }
  return ExtrapolatedResistance(plates, static_cast<int>(reference.size()),
                                Eigen::Vector3d::Zero(), kBlobOverSpacing * width_m / across, true,
                                viscosity_Pa_s);
}

// Per segment (rows): broadside force, axial force (both with the whole
// body translating at unit speed) and own rotational drag, at `across`.
Eigen::MatrixXd SegmentDrags(double viscosity_Pa_s, const std::vector<Segment>& reference,
                             double width_m, int across) {
  const int n = static_cast<int>(reference.size());
  const Eigen::MatrixXd r = SegmentPlatesResistance(viscosity_Pa_s, reference, width_m, across);
  Eigen::VectorXd broadside = Eigen::VectorXd::Zero(6 * n), axial = Eigen::VectorXd::Zero(6 * n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d t = reference[i].tangent_W.normalized();
    broadside.segment<3>(6 * i + 3) = Eigen::Vector3d::UnitZ().cross(t);
    axial.segment<3>(6 * i + 3) = t;
  }
  const Eigen::VectorXd broadside_wrench = r * broadside, axial_wrench = r * axial;
  Eigen::MatrixXd drags(n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d t = reference[i].tangent_W.normalized();
    const Eigen::Vector3d c = reference[i].center_W;
    drags(i, 0) = broadside_wrench.segment<3>(6 * i + 3).dot(Eigen::Vector3d::UnitZ().cross(t));
    drags(i, 1) = axial_wrench.segment<3>(6 * i + 3).dot(t);
    // Its own turn about z through c: V = [e_z; -e_z x c] (the velocity of
    // the body point at the origin); the torque about c is T_0 - c x F.
    Eigen::Matrix<double, 6, 1> turn;
    turn << Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ().cross(c);
    const Eigen::Matrix<double, 6, 1> wrench = r.block<6, 6>(6 * i, 6 * i) * turn;
    drags(i, 2) = (wrench.head<3>() - c.cross(Eigen::Vector3d(wrench.tail<3>()))).z();
  }
  return drags;
}

}  // namespace

std::vector<DragCoefficients> PlateCalibratedCoefficients(double viscosity_Pa_s,
                                                          const std::vector<Segment>& reference,
                                                          double width_m) {
  const Eigen::MatrixXd coarse = SegmentDrags(viscosity_Pa_s, reference, width_m, kCoarseAcross);
  const Eigen::MatrixXd fine = SegmentDrags(viscosity_Pa_s, reference, width_m, kFineAcross);
  // The remaining error is first order in the spacing w / k.
  const Eigen::MatrixXd converged =
      (kFineAcross * fine - kCoarseAcross * coarse) / (kFineAcross - kCoarseAcross);
  std::vector<DragCoefficients> xi;
  for (size_t i = 0; i < reference.size(); ++i) {
    const double length_m = reference[i].length_m;
    xi.push_back({converged(i, 0) / length_m, converged(i, 1) / length_m, converged(i, 2)});
  }
  return xi;
}

std::vector<DragCoefficients> FittedToPaperSwim(std::vector<DragCoefficients> calibrated) {
  for (DragCoefficients& xi : calibrated) {
    xi.normal_N_s_m2 *= kFittedBroadsideScale;
    xi.rotation_N_m_s *= kFittedRotationScale;
  }
  return calibrated;
}

}  // namespace ipmc

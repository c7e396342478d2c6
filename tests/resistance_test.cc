// The resistance of a body held rigid (ipmc_swim/resistance.h): a sphere's
// and an ellipsoid's exact values about the origin, R symmetric and
// negative definite under every fluid model (Stokes flow: the reciprocal
// theorem, dissipation), and the rigid helices of Rodenborn, Chen, Swinney,
// Liu & Zhang (PNAS 110, E338-E347, 2013) against their measurements.
#include "ipmc_swim/resistance.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <string>

#include "sim/base/numbers.h"
#include "sim/core/simulation.h"
#include "tests/oberbeck_drag.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;

// R's asymmetry relative to its largest entry: at most 6e-18 measured over
// the helices under every model (rounding in the sums of blocks).
constexpr double kSymmetry = 1e-15;

Matrix6 ResistanceOf(const mjModel* m, const ResistanceSettings& settings = {}) {
  mjData* d = mj_makeData(m);
  const std::array<double, 36> r = RigidBodyResistance(m, d, settings);
  mj_deleteData(d);
  return Eigen::Map<const Matrix6>(r.data());
}

// R symmetric (max |R - R^T| / max |R| below the tolerance) and negative
// definite (every eigenvalue of its symmetric part < 0), or only
// semi-definite (the largest at most 1e-12 of the smallest's magnitude).
void ExpectSymmetricNegativeDefinite(const Matrix6& r, double symmetry_tolerance,
                                     bool semi = false) {
  EXPECT_LT((r - r.transpose()).cwiseAbs().maxCoeff() / r.cwiseAbs().maxCoeff(),
            symmetry_tolerance);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(0.5 * (r + r.transpose()));
  const double largest = eigen.eigenvalues().maxCoeff();
  if (semi) {
    EXPECT_LE(largest, 1e-12 * std::abs(eigen.eigenvalues().minCoeff()));
  } else {
    EXPECT_LT(largest, 0.0);
  }
}

TEST(ResistanceTest, SphereAndEllipsoidAboutTheOrigin) {
  // A sphere of radius a = 1.5 mm centred at c = (10, 0, 0) mm: -6 pi mu a
  // on the diagonal of the force block, the torque about the origin of the
  // force at c (c x F), and -(8 pi mu a^3 + 6 pi mu a c^2) about y and z.
  const ModelPtr sphere = LoadModelString(
      "<mujoco><custom><numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/></custom>"
      "<worldbody><body pos=\"0.01 0 0\"><freejoint/><geom type=\"sphere\" size=\"0.0015\"/>"
      "</body></worldbody></mujoco>");
  const double mu = 1e-3, a = 1.5e-3, c = 1e-2;
  const double k_t = 6 * kPi * mu * a, k_r = 8 * kPi * mu * a * a * a;
  Matrix6 expected = Matrix6::Zero();
  expected.topLeftCorner<3, 3>().diagonal().setConstant(-k_t);
  expected(1, 5) = expected(5, 1) = -k_t * c;  // F_y = -k_t (w x c)_y = -k_t c w_z
  expected(2, 4) = expected(4, 2) = k_t * c;
  expected(3, 3) = -k_r;
  expected(4, 4) = expected(5, 5) = -(k_r + k_t * c * c);
  const Matrix6 r = ResistanceOf(sphere.get());
  EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-12 * k_t);
  // An ellipsoid (3, 2, 1) mm at the origin: Oberbeck's diagonal.
  const ModelPtr ellipsoid = LoadModelString(
      "<mujoco><custom><numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/></custom>"
      "<worldbody><body><freejoint/><geom type=\"ellipsoid\" size=\"0.003 0.002 0.001\"/>"
      "</body></worldbody></mujoco>");
  const OberbeckEllipsoid exact(Eigen::Vector3d(3e-3, 2e-3, 1e-3), mu);
  const Matrix6 e = ResistanceOf(ellipsoid.get());
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(-e(i, i) / exact.Drag_N_s_m(i), 1.0, 1e-9);
    EXPECT_NEAR(-e(3 + i, 3 + i) / exact.RotationalDrag_N_m_s(i), 1.0, 1e-9);
  }
  EXPECT_LT(e.cwiseAbs().maxCoeff() - e.diagonal().cwiseAbs().maxCoeff(), 1e-30);
}

// Rodenborn et al. (2013): helix radius R = 6.3 mm, axial length 130 mm,
// filament radius 0.397 mm; models/helices/ (make_helices.py).
constexpr double kHelixRadius_m = 6.3e-3;
struct Measured {
  const char* pitch_over_radius;
  double thrust, torque, drag;  // their Fig. 2, digitised: / (mu w R^2), (mu w R^3), (mu U R)
};
constexpr Measured kMeasured[] = {{"2.226", 6.26, 131.9, 52.1},
                                  {"3.677", 9.60, 100.8, 47.0},
                                  {"6.509", 11.03, 81.9, 39.4},
                                  {"9.811", 9.57, 72.7, 35.3},
                                  {"15.241", 7.84, 68.1, 34.1}};

struct Scaled {
  double thrust, torque, drag;
};

Scaled HelixNumbers(const Measured& helix, const ResistanceSettings& settings) {
  const ModelPtr m = LoadModelFile(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/helices/rodenborn_" +
                                              std::string(helix.pitch_over_radius) + ".xml");
  const Matrix6 r = ResistanceOf(m.get(), settings);
  ExpectSymmetricNegativeDefinite(r, kSymmetry);
  std::array<double, 36> flat;
  Eigen::Map<Matrix6>(flat.data()) = r;
  const PropulsionMatrix p = Propulsion(flat, 0);  // the helix's axis is x
  const double mu = 1.0, radius = kHelixRadius_m;  // the models' viscosity [Pa s]
  return {std::abs(p.b_N_s) / (mu * radius * radius), p.d_N_m_s / (mu * radius * radius * radius),
          p.a_N_s_m / (mu * radius)};
}

TEST(ResistanceTest, StokesletsMatchRodenbornsHelices) {
  // Regularized Stokeslets at 3 points per mm (converged: 6 per mm moves
  // every number by under 0.5 %, docs/VALIDATION.md): within 8 % of the
  // measurements up to lambda/R = 9.811 and 12 % at 15.241 (the target;
  // measured misses at most -7.0 % and -11.5 %).
  ResistanceSettings settings;
  settings.fluid_model = "stokeslets";
  settings.fluid_parameters = {{"ipmc_fluid_stokeslet_points_per_m", 3000.0}};
  for (const Measured& helix : kMeasured) {
    SCOPED_TRACE(helix.pitch_over_radius);
    const Scaled here = HelixNumbers(helix, settings);
    const double tolerance = std::string(helix.pitch_over_radius) == "15.241" ? 0.12 : 0.08;
    EXPECT_NEAR(here.thrust / helix.thrust, 1.0, tolerance);
    EXPECT_NEAR(here.torque / helix.torque, 1.0, tolerance);
    EXPECT_NEAR(here.drag / helix.drag, 1.0, tolerance);
  }
}

TEST(ResistanceTest, GrayHancockRftMissesTheHelicesTorque) {
  // RFT is local: with Gray & Hancock's coefficients (lambda the pitch) its
  // torque is 0.6 of the measured at lambda/R = 9.811 (43.4 against 72.7);
  // checked so that the documented miss stays what the program prints.
  const Scaled here = HelixNumbers(kMeasured[3], {});
  EXPECT_NEAR(here.torque, 43.4, 0.5);
  EXPECT_NEAR(here.drag / kMeasured[3].drag, 1.0, 0.05);
}

TEST(ResistanceTest, SymmetricAndNegativeDefiniteUnderEveryFluidModel) {
  // The paper's straight strip: definite where its surface carries the
  // force (plates), semi-definite where a line does (rft, stokeslets, and
  // the ribbon's force line): turning about the strip's own axis moves no
  // fluid there.
  const ModelPtr m = LoadModelFile(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/flagellum3.xml");
  for (const char* fluid : {"rft", "stokeslets", "ribbon", "plates"}) {
    SCOPED_TRACE(fluid);
    ResistanceSettings settings;
    settings.fluid_model = fluid;
    const bool centreline = std::string(fluid) != "plates";
    ExpectSymmetricNegativeDefinite(ResistanceOf(m.get(), settings), kSymmetry, centreline);
  }
}

}  // namespace
}  // namespace ipmc::testing

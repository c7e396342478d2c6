// The inertia-free RFT solver of tests/inertia_free_rft.h on its own:
// its kinematics against MuJoCo, its resistance matrix, reciprocal
// strokes (no net motion, Purcell 1977) and a many-segment chain against
// Gray & Hancock's travelling-wave result.
#include "tests/inertia_free_rft.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace ipmc::testing {
namespace {

// ---------------------------------------------------------------------------

// The chain's kinematics and mass distribution, built from the rest
// geometry, against MuJoCo's own forward kinematics at random poses.
TEST(PropulsionCrossCheckTest, ChainKinematicsMatchMujoco) {
  const ModelPtr paper = PaperModel();
  const ModelPtr many = LoadModelString(GenerateFlagellumMjcf(StokesChain(12, 30.0)));
  const ModelPtr head_and_tail =
      LoadModelFile(std::string(IPMC_SWIM_SOURCE_DIR) + "/models/head_and_tail.xml");
  std::mt19937 random(7);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  for (const mjModel* m : {paper.get(), many.get(), head_and_tail.get()}) {
    const Chain chain = ChainFromModel(m);
    ASSERT_EQ(chain.segments.size() + chain.spheres.size(), static_cast<size_t>(m->ngeom));
    ASSERT_EQ(chain.Hinges(), m->njnt - 3);  // all but the planar root
    mjData* d = mj_makeData(m);
    for (int trial = 0; trial < 20; ++trial) {
      for (int i = 0; i < m->nq; ++i) d->qpos[i] = 0.01 * angle(random);
      d->qpos[RootYawQposAdr(m)] = 3.0 * angle(random);
      for (const Hinge& hinge : chain.hinges) d->qpos[hinge.qpos_adr] = angle(random);
      mj_kinematics(m, d);
      mj_comPos(m, d);
      const ChainShape shape = ShapeOf(chain, HingeAngles_rad(chain, d));
      const Eigen::Vector3d root_pos(d->xpos + 3 * kRootBody);
      Eigen::Matrix3d root_rot;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) root_rot(r, c) = d->xmat[9 * kRootBody + 3 * r + c];
      for (size_t i = 0; i < chain.segments.size(); ++i) {
        const int g = chain.segments[i].geom_id;
        const Eigen::Vector3d centre = root_pos + root_rot * shape.segment_centre_m[i];
        const Eigen::Vector3d tangent = root_rot * shape.segment_tangent[i];
        EXPECT_LT((centre - Eigen::Vector3d(d->geom_xpos + 3 * g)).norm(), 1e-13);
        const int axis = m->geom_type[g] == mjGEOM_BOX ? 0 : 2;
        const Eigen::Vector3d mujoco_tangent(d->geom_xmat[9 * g + axis],
                                             d->geom_xmat[9 * g + 3 + axis],
                                             d->geom_xmat[9 * g + 6 + axis]);
        EXPECT_LT((tangent - mujoco_tangent).norm(), 1e-12);
      }
      for (size_t i = 0; i < chain.spheres.size(); ++i) {
        const Eigen::Vector3d centre = root_pos + root_rot * shape.sphere_centre_m[i];
        const int g = chain.spheres[i].geom_id;
        EXPECT_LT((centre - Eigen::Vector3d(d->geom_xpos + 3 * g)).norm(), 1e-13);
      }
      const Eigen::Vector3d com = root_pos + root_rot * CentreOfMass_m(chain, shape);
      EXPECT_LT((com - Eigen::Vector3d(d->subtree_com + 3 * kRootBody)).norm(), 1e-13);
    }
    mj_deleteData(d);
  }
}

// RFT drag dissipates and obeys reciprocity: R is symmetric and negative
// definite. Its diagonal for the straight body is known in closed form:
//   R_xx = -xi_t L,  R_yy = -xi_n L  (segments along x).
TEST(PropulsionCrossCheckTest, ResistanceMatrixIsSymmetricAndDissipative) {
  const ModelPtr m = PaperModel();
  const Chain chain = ChainFromModel(m.get());
  const Eigen::Matrix3d straight =
      ResistanceMatrix(chain, ShapeOf(chain, Eigen::VectorXd::Zero(chain.Hinges())));
  EXPECT_NEAR(straight(0, 0), -chain.xi.tangential_N_s_m2 * chain.length_m,
              1e-12 * std::abs(straight(0, 0)));
  EXPECT_NEAR(straight(1, 1), -chain.xi.normal_N_s_m2 * chain.length_m,
              1e-12 * std::abs(straight(1, 1)));
  // Gray-Hancock coefficients for docs/MODEL.md's water and strip: 2.582e-3, 1.625e-3 N s/m^2.
  EXPECT_NEAR(chain.xi.normal_N_s_m2, 2.582e-3, 1e-6);
  EXPECT_NEAR(chain.xi.tangential_N_s_m2, 1.625e-3, 1e-6);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> angle(-1.2, 1.2);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd q(chain.Hinges());
    for (int j = 0; j < q.size(); ++j) q[j] = angle(random);
    const Eigen::Matrix3d r = ResistanceMatrix(chain, ShapeOf(chain, q));
    EXPECT_LT((r - r.transpose()).norm(), 1e-12 * r.norm());
    const Eigen::Vector3d eigenvalues =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(r).eigenvalues();
    EXPECT_LT(eigenvalues.maxCoeff(), 0.0);
  }
}

// Scallop theorem: a reciprocal stroke (every hinge in phase, so the shape
// goes back and forth along one path) gives no net motion; a travelling
// wave of the same amplitudes does.
TEST(PropulsionCrossCheckTest, ReciprocalStrokesGiveNoNetDisplacement) {
  const ModelPtr m = PaperModel();
  const Chain chain = ChainFromModel(m.get());
  const int n = chain.Hinges();
  const Eigen::VectorXd amplitude = Eigen::VectorXd::Constant(n, 0.6);
  const double period_s = 100.0;
  Eigen::VectorXd in_phase = Eigen::VectorXd::Constant(n, kPi / 2);  // cosines
  Eigen::VectorXd wave(n);
  for (int j = 0; j < n; ++j) wave[j] = -2.0 * j;
  const PlanarPose start;
  const Swim travelling =
      SwimOver(chain, SineStroke(amplitude, wave, 1.0 / period_s), 0.0, period_s, 200, start);
  // q(t) = A cos(w t) is symmetric about t = 0 and T/2, the grid too: the
  // time-symmetric Magnus steps of the second half undo those of the first
  // exactly, so only round-off remains.
  const Swim symmetric =
      SwimOver(chain, SineStroke(amplitude, in_phase, 1.0 / period_s), 0.0, period_s, 200, start);
  // q(t) = A (sin(w t) + 0.4 sin(2 w t)): fast one way, slow back, still
  // reciprocal; zero up to the integrator's O(h^4) error.
  const Swim lopsided = SwimOver(
      chain, SineStroke(amplitude, Eigen::VectorXd::Zero(n), 1.0 / period_s, 0.4 * amplitude), 0.0,
      period_s, 200, start);
  const double symmetric_m = std::hypot(symmetric.com_along_m, symmetric.com_across_m);
  const double lopsided_m = std::hypot(lopsided.com_along_m, lopsided.com_across_m);
  std::printf(
      "travelling wave %.6f mm per cycle; reciprocal: symmetric %.2e mm, lopsided %.2e mm\n",
      travelling.com_along_m * kMToMm, symmetric_m * kMToMm, lopsided_m * kMToMm);
  EXPECT_GT(travelling.com_along_m, 1e-4);  // head first, against the wave (measured 0.383 mm)
  // Measured 4e-14 of the travelling wave's displacement and 6.8e-16 rad.
  EXPECT_LT(symmetric_m, 5e-13 * travelling.com_along_m);
  EXPECT_LT(std::abs(symmetric.yaw_rad), 1e-14);
  // Measured 4.4e-8 with 200 steps per cycle (fourth order in the step).
  EXPECT_LT(lopsided_m, 5e-7 * travelling.com_along_m);
}

// Gray & Hancock (1955), Taylor (1951): an infinite filament carrying
// y = b sin(k x - w t) swims at U = (xi_n / xi_t - 1) (b k)^2 c / 2 to
// second order in b k, per cycle (xi_n / xi_t - 1) (b k)^2 lambda / 2. The
// finite free swimmer recoils sideways and in yaw, which slows it by a few
// percent: 9.0 % with two wavelengths on the body and 3.6 % with four in
// the MuJoCo runs of tests/swimming_test.cc (same chain and wave).
TEST(PropulsionCrossCheckTest, ManySegmentChainMatchesGrayHancock) {
  constexpr int kLinks = 48;
  constexpr double kLength_mm = 32.0;
  constexpr double kBk = 0.1;
  const ModelPtr m = LoadModelString(GenerateFlagellumMjcf(StokesChain(kLinks, kLength_mm)));
  const Chain chain = ChainFromModel(m.get());
  ASSERT_EQ(chain.Hinges(), kLinks - 1);
  const double ratio = chain.xi.normal_N_s_m2 / chain.xi.tangential_N_s_m2;
  std::vector<double> deficits;
  for (double waves : {2.0, 4.0}) {
    const double lambda_mm = kLength_mm / waves;
    const double k_per_mm = 2.0 * kPi / lambda_mm;
    const double dx_mm = kLength_mm / kLinks;
    // Joint angle = curvature x link length: y'' = -b k^2 sin(k x - w t).
    Eigen::VectorXd amplitude = Eigen::VectorXd::Constant(kLinks - 1, kBk * k_per_mm * dx_mm);
    Eigen::VectorXd phase(kLinks - 1);
    for (int j = 0; j < kLinks - 1; ++j) phase[j] = -(j + 1) * k_per_mm * dx_mm;
    // One cycle at 1 Hz: without inertia the displacement per cycle does not
    // depend on the frequency.
    const Swim swim =
        SwimOver(chain, SineStroke(amplitude, phase, 1.0), 0.0, 1.0, 100, PlanarPose());
    const double classical_mm = 0.5 * (ratio - 1.0) * kBk * kBk * lambda_mm;
    const double deficit = 1.0 - swim.com_along_m * kMToMm / classical_mm;
    std::printf("%.0f wavelengths: %.6f mm per cycle, classical %.6f mm, %.2f %% slower\n", waves,
                swim.com_along_m * kMToMm, classical_mm, 100 * deficit);
    deficits.push_back(deficit);
  }
  // Measured 8.88 % and 3.25 % slower (the MuJoCo runs' small extra gap
  // is their inertia and time step). Within the few percent of
  // docs/VALIDATION.md (classical RFT speed), and
  // fading with more wavelengths:
  EXPECT_GT(deficits[0], deficits[1]);
  EXPECT_GT(deficits[1], 0.0);
  EXPECT_LT(deficits[0], 0.10);
  EXPECT_LT(deficits[1], 0.05);
}

// The default job (scenarios/paper.toml: PID, +-6 V clamp, three 100 s
// cycles) against the solver fed with the hinge angles the run recorded.
//
// Sample spacing: 2000 samples per cycle (every 50 ms). Measured on this
// run: recording 20 000 per cycle changes the solver's second-cycle
// displacement by less than 1e-9 relative, 1000 per cycle by 2.4e-8 and 200 per
// cycle by 1.9e-5.
}  // namespace
}  // namespace ipmc::testing

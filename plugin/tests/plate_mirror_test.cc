// The plates' resistance solved by the z-even and z-odd halves of the
// mirror symmetry about the beat plane (SurfaceResistance,
// plugin/fluid/plate_fluid.h) against the full matrix's solve: the same R
// to round-off on the paper's strip bent in its plane (a 1 mm head and
// three 10 mm links of 8 sub-segments, 3 mm wide, each hinge at its own
// angle), with an even and an odd number of force points across (pairs
// only, and points on the plane); and the full solve, unchanged, whenever
// the symmetry is broken (a tilted plate, a plate off the plane, a wall, a
// mesh that is not symmetric); the even half alone, for bodies that move
// in the plane; and both solves against the textbook solve, written out
// from the public pieces.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "plugin/fluid/plate_fluid.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3;  // Pa s
constexpr double kWidth = 3e-3;
constexpr double kPlaneZ = 0.2e-3;  // the strip's plane, off z = 0

// The strip's segments in the plane z = kPlaneZ: the head, then 24
// sub-segments, hinge k turned by its own angle (up to 0.3 rad), every
// segment its own body.
struct BentStrip {
  std::vector<SurfaceMesh> meshes;
  std::vector<PlacedSurface> plates;
  std::vector<Eigen::MatrixXd> self_blocks;  // each plate's own, in its frame
};

BentStrip MakeBentStrip(int across, double blob_m) {
  std::vector<double> lengths = {1e-3};
  for (int k = 0; k < 24; ++k) lengths.push_back(10e-3 / 8);
  BentStrip strip;
  strip.meshes.reserve(lengths.size());
  Eigen::Vector3d root(0, 0, kPlaneZ);
  double angle = 0.0;
  for (size_t k = 0; k < lengths.size(); ++k) {
    angle += 0.3 * std::sin(0.9 * k + 0.4);
    Segment segment;
    segment.tangent_W = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0);
    segment.center_W = root + 0.5 * lengths[k] * segment.tangent_W;
    segment.length_m = lengths[k];
    root += lengths[k] * segment.tangent_W;
    strip.meshes.push_back(RectangleMesh(lengths[k], kWidth, across, 4));
    strip.plates.push_back(PlateOnSegment(segment, &strip.meshes.back(), static_cast<int>(k)));
    if (k % 2 == 1) {
      // Every other plate turned over (its width along -z): the same
      // surface, its force points in another order.
      strip.plates.back().rotation.col(1) *= -1.0;
      strip.plates.back().rotation.col(2) *= -1.0;
    }
    PlacedSurface own;
    own.mesh = &strip.meshes.back();
    strip.self_blocks.push_back(NearestNeighbourBlock(own, own, blob_m, kMu));
  }
  return strip;
}

// max |a_ij - b_ij| / sqrt(b_ii b_jj): each entry against the drags and
// torques of its row and column (R's diagonal is positive), whatever the
// units.
double RelativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const Eigen::VectorXd scale = b.diagonal().cwiseSqrt().cwiseInverse();
  return (scale.asDiagonal() * (a - b) * scale.asDiagonal()).cwiseAbs().maxCoeff();
}

// Measured: at most 3.57e-15 (4 across) and 2.43e-15 (3 across) over the
// moment points and with or without the cached own blocks; asserted
// within 3.6e-14.
TEST(PlateMirrorTest, HalvesMatchTheFullSolveOnTheBentStrip) {
  for (int across : {4, 3}) {
    const double blob_m = 0.5 * kWidth / across;
    const BentStrip strip = MakeBentStrip(across, blob_m);
    ASSERT_TRUE(MirrorSymmetric(strip.plates));
    const int bodies = static_cast<int>(strip.plates.size());
    // A moment point on the plane and one off it (R moved to it).
    for (const Eigen::Vector3d& c :
         {Eigen::Vector3d(2e-3, 1e-3, kPlaneZ), Eigen::Vector3d(2e-3, -1e-3, -0.7e-3)}) {
      for (bool cached : {false, true}) {
        const std::vector<Eigen::MatrixXd> self = cached ? strip.self_blocks
                                                         : std::vector<Eigen::MatrixXd>{};
        const Eigen::MatrixXd halves =
            SurfaceResistance(strip.plates, bodies, c, blob_m, kMu, self);
        const Eigen::MatrixXd full = SurfaceResistance(strip.plates, bodies, c, blob_m, kMu, self,
                                                       std::nullopt, SurfaceSolve::kFullMatrix);
        const double difference = RelativeDifference(halves, full);
        std::printf("%d across, c_z %+.1f mm, %s own blocks: halves against full %.2e\n", across,
                    1e3 * c.z(), cached ? "cached" : "summed", difference);
        EXPECT_LT(difference, 3.6e-14);
      }
    }
  }
}

// A disk flat in the plane: every force point its own image (only the
// x, y forces in the even half, z in the odd one). Measured 7.0e-16;
// asserted within 7e-15.
TEST(PlateMirrorTest, HalvesMatchTheFullSolveOnADiskInThePlane) {
  const SurfaceMesh mesh = DiskMesh(1e-3, 6, 4);
  PlacedSurface disk;
  disk.mesh = &mesh;
  ASSERT_TRUE(MirrorSymmetric({disk}));
  const Eigen::Vector3d c(0.1e-3, 0.2e-3, 0.3e-3);
  const double blob_m = 0.5e-3 / 6;
  const double difference =
      RelativeDifference(SurfaceResistance({disk}, 1, c, blob_m, kMu),
                         SurfaceResistance({disk}, 1, c, blob_m, kMu, {}, std::nullopt,
                                           SurfaceSolve::kFullMatrix));
  std::printf("disk: halves against full %.2e\n", difference);
  EXPECT_LT(difference, 7e-15);
}

// Without the symmetry the full matrix is solved: the same R bit for bit.
void ExpectFullSolve(const std::vector<PlacedSurface>& plates, double blob_m,
                     std::optional<double> wall_z_m) {
  EXPECT_FALSE(MirrorSymmetric(plates, wall_z_m));
  const int bodies = static_cast<int>(plates.size());
  const Eigen::Vector3d c(2e-3, 1e-3, kPlaneZ);
  const Eigen::MatrixXd chosen = SurfaceResistance(plates, bodies, c, blob_m, kMu, {}, wall_z_m);
  const Eigen::MatrixXd full = SurfaceResistance(plates, bodies, c, blob_m, kMu, {}, wall_z_m,
                                                 SurfaceSolve::kFullMatrix);
  EXPECT_EQ(RelativeDifference(chosen, full), 0.0);
}

TEST(PlateMirrorTest, BrokenSymmetrySolvesTheFullMatrix) {
  const int across = 3;
  const double blob_m = 0.5 * kWidth / across;
  {
    SCOPED_TRACE("a plate tilted about its length by 1e-3 rad");
    BentStrip strip = MakeBentStrip(across, blob_m);
    PlacedSurface& plate = strip.plates[5];
    plate.rotation =
        Eigen::AngleAxisd(1e-3, plate.rotation.col(0)).toRotationMatrix() * plate.rotation;
    ExpectFullSolve(strip.plates, blob_m, std::nullopt);
  }
  {
    SCOPED_TRACE("a plate 1 um off the plane");
    BentStrip strip = MakeBentStrip(across, blob_m);
    strip.plates[7].position.z() += 1e-6;
    ExpectFullSolve(strip.plates, blob_m, std::nullopt);
  }
  {
    SCOPED_TRACE("a wall 2 mm below the strip's plane (0.5 mm below its edges)");
    const BentStrip strip = MakeBentStrip(across, blob_m);
    ExpectFullSolve(strip.plates, blob_m, kPlaneZ - 2e-3);
  }
  {
    SCOPED_TRACE("a mesh with one quadrature cell's area changed");
    BentStrip strip = MakeBentStrip(across, blob_m);
    strip.meshes[3].quadrature_area_m2[0] *= 1.0 + 1e-6;
    ExpectFullSolve(strip.plates, blob_m, std::nullopt);
  }
  {
    SCOPED_TRACE("a mesh with one quadrature point moved across");
    BentStrip strip = MakeBentStrip(across, blob_m);
    strip.meshes[3].quadrature_points[0].z() += 1e-9;
    ExpectFullSolve(strip.plates, blob_m, std::nullopt);
  }
}

// The even half alone (kInPlaneHalfWhenSymmetric): R's in-plane entries
// (w_z, v_x, v_y of every body against every body) bit for bit those of
// both halves, every entry of an out-of-plane motion zero, and said so;
// without the symmetry the full solve, bit for bit, and nothing left out.
TEST(PlateMirrorTest, TheInPlaneHalfIsTheHalvesInPlanePart) {
  const int across = 4;
  const double blob_m = 0.5 * kWidth / across;
  BentStrip strip = MakeBentStrip(across, blob_m);
  const int bodies = static_cast<int>(strip.plates.size());
  const Eigen::Vector3d c(2e-3, 1e-3, kPlaneZ);
  bool left_out = false;
  const Eigen::MatrixXd in_plane =
      ExtrapolatedResistance(strip.plates, bodies, c, blob_m, true, kMu, std::nullopt, {}, {},
                             SurfaceSolve::kInPlaneHalfWhenSymmetric, &left_out);
  const Eigen::MatrixXd halves = ExtrapolatedResistance(strip.plates, bodies, c, blob_m, true, kMu);
  EXPECT_TRUE(left_out);
  const auto out_of_plane = [](Eigen::Index i) { return i % 6 < 2 || i % 6 == 5; };
  for (Eigen::Index j = 0; j < halves.cols(); ++j) {
    for (Eigen::Index i = 0; i < halves.rows(); ++i) {
      const double expected = out_of_plane(i) || out_of_plane(j) ? 0.0 : halves(i, j);
      ASSERT_EQ(in_plane(i, j), expected) << "row " << i << ", column " << j;
    }
  }
  // A plate tilted about its length: no symmetry, the whole R.
  strip.plates[5].rotation =
      Eigen::AngleAxisd(1e-3, strip.plates[5].rotation.col(0)).toRotationMatrix() *
      strip.plates[5].rotation;
  const Eigen::MatrixXd tilted =
      ExtrapolatedResistance(strip.plates, bodies, c, blob_m, true, kMu, std::nullopt, {}, {},
                             SurfaceSolve::kInPlaneHalfWhenSymmetric, &left_out);
  EXPECT_FALSE(left_out);
  EXPECT_EQ(RelativeDifference(tilted,
                               ExtrapolatedResistance(strip.plates, bodies, c, blob_m, true, kMu)),
            0.0);
}

// The textbook solve, written out here from the public pieces: the whole
// velocity matrix from NearestNeighbourBlock block by block, the rigid
// motions' velocities M at the force points (u = v + w x (x - c)) and
// their wrenches W (each force point's cell area times M^T), R the
// symmetric part of W A^-1 M by one LU. SurfaceResistance's full solve and
// its mirror halves (each triangular solve started at a body's first
// unknown, plugin/fluid/plate_fluid.h) against it. Measured 3.6e-15
// (full) and 1.8e-15 (halves); asserted within 3.6e-14.
TEST(PlateMirrorTest, SolvesMatchTheTextbookSolve) {
  const int across = 4;
  const double blob_m = 0.5 * kWidth / across;
  const BentStrip strip = MakeBentStrip(across, blob_m);
  const int bodies = static_cast<int>(strip.plates.size());
  const Eigen::Vector3d c(2e-3, 1e-3, kPlaneZ);
  std::vector<int> offset = {0};
  for (const PlacedSurface& plate : strip.plates) {
    offset.push_back(offset.back() + 3 * static_cast<int>(plate.mesh->force_points.size()));
  }
  const int n = offset.back();
  Eigen::MatrixXd velocity(n, n), motion = Eigen::MatrixXd::Zero(n, 6 * bodies);
  Eigen::MatrixXd wrench = Eigen::MatrixXd::Zero(6 * bodies, n);
  for (int t = 0; t < bodies; ++t) {
    for (int s = 0; s < bodies; ++s) {
      velocity.block(offset[t], offset[s], offset[t + 1] - offset[t], offset[s + 1] - offset[s]) =
          NearestNeighbourBlock(strip.plates[t], strip.plates[s], blob_m, kMu);
    }
    const PlacedSurface& plate = strip.plates[t];
    const SurfaceMesh& mesh = *plate.mesh;
    for (size_t j = 0; j < mesh.force_points.size(); ++j) {
      double area_m2 = 0.0;
      for (size_t q = 0; q < mesh.owner.size(); ++q) {
        if (mesh.owner[q] == static_cast<int>(j)) area_m2 += mesh.quadrature_area_m2[q];
      }
      const Eigen::Vector3d x = plate.position + plate.rotation * mesh.force_points[j];
      Eigen::Matrix<double, 3, 6> rigid;  // [w; v] -> v + w x (x - c)
      rigid << -CrossMatrix(x - c), Eigen::Matrix3d::Identity();
      motion.block<3, 6>(offset[t] + 3 * static_cast<int>(j), 6 * plate.body) = rigid;
      wrench.block<6, 3>(6 * plate.body, offset[t] + 3 * static_cast<int>(j)) =
          area_m2 * rigid.transpose();
    }
  }
  const Eigen::MatrixXd projected = wrench * velocity.partialPivLu().solve(motion);
  const Eigen::MatrixXd textbook = 0.5 * (projected + projected.transpose());
  const double full = RelativeDifference(
      SurfaceResistance(strip.plates, bodies, c, blob_m, kMu, {}, std::nullopt,
                        SurfaceSolve::kFullMatrix),
      textbook);
  const double halves =
      RelativeDifference(SurfaceResistance(strip.plates, bodies, c, blob_m, kMu), textbook);
  std::printf("against the textbook solve: full %.2e, halves %.2e\n", full, halves);
  EXPECT_LT(full, 3.6e-14);
  EXPECT_LT(halves, 3.6e-14);
}

}  // namespace
}  // namespace ipmc::testing

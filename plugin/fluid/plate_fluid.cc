#include "plugin/fluid/plate_fluid.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/base/numbers.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

void RequireInRange(double value, double low, double high, const char* what) {
  if (!(value > low && value <= high)) {
    std::ostringstream msg;
    msg << "plate fluid: " << what << " must be in (" << low << ", " << high << "] (got " << value
        << ")";
    throw std::invalid_argument(msg.str());
  }
}

void RequireCount(int value, int high, const char* what) {
  if (value < 1 || value > high) {
    throw std::invalid_argument(std::string("plate fluid: ") + what + " must be in [1, " +
                                std::to_string(high) + "] (got " + std::to_string(value) + ")");
  }
}

// The cells of `cells` equal intervals of [-half, half] cut into `refinement`
// sub-intervals each: the sub-interval centres.
std::vector<double> SubCentres(double half_m, int cells, int refinement) {
  const int n = cells * refinement;
  std::vector<double> centres(n);
  for (int i = 0; i < n; ++i) centres[i] = -half_m + (i + 0.5) * 2.0 * half_m / n;
  return centres;
}

// Each quadrature point's nearest force point (brute force, once per mesh).
void AssignNearest(SurfaceMesh* mesh) {
  mesh->owner.assign(mesh->quadrature_points.size(), -1);
  for (size_t q = 0; q < mesh->quadrature_points.size(); ++q) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < mesh->force_points.size(); ++j) {
      const double d2 = (mesh->quadrature_points[q] - mesh->force_points[j]).squaredNorm();
      if (d2 < best) {
        best = d2;
        mesh->owner[q] = static_cast<int>(j);
      }
    }
  }
}

// The world positions of a placed mesh's points.
std::vector<Eigen::Vector3d> Placed(const PlacedSurface& s, const std::vector<Eigen::Vector3d>& p) {
  std::vector<Eigen::Vector3d> out(p.size());
  for (size_t k = 0; k < p.size(); ++k) out[k] = s.position + s.rotation * p[k];
  return out;
}

// diag(Q, Q, ...) A diag(Q, Q, ...)^T, 3 x 3 blocks.
Eigen::MatrixXd RotateBlocks(const Eigen::MatrixXd& a, const Eigen::Matrix3d& q) {
  Eigen::MatrixXd out(a.rows(), a.cols());
  for (int i = 0; i < a.rows() / 3; ++i) {
    for (int j = 0; j < a.cols() / 3; ++j) {
      out.block<3, 3>(3 * i, 3 * j) = q * a.block<3, 3>(3 * i, 3 * j) * q.transpose();
    }
  }
  return out;
}

}  // namespace

void PlateSettings::Validate() const {
  RequireCount(points_across, kMaxPlatePointsAcross, "the force points across the width");
  RequireCount(quadrature_refinement, kMaxPlateQuadratureRefinement,
               "the quadrature refinement");
  RequireInRange(blob_over_spacing, 0.0, 2.0, "the blob over the force spacing");
  if (!(width_m > 0.0) || !std::isfinite(width_m)) {
    throw std::invalid_argument("plate fluid: the plates' width must be finite and > 0");
  }
  if (!(shape_tolerance_rad >= 0.0) || !std::isfinite(shape_tolerance_rad)) {
    throw std::invalid_argument("plate fluid: the shape tolerance must be finite and >= 0");
  }
  if (!(secant_reach_rad >= 0.0) || !std::isfinite(secant_reach_rad)) {
    throw std::invalid_argument("plate fluid: the secant's reach must be finite and >= 0");
  }
  if (!(fit_tolerance >= 0.0) || !std::isfinite(fit_tolerance)) {
    throw std::invalid_argument("plate fluid: the fit's tolerance must be finite and >= 0");
  }
  if (wall_distance_m && !(*wall_distance_m > 0.5 * width_m && std::isfinite(*wall_distance_m))) {
    std::ostringstream msg;
    msg << "plate fluid: the wall distance must be finite and > half the plates' width "
        << 0.5 * width_m << " m (got " << *wall_distance_m << " m)";
    throw std::invalid_argument(msg.str());
  }
}

int CellsAlong(double length_m, double width_m, int across) {
  return std::max(1, static_cast<int>(std::lround(length_m / (width_m / across))));
}

SurfaceMesh RectangleMesh(double length_m, double width_m, int across, int refinement) {
  const int along = CellsAlong(length_m, width_m, across);
  SurfaceMesh mesh;
  for (double x : SubCentres(0.5 * length_m, along, 1)) {
    for (double z : SubCentres(0.5 * width_m, across, 1)) mesh.force_points.emplace_back(x, 0, z);
  }
  const double area_m2 = length_m * width_m / (along * across * refinement * refinement);
  for (double x : SubCentres(0.5 * length_m, along, refinement)) {
    for (double z : SubCentres(0.5 * width_m, across, refinement)) {
      mesh.quadrature_points.emplace_back(x, 0, z);
      mesh.quadrature_area_m2.push_back(area_m2);
    }
  }
  AssignNearest(&mesh);
  return mesh;
}

SurfaceMesh DiskMesh(double radius_m, int rings, int refinement) {
  // Ring i spans [i, i + 1] dr and holds the nearest whole number of
  // cells to its mid-circumference over dr (at least 3): cells close to
  // square, the rim exact.
  SurfaceMesh mesh;
  const double dr_m = radius_m / rings;
  for (int i = 0; i < rings; ++i) {
    const int cells = std::max(3, static_cast<int>(std::lround(2.0 * kPi * (i + 0.5))));
    const double dtheta = 2.0 * kPi / cells;
    for (int j = 0; j < cells; ++j) {
      const int owner = static_cast<int>(mesh.force_points.size());
      double area_m2 = 0.0;
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int a = 0; a < refinement; ++a) {
        const double r0 = (i + static_cast<double>(a) / refinement) * dr_m;
        const double r1 = r0 + dr_m / refinement;
        for (int b = 0; b < refinement; ++b) {
          const double theta = (j + (b + 0.5) / refinement) * dtheta;
          // The sub-cell's centroid radius and area.
          const double rc = 2.0 / 3.0 * (r1 * r1 * r1 - r0 * r0 * r0) / (r1 * r1 - r0 * r0);
          const double cell_m2 = 0.5 * (r1 * r1 - r0 * r0) * dtheta / refinement;
          mesh.quadrature_points.emplace_back(rc * std::cos(theta), rc * std::sin(theta), 0);
          mesh.quadrature_area_m2.push_back(cell_m2);
          mesh.owner.push_back(owner);
          area_m2 += cell_m2;
          centroid += cell_m2 * mesh.quadrature_points.back();
        }
      }
      mesh.force_points.push_back(centroid / area_m2);
    }
  }
  return mesh;
}

namespace {

// `count` zero matrices, each made in place (a vector's fill would copy
// the first into each).
std::vector<Eigen::MatrixXd> ZeroMatrices(size_t count, Eigen::Index rows, Eigen::Index cols) {
  std::vector<Eigen::MatrixXd> matrices(count);
  for (Eigen::MatrixXd& matrix : matrices) matrix.setZero(rows, cols);
  return matrices;
}

// A placed source's quadrature points in the world, grouped by owner
// (owner j's are [start[j], start[j + 1])), each weighted by its area
// over 8 pi mu.
struct OwnedQuadrature {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weight;
  std::vector<int> start;
};

OwnedQuadrature Owned(const PlacedSurface& source, double viscosity_Pa_s) {
  const SurfaceMesh& mesh = *source.mesh;
  const int owners = static_cast<int>(mesh.force_points.size());
  OwnedQuadrature owned;
  owned.start.assign(owners + 1, 0);
  for (int owner : mesh.owner) ++owned.start[owner + 1];
  for (int j = 0; j < owners; ++j) owned.start[j + 1] += owned.start[j];
  owned.points.resize(mesh.owner.size());
  owned.weight.resize(mesh.owner.size());
  std::vector<int> next(owned.start.begin(), owned.start.end() - 1);
  const double scale = 1.0 / (8.0 * kPi * viscosity_Pa_s);
  for (size_t q = 0; q < mesh.owner.size(); ++q) {
    const int k = next[mesh.owner[q]]++;
    owned.points[k] = source.position + source.rotation * mesh.quadrature_points[q];
    owned.weight[k] = scale * mesh.quadrature_area_m2[q];
  }
  return owned;
}

// The velocity matrix's rows of the targets x (world points, 3 rows each)
// against the columns of `source`'s force points (3 each), at each blob:
// (1 / 8 pi mu) sum over the quadrature points y owned by force point j of
// S_eps(x_i - y) dA(y). Two targets at a time, the sums of each owner's
// points in order.
std::vector<Eigen::MatrixXd> KernelSums(const std::vector<Eigen::Vector3d>& x,
                                        const OwnedQuadrature& source,
                                        const std::vector<double>& blobs_m) {
  using Pair = Eigen::Array2d;
  constexpr int kBlobs = 2;  // blobs summed in one pass
  const int targets = static_cast<int>(x.size());
  const int owners = static_cast<int>(source.start.size()) - 1;
  std::vector<Eigen::MatrixXd> blocks(blobs_m.size());  // every entry set below
  for (Eigen::MatrixXd& block : blocks) block.resize(3 * targets, 3 * owners);
  for (size_t first_blob = 0; first_blob < blobs_m.size(); first_blob += kBlobs) {
    const int blobs = static_cast<int>(std::min<size_t>(kBlobs, blobs_m.size() - first_blob));
    double e2[kBlobs];
    for (int b = 0; b < blobs; ++b) e2[b] = blobs_m[first_blob + b] * blobs_m[first_blob + b];
    for (int i = 0; i < targets; i += 2) {
      const int i1 = std::min(i + 1, targets - 1);  // an odd count's last pair repeats it
      const Pair tx(x[i].x(), x[i1].x()), ty(x[i].y(), x[i1].y()), tz(x[i].z(), x[i1].z());
      for (int j = 0; j < owners; ++j) {
        // Per blob: the diagonal's (r^2 + 2 eps^2) sum, then r r^T's
        // xx, yy, zz, xy, xz, yz sums.
        Pair sum[kBlobs][7];
        for (auto& blob : sum) {
          for (Pair& entry : blob) entry.setZero();
        }
        for (int q = source.start[j]; q < source.start[j + 1]; ++q) {
          const Eigen::Vector3d& y = source.points[q];
          const Pair rx = tx - y.x(), ry = ty - y.y(), rz = tz - y.z();
          const Pair r2 = rx * rx + ry * ry + rz * rz;
          for (int b = 0; b < blobs; ++b) {
            // Cortez et al. (2005) eq. 10a:
            // [(r^2 + 2 eps^2) I + r r^T] / (r^2 + eps^2)^(3/2).
            const Pair soft = r2 + e2[b];
            const Pair inv3 = source.weight[q] / (soft * soft.sqrt());
            const Pair xs = rx * inv3, ys = ry * inv3, zs = rz * inv3;
            sum[b][0] += (r2 + 2.0 * e2[b]) * inv3;
            sum[b][1] += xs * rx;
            sum[b][2] += ys * ry;
            sum[b][3] += zs * rz;
            sum[b][4] += xs * ry;
            sum[b][5] += xs * rz;
            sum[b][6] += ys * rz;
          }
        }
        for (int b = 0; b < blobs; ++b) {
          for (int lane = 0; lane < (i1 > i ? 2 : 1); ++lane) {
            const auto at = [&](int k) { return sum[b][k][lane]; };
            blocks[first_blob + b].block<3, 3>(3 * (i + lane), 3 * j) << at(1) + at(0), at(4),
                at(5), at(4), at(2) + at(0), at(6), at(5), at(6), at(3) + at(0);
          }
        }
      }
    }
  }
  return blocks;
}

}  // namespace

Eigen::MatrixXd NearestNeighbourBlock(const PlacedSurface& target, const PlacedSurface& source,
                                      double blob_m, double viscosity_Pa_s) {
  return KernelSums(Placed(target, target.mesh->force_points), Owned(source, viscosity_Pa_s),
                    {blob_m})[0];
}

Eigen::MatrixXd NearestNeighbourImageBlock(const PlacedSurface& target,
                                           const PlacedSurface& source, double wall_z_m,
                                           double blob_m, double viscosity_Pa_s) {
  const std::vector<Eigen::Vector3d> x = Placed(target, target.mesh->force_points);
  const std::vector<Eigen::Vector3d> y = Placed(source, source.mesh->quadrature_points);
  const std::vector<int>& owner = source.mesh->owner;
  const std::vector<double>& area = source.mesh->quadrature_area_m2;
  const double scale = 1.0 / (8.0 * kPi * viscosity_Pa_s);
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(3 * x.size(), 3 * source.mesh->force_points.size());
  for (size_t i = 0; i < x.size(); ++i) {
    for (size_t q = 0; q < y.size(); ++q) {
      block.block<3, 3>(3 * i, 3 * owner[q]) +=
          (scale * area[q]) * RegularizedWallImage(x[i], y[q], wall_z_m, blob_m);
    }
  }
  return block;
}

namespace {

// The index of each surface's first row in the velocity matrix (3 per
// force point), and the total at the end.
std::vector<int> RowOffsets(const std::vector<PlacedSurface>& surfaces) {
  std::vector<int> offset(surfaces.size() + 1, 0);
  for (size_t s = 0; s < surfaces.size(); ++s) {
    offset[s + 1] = offset[s] + 3 * static_cast<int>(surfaces[s].mesh->force_points.size());
  }
  return offset;
}

// The rigid motions and the wrench of the force densities about c.
struct RigidBodyMaps {
  Eigen::MatrixXd motion;  // n x 6 bodies: u at the force points of [w; v] (v at c)
  Eigen::MatrixXd wrench;  // 6 bodies x n: [torque about c; force] on the fluid of f
};

RigidBodyMaps RigidMaps(const std::vector<PlacedSurface>& surfaces, int bodies,
                        const Eigen::Vector3d& c) {
  const std::vector<int> offset = RowOffsets(surfaces);
  RigidBodyMaps maps{Eigen::MatrixXd::Zero(offset.back(), 6 * bodies),
                     Eigen::MatrixXd::Zero(6 * bodies, offset.back())};
  for (size_t t = 0; t < surfaces.size(); ++t) {
    // Each force point's cell area: the areas of the quadrature points it owns.
    const SurfaceMesh& mesh = *surfaces[t].mesh;
    std::vector<double> cell_m2(mesh.force_points.size(), 0.0);
    for (size_t q = 0; q < mesh.owner.size(); ++q) cell_m2[mesh.owner[q]] += mesh.quadrature_area_m2[q];
    const std::vector<Eigen::Vector3d> x = Placed(surfaces[t], mesh.force_points);
    const int body = surfaces[t].body;
    for (size_t j = 0; j < x.size(); ++j) {
      Eigen::Matrix<double, 3, 6> motion;  // u = -[x - c]x w + v
      motion << -CrossMatrix(x[j] - c), Eigen::Matrix3d::Identity();
      maps.motion.block<3, 6>(offset[t] + 3 * j, 6 * body) = motion;
      maps.wrench.block<6, 3>(6 * body, offset[t] + 3 * j) = cell_m2[j] * motion.transpose();
    }
  }
  return maps;
}

// Columns at a time in the triangular solves of ProjectedInverse (the
// fewest instructions on the flexible-link plates of docs/FLUIDS.md).
constexpr int kSolveChunk = 12;

// T^-1 b for a lower-triangular T, `corner(top)` its trailing corner from
// row `top` on: the columns of b in the order of their first non-zero row
// (*order: b's column of each), kSolveChunk at a time, each chunk solved
// from its first non-zero row down (the solution is zero above it).
template <typename Corner>
Eigen::MatrixXd SolveBelowLeadingZeros(const Corner& corner, const Eigen::MatrixXd& b,
                                       std::vector<int>* order) {
  const Eigen::Index n = b.rows(), columns = b.cols();
  std::vector<Eigen::Index> first(columns);
  for (Eigen::Index c = 0; c < columns; ++c) {
    Eigen::Index row = 0;
    while (row < n && b(row, c) == 0.0) ++row;
    first[c] = row;
  }
  order->resize(columns);
  std::iota(order->begin(), order->end(), 0);
  std::stable_sort(order->begin(), order->end(), [&](int i, int j) { return first[i] < first[j]; });
  Eigen::MatrixXd x(n, columns);
  for (Eigen::Index k = 0; k < columns; ++k) x.col(k) = b.col((*order)[k]);
  for (Eigen::Index k = 0; k < columns; k += kSolveChunk) {
    const Eigen::Index top = first[(*order)[k]];
    if (top == n) break;  // these columns and the rest are zero
    auto chunk = x.block(top, k, n - top, std::min<Eigen::Index>(kSolveChunk, columns - k));
    corner(top).solveInPlace(chunk);
  }
  return x;
}

// W A^-1 M from A's partial-pivoting LU (P A = L U) as Z X with
// X = L^-1 P M and Z^T = U^-T W^T: a body's columns of M and rows of W are
// non-zero on its own unknowns only, so each triangular solve starts at
// the body's first row (and skips a third of the work on average).
Eigen::MatrixXd ProjectedInverse(const Eigen::MatrixXd& a, const Eigen::MatrixXd& motion,
                                 const Eigen::MatrixXd& wrench) {
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  const Eigen::MatrixXd& factors = lu.matrixLU();
  const Eigen::Index n = a.rows();
  std::vector<int> motion_order, wrench_order;
  const Eigen::MatrixXd x = SolveBelowLeadingZeros(
      [&](Eigen::Index top) {
        return factors.bottomRightCorner(n - top, n - top).triangularView<Eigen::UnitLower>();
      },
      lu.permutationP() * motion, &motion_order);
  const Eigen::MatrixXd zt = SolveBelowLeadingZeros(
      [&](Eigen::Index top) {
        return factors.bottomRightCorner(n - top, n - top)
            .triangularView<Eigen::Upper>()
            .transpose();
      },
      wrench.transpose(), &wrench_order);
  const Eigen::MatrixXd sorted = zt.transpose() * x;
  Eigen::MatrixXd projected(wrench.rows(), motion.cols());
  for (Eigen::Index j = 0; j < sorted.cols(); ++j) {
    for (Eigen::Index i = 0; i < sorted.rows(); ++i) {
      projected(wrench_order[i], motion_order[j]) = sorted(i, j);
    }
  }
  return projected;
}

// The reciprocal theorem makes R symmetric; its discrete form nearly so.
Eigen::MatrixXd Reciprocal(const Eigen::MatrixXd& resistance) {
  return 0.5 * (resistance + resistance.transpose());
}

// Per blob: each surface's own block in its frame, or none (an empty list).
using SelfBlocks = std::vector<std::vector<Eigen::MatrixXd>>;

// The world positions of the force points of all surfaces, in order.
std::vector<Eigen::Vector3d> AllForcePoints(const std::vector<PlacedSurface>& surfaces) {
  std::vector<Eigen::Vector3d> points;
  for (const PlacedSurface& surface : surfaces) {
    const std::vector<Eigen::Vector3d> placed = Placed(surface, surface.mesh->force_points);
    points.insert(points.end(), placed.begin(), placed.end());
  }
  return points;
}

// Surface s's own block at each blob, rotated from its frame.
std::vector<Eigen::MatrixXd> OwnBlocks(const std::vector<PlacedSurface>& surfaces, size_t s,
                                       const SelfBlocks& self_blocks) {
  std::vector<Eigen::MatrixXd> blocks;
  for (const std::vector<Eigen::MatrixXd>& self : self_blocks) {
    blocks.push_back(RotateBlocks(self[s], surfaces[s].rotation));
  }
  return blocks;
}

// The whole velocity matrix solved for every rigid motion, at each blob.
std::vector<Eigen::MatrixXd> FullResistances(const std::vector<PlacedSurface>& surfaces,
                                             int bodies, const Eigen::Vector3d& c,
                                             const std::vector<double>& blobs_m,
                                             double viscosity_Pa_s, const SelfBlocks& self_blocks,
                                             std::optional<double> wall_z_m) {
  const std::vector<int> offset = RowOffsets(surfaces);
  const int n = offset.back();
  const std::vector<Eigen::Vector3d> targets = AllForcePoints(surfaces);
  // u = velocity f, f the force per area
  std::vector<Eigen::MatrixXd> velocity = ZeroMatrices(blobs_m.size(), n, n);
  for (size_t s = 0; s < surfaces.size(); ++s) {
    const int width = offset[s + 1] - offset[s];
    const std::vector<Eigen::MatrixXd> columns =
        KernelSums(targets, Owned(surfaces[s], viscosity_Pa_s), blobs_m);
    const std::vector<Eigen::MatrixXd> own = OwnBlocks(surfaces, s, self_blocks);
    for (size_t b = 0; b < blobs_m.size(); ++b) {
      velocity[b].middleCols(offset[s], width) = columns[b];
      if (!own.empty()) velocity[b].block(offset[s], offset[s], width, width) = own[b];
      for (size_t t = 0; wall_z_m && t < surfaces.size(); ++t) {
        velocity[b].block(offset[t], offset[s], offset[t + 1] - offset[t], width) +=
            NearestNeighbourImageBlock(surfaces[t], surfaces[s], *wall_z_m, blobs_m[b],
                                       viscosity_Pa_s);
      }
    }
  }
  const RigidBodyMaps maps = RigidMaps(surfaces, bodies, c);
  std::vector<Eigen::MatrixXd> resistances;
  for (const Eigen::MatrixXd& v : velocity) {
    resistances.push_back(Reciprocal(ProjectedInverse(v, maps.motion, maps.wrench)));
  }
  return resistances;
}

// Mirror symmetry about the beat plane z = z0. With P = diag(1, 1, -1),
// the reflection is x -> P x + 2 z0 e_z, and the free-space kernel is
// isotropic: S_eps(P r) = P S_eps(r) P. If the reflection maps every force
// point i onto a force point pi(i), and every quadrature point onto one of
// the same area owned by the image of its owner, the nearest-neighbour sums
// map term by term and the velocity matrix's 3 x 3 blocks obey
//   A(pi i, pi j) = P A(i, j) P.
// So A maps force distributions even under the reflection (f_pi(j) = P f_j)
// to even velocities, and odd ones (f_pi(j) = -P f_j) to odd ones: in the
// basis of even and odd distributions A is block diagonal. With one
// representative i of each pair {i, pi i} the even half is
//   A(i, j) + A(i, pi j) P,  the odd half  A(i, j) - A(i, pi j) P,
// and a point on the plane (pi i = i) carries only x and y in the even
// half and only z in the odd one. A rigid motion about a point on the
// plane is even for w_z, v_x, v_y and odd for w_x, w_y, v_z, so each half
// is solved for its three motions of each body only: two LUs of about n / 2
// (a quarter of the work each) with half the right-hand sides each.
struct MirrorPlane {
  double z_m = 0.0;         // the plane z = z0
  std::vector<int> image;   // pi: each force point's image, all surfaces in order
};

// P's diagonal.
constexpr double kMirrorSign[3] = {1.0, 1.0, -1.0};

// The image of each of `mesh`'s force points under z -> -z in its own
// frame, if that maps force points onto force points and quadrature points
// onto quadrature points of the same area owned by their owner's image, to
// round-off (1e-12 of the mesh's extent and of the areas); none otherwise.
std::optional<std::vector<int>> MeshMirror(const SurfaceMesh& mesh) {
  double extent_m = 0.0;
  for (const auto* points : {&mesh.force_points, &mesh.quadrature_points}) {
    for (const Eigen::Vector3d& p : *points) {
      extent_m = std::max(extent_m, p.lpNorm<Eigen::Infinity>());
    }
  }
  const double tolerance_m = 1e-12 * extent_m;
  const auto mirrored = [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p.x(), p.y(), -p.z());
  };
  const auto same = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - b).lpNorm<Eigen::Infinity>() <= tolerance_m;
  };
  const int points = static_cast<int>(mesh.force_points.size());
  std::vector<int> image(points, -1);
  for (int j = 0; j < points; ++j) {
    for (int k = 0; k < points && image[j] < 0; ++k) {
      if (same(mirrored(mesh.force_points[j]), mesh.force_points[k])) image[j] = k;
    }
    if (image[j] < 0) return std::nullopt;
  }
  for (int j = 0; j < points; ++j) {
    if (image[image[j]] != j) return std::nullopt;
  }
  // Quadrature points: searched among those of the owner's image.
  std::vector<std::vector<int>> owned(points);
  for (size_t q = 0; q < mesh.owner.size(); ++q) {
    owned[mesh.owner[q]].push_back(static_cast<int>(q));
  }
  for (size_t q = 0; q < mesh.owner.size(); ++q) {
    const Eigen::Vector3d y = mirrored(mesh.quadrature_points[q]);
    const double area_m2 = mesh.quadrature_area_m2[q];
    bool found = false;
    for (int k : owned[image[mesh.owner[q]]]) {
      found = same(y, mesh.quadrature_points[k]) &&
              std::abs(mesh.quadrature_area_m2[k] - area_m2) <= 1e-12 * area_m2;
      if (found) break;
    }
    if (!found) return std::nullopt;
  }
  return image;
}

// The plane all surfaces are mirror-symmetric about, if any: no wall (its
// image breaks the symmetry), every rotation's third column exactly +-e_z
// (then P Q = Q P), every surface centred on the same plane z = z0 exactly,
// and every mesh mirror-symmetric about its own z = 0 (MeshMirror); then
// P (p + Q x) + 2 z0 e_z = p + Q (P x) maps each surface onto itself.
std::optional<MirrorPlane> FindMirrorPlane(const std::vector<PlacedSurface>& surfaces,
                                           std::optional<double> wall_z_m) {
  if (wall_z_m || surfaces.empty()) return std::nullopt;
  MirrorPlane plane;
  plane.z_m = surfaces.front().position.z();
  std::vector<std::pair<const SurfaceMesh*, std::vector<int>>> seen;  // the meshes checked
  for (const PlacedSurface& surface : surfaces) {
    const Eigen::Matrix3d& q = surface.rotation;
    if (q(2, 0) != 0.0 || q(2, 1) != 0.0 || q(0, 2) != 0.0 || q(1, 2) != 0.0 ||
        std::abs(q(2, 2)) != 1.0 || surface.position.z() != plane.z_m) {
      return std::nullopt;
    }
    auto it = std::find_if(seen.begin(), seen.end(),
                           [&](const auto& entry) { return entry.first == surface.mesh; });
    if (it == seen.end()) {
      std::optional<std::vector<int>> image = MeshMirror(*surface.mesh);
      if (!image) return std::nullopt;
      it = seen.emplace(seen.end(), surface.mesh, std::move(*image));
    }
    const int first = static_cast<int>(plane.image.size());
    for (int k : it->second) plane.image.push_back(first + k);
  }
  return plane;
}

// One unknown of a half: component `axis` of the force at force point
// `point`, which is its pair's representative (the lower index) and stands
// for its `image` too (f_image = +-P f_point), or lies on the plane (image -1).
struct MirrorUnknown {
  int point, axis, image;
};

// The unknowns of the even (parity +1) or odd (-1) half.
std::vector<MirrorUnknown> HalfUnknowns(const std::vector<int>& image, int parity) {
  std::vector<MirrorUnknown> unknowns;
  for (int a = 0; a < static_cast<int>(image.size()); ++a) {
    if (image[a] < a) continue;
    for (int k = 0; k < 3; ++k) {
      if (image[a] != a) {
        unknowns.push_back({a, k, image[a]});
      } else if (parity * kMirrorSign[k] > 0) {
        unknowns.push_back({a, k, -1});
      }
    }
  }
  return unknowns;
}

// Columns of `full` (3 per force point) combined as the half's unknowns
// act: column 3a + k plus parity P_kk times its image's 3 pi(a) + k.
Eigen::MatrixXd HalfColumns(const Eigen::MatrixXd& full,
                            const std::vector<MirrorUnknown>& unknowns, int parity) {
  Eigen::MatrixXd half(full.rows(), unknowns.size());
  for (size_t c = 0; c < unknowns.size(); ++c) {
    const MirrorUnknown& u = unknowns[c];
    half.col(c) = full.col(3 * u.point + u.axis);
    if (u.image >= 0) half.col(c) += parity * kMirrorSign[u.axis] * full.col(3 * u.image + u.axis);
  }
  return half;
}

// Where each row and column of the full velocity matrix (3 per force
// point) goes in a half: the row of its unknown's equation (-1: none, an
// image's row or an axis the half leaves out), and the column of the
// unknown it acts as, with its sign (-1 and 0: none).
struct HalfPlaces {
  std::vector<int> row, column;
  std::vector<double> sign;
};

HalfPlaces PlacesOf(const std::vector<MirrorUnknown>& unknowns, int parity, int points) {
  HalfPlaces places{std::vector<int>(3 * points, -1), std::vector<int>(3 * points, -1),
                    std::vector<double>(3 * points, 0.0)};
  for (size_t c = 0; c < unknowns.size(); ++c) {
    const MirrorUnknown& u = unknowns[c];
    const int own = 3 * u.point + u.axis;
    places.row[own] = places.column[own] = static_cast<int>(c);
    places.sign[own] = 1.0;
    if (u.image >= 0) {
      places.column[3 * u.image + u.axis] = static_cast<int>(c);
      places.sign[3 * u.image + u.axis] = parity * kMirrorSign[u.axis];
    }
  }
  return places;
}

// The even and (with `count` 2) odd halves' matrices at each blob, summed
// straight from the kernel sums of the pairs' representatives' rows (the
// other rows follow from them by the symmetry).
std::array<std::vector<Eigen::MatrixXd>, 2> MirrorHalves(
    const std::vector<PlacedSurface>& surfaces, const std::array<HalfPlaces, 2>& places,
    const std::array<int, 2>& sizes, int count, const MirrorPlane& plane,
    const std::vector<double>& blobs_m, double viscosity_Pa_s, const SelfBlocks& self_blocks) {
  std::array<std::vector<Eigen::MatrixXd>, 2> halves;
  for (int h = 0; h < count; ++h) {
    halves[h] = ZeroMatrices(blobs_m.size(), sizes[h], sizes[h]);
  }
  const std::vector<int> offset = RowOffsets(surfaces);
  const std::vector<Eigen::Vector3d> points = AllForcePoints(surfaces);
  // The representatives (global force point indices) and where they are.
  std::vector<int> representatives;
  std::vector<Eigen::Vector3d> targets;
  for (int a = 0; a < static_cast<int>(points.size()); ++a) {
    if (plane.image[a] < a) continue;
    representatives.push_back(a);
    targets.push_back(points[a]);
  }
  // (the kernel sums' row, the half's row) of each of the half's equations
  std::array<std::vector<std::pair<int, int>>, 2> rows;
  for (int h = 0; h < count; ++h) {
    for (size_t r = 0; r < representatives.size(); ++r) {
      for (int k = 0; k < 3; ++k) {
        const int row = places[h].row[3 * representatives[r] + k];
        if (row >= 0) rows[h].emplace_back(3 * static_cast<int>(r) + k, row);
      }
    }
  }
  // Whether they are the kernel sums' rows in order (no force point on the
  // plane): then each column is added whole.
  std::array<bool, 2> in_order;
  for (int h = 0; h < count; ++h) {
    in_order[h] = rows[h].size() == 3 * representatives.size() &&
                  std::all_of(rows[h].begin(), rows[h].end(),
                              [](const auto& pair) { return pair.first == pair.second; });
  }
  for (size_t s = 0; s < surfaces.size(); ++s) {
    const int width = offset[s + 1] - offset[s];
    std::vector<Eigen::MatrixXd> columns =
        KernelSums(targets, Owned(surfaces[s], viscosity_Pa_s), blobs_m);
    // The surface's own representatives' rows from its cached block.
    const std::vector<Eigen::MatrixXd> own = OwnBlocks(surfaces, s, self_blocks);
    for (size_t r = 0; !own.empty() && r < representatives.size(); ++r) {
      const int local = representatives[r] - offset[s] / 3;
      if (local < 0 || local >= width / 3) continue;
      for (size_t b = 0; b < blobs_m.size(); ++b) {
        columns[b].middleRows<3>(3 * r) = own[b].middleRows<3>(3 * local);
      }
    }
    for (int h = 0; h < count; ++h) {
      for (int col = 0; col < width; ++col) {
        const int column = places[h].column[offset[s] + col];
        if (column < 0) continue;
        const double sign = places[h].sign[offset[s] + col];
        for (size_t b = 0; b < blobs_m.size(); ++b) {
          if (in_order[h]) {
            halves[h][b].col(column) += sign * columns[b].col(col);
            continue;
          }
          for (const auto& [from, row] : rows[h]) {
            halves[h][b](row, column) += sign * columns[b](from, col);
          }
        }
      }
    }
  }
  return halves;
}

// R of surfaces mirror-symmetric about `plane`, by the even and odd
// halves, at each blob; `in_plane_only`: the even half only, the rows and
// columns of the out-of-plane motions left zero.
std::vector<Eigen::MatrixXd> MirrorResistances(const std::vector<PlacedSurface>& surfaces,
                                               int bodies, const Eigen::Vector3d& c,
                                               const std::vector<double>& blobs_m,
                                               double viscosity_Pa_s,
                                               const SelfBlocks& self_blocks,
                                               const MirrorPlane& plane, bool in_plane_only) {
  const int count = in_plane_only ? 1 : 2;
  const int points = static_cast<int>(plane.image.size());
  std::array<std::vector<MirrorUnknown>, 2> unknowns;  // [even, odd]
  std::array<HalfPlaces, 2> places;
  std::array<int, 2> sizes;
  for (int h = 0; h < count; ++h) {
    unknowns[h] = HalfUnknowns(plane.image, h == 0 ? 1 : -1);
    places[h] = PlacesOf(unknowns[h], h == 0 ? 1 : -1, points);
    sizes[h] = static_cast<int>(unknowns[h].size());
  }
  const std::array<std::vector<Eigen::MatrixXd>, 2> halves =
      MirrorHalves(surfaces, places, sizes, count, plane, blobs_m, viscosity_Pa_s, self_blocks);
  // About a point on the plane each rigid motion has a parity.
  const Eigen::Vector3d on_plane(c.x(), c.y(), plane.z_m);
  const RigidBodyMaps maps = RigidMaps(surfaces, bodies, on_plane);
  std::vector<Eigen::MatrixXd> resistances =
      ZeroMatrices(blobs_m.size(), 6 * bodies, 6 * bodies);
  for (int h = 0; h < count; ++h) {
    const int parity = h == 0 ? 1 : -1;
    // [w_x w_y w_z v_x v_y v_z]: w_z, v_x and v_y even, the others odd.
    const std::vector<int> motions =
        parity > 0 ? std::vector<int>{2, 3, 4} : std::vector<int>{0, 1, 5};
    std::vector<int> columns;
    for (int b = 0; b < bodies; ++b) {
      for (int k : motions) columns.push_back(6 * b + k);
    }
    Eigen::MatrixXd motion(sizes[h], columns.size());  // the half's equations: its unknowns' rows
    for (size_t k = 0; k < columns.size(); ++k) {
      for (int r = 0; r < sizes[h]; ++r) {
        const MirrorUnknown& u = unknowns[h][r];
        motion(r, k) = maps.motion(3 * u.point + u.axis, columns[k]);
      }
    }
    // The wrench of the half's unknowns, on its motions' components only
    // (the others vanish by the symmetry).
    const Eigen::MatrixXd wrench =
        HalfColumns(maps.wrench(columns, Eigen::all), unknowns[h], parity);
    for (size_t b = 0; b < blobs_m.size(); ++b) {
      const Eigen::MatrixXd half = ProjectedInverse(halves[h][b], motion, wrench);
      for (size_t j = 0; j < columns.size(); ++j) {
        for (size_t i = 0; i < columns.size(); ++i) {
          resistances[b](columns[i], columns[j]) = half(i, j);
        }
      }
    }
  }
  for (Eigen::MatrixXd& resistance : resistances) {
    if (c.z() != plane.z_m) {
      // Moved to c: R_c = T^T R_p T, T = [I 0; -[p - c]x I] on each body
      // (the velocity at p is v_c + w x (p - c), the torque about c
      // tau_p + (p - c) x F).
      Eigen::MatrixXd shift = Eigen::MatrixXd::Identity(6 * bodies, 6 * bodies);
      for (int b = 0; b < bodies; ++b) {
        shift.block<3, 3>(6 * b + 3, 6 * b) = -CrossMatrix(on_plane - c);
      }
      resistance = shift.transpose() * resistance * shift;
    }
    resistance = Reciprocal(resistance);
  }
  return resistances;
}

// R at each blob, by the mirror halves (or the even half alone) when the
// surfaces allow and `solve` asks, else by the full matrix;
// *out_of_plane_left_out (if given) says whether the even half was alone.
std::vector<Eigen::MatrixXd> SurfaceResistances(const std::vector<PlacedSurface>& surfaces,
                                                int bodies, const Eigen::Vector3d& c,
                                                const std::vector<double>& blobs_m,
                                                double viscosity_Pa_s,
                                                const SelfBlocks& self_blocks,
                                                std::optional<double> wall_z_m,
                                                SurfaceSolve solve,
                                                bool* out_of_plane_left_out = nullptr) {
  const bool in_plane_only = solve == SurfaceSolve::kInPlaneHalfWhenSymmetric;
  if (out_of_plane_left_out) *out_of_plane_left_out = false;
  if (solve != SurfaceSolve::kFullMatrix) {
    if (const std::optional<MirrorPlane> plane = FindMirrorPlane(surfaces, wall_z_m)) {
      if (out_of_plane_left_out) *out_of_plane_left_out = in_plane_only;
      return MirrorResistances(surfaces, bodies, c, blobs_m, viscosity_Pa_s, self_blocks, *plane,
                               in_plane_only);
    }
  }
  return FullResistances(surfaces, bodies, c, blobs_m, viscosity_Pa_s, self_blocks, wall_z_m);
}

}  // namespace

bool MirrorSymmetric(const std::vector<PlacedSurface>& surfaces, std::optional<double> wall_z_m) {
  return FindMirrorPlane(surfaces, wall_z_m).has_value();
}

Eigen::MatrixXd SurfaceResistance(const std::vector<PlacedSurface>& surfaces, int bodies,
                                  const Eigen::Vector3d& c, double blob_m, double viscosity_Pa_s,
                                  const std::vector<Eigen::MatrixXd>& self_blocks,
                                  std::optional<double> wall_z_m, SurfaceSolve solve) {
  const SelfBlocks self = self_blocks.empty() ? SelfBlocks{} : SelfBlocks{self_blocks};
  return SurfaceResistances(surfaces, bodies, c, {blob_m}, viscosity_Pa_s, self, wall_z_m,
                            solve)[0];
}

Eigen::MatrixXd ExtrapolatedResistance(const std::vector<PlacedSurface>& surfaces, int bodies,
                                       const Eigen::Vector3d& c, double blob_m, bool richardson,
                                       double viscosity_Pa_s, std::optional<double> wall_z_m,
                                       const std::vector<Eigen::MatrixXd>& self_blocks,
                                       const std::vector<Eigen::MatrixXd>& half_blob_self_blocks,
                                       SurfaceSolve solve, bool* out_of_plane_left_out) {
  std::vector<double> blobs_m = {blob_m};
  SelfBlocks self;
  if (!self_blocks.empty()) self.push_back(self_blocks);
  if (richardson) {
    blobs_m.push_back(0.5 * blob_m);
    if (!self_blocks.empty()) self.push_back(half_blob_self_blocks);
  }
  const std::vector<Eigen::MatrixXd> r = SurfaceResistances(
      surfaces, bodies, c, blobs_m, viscosity_Pa_s, self, wall_z_m, solve, out_of_plane_left_out);
  return richardson ? Eigen::MatrixXd(2.0 * r[1] - r[0]) : r[0];
}

StripDragPerLength ConvergedStripDrag(double viscosity_Pa_s, double length_m, double width_m) {
  constexpr int kCoarse = 4, kFine = 6, kRefinement = 4;
  constexpr double kBlobOverSpacing = 0.5;
  Eigen::Vector2d drag[2];  // broadside, axial at kCoarse and kFine
  for (int i = 0; i < 2; ++i) {
    const int across = i == 0 ? kCoarse : kFine;
    const SurfaceMesh mesh = RectangleMesh(length_m, width_m, across, kRefinement);
    PlacedSurface plate;
    plate.mesh = &mesh;
    const Eigen::MatrixXd r =
        ExtrapolatedResistance({plate}, 1, Eigen::Vector3d::Zero(),
                               kBlobOverSpacing * width_m / across, true, viscosity_Pa_s);
    drag[i] = Eigen::Vector2d(r(4, 4), r(3, 3));  // the face's normal is y
  }
  const Eigen::Vector2d converged = (kFine * drag[1] - kCoarse * drag[0]) / (kFine - kCoarse);
  return {converged[0] / length_m, converged[1] / length_m};
}

namespace {

// The parameters (FluidParameter, fluid_model.h).
FluidParameter PointsAcross() {
  return SetsResolution(IntegerParameter(
      "plate_points_across", "ipmc_fluid_plate_points_across", 4, 1, kMaxPlatePointsAcross, 6,
      "Force points across the strip's width on each plate (square cells along its length; the "
      "blob is half their spacing): the plate model's resolution (docs/FLUIDS.md, \"Flat "
      "plates\")"));
}

FluidParameter QuadratureRefinement() {
  return IntegerParameter("plate_quadrature_refinement",
                          "ipmc_fluid_plate_quadrature_refinement", 4, 1,
                          kMaxPlateQuadratureRefinement, 6,
                          "Quadrature points per force point along each side of its cell (the "
                          "nearest-neighbour method's finer grid)");
}

FluidParameter Richardson() {
  return BooleanParameter("plate_richardson", "ipmc_fluid_plate_richardson", true,
                          "Richardson extrapolation in the blob: 2 R(eps / 2) - R(eps), which "
                          "removes the regularization's error, linear in eps (two solves per "
                          "resistance)");
}

const CacheParameters& Cache() {
  static const CacheParameters cache("plate", "the plates' resistance", "Flat plates");
  return cache;
}

PlateSettings SettingsFromParameters(const mjModel* m, const RftDrag& segments,
                                     const RftDragOverrides& overrides) {
  const auto value = [&](const FluidParameter& p) {
    return *FluidParameterValue(m, overrides, "plate fluid", p);
  };
  PlateSettings settings;
  settings.points_across = static_cast<int>(value(PointsAcross()));
  settings.quadrature_refinement = static_cast<int>(value(QuadratureRefinement()));
  settings.richardson = value(Richardson()) != 0.0;
  settings.shape_tolerance_rad = value(Cache().ShapeToleranceRad());
  settings.secant_reach_rad = value(Cache().SecantReachRad());
  settings.fit_tolerance = value(Cache().FitTolerance());
  settings.wall_distance_m = WallDistance_m(segments);
  return settings;
}

}  // namespace

std::vector<FluidParameter> PlateFluid::Parameters() {
  return {PointsAcross(), QuadratureRefinement(), Richardson(), Cache().ShapeToleranceRad(),
          Cache().SecantReachRad(), Cache().FitTolerance()};
}

std::unique_ptr<Fluid> PlateFluid::Make(const mjModel* m, const RftDrag& segments,
                                        const RftDragOverrides& overrides) {
  return std::make_unique<PlateFluid>(m, segments, SettingsFromParameters(m, segments, overrides));
}

double PlateFluid::ForcePoints(const mjModel* m, const RftDrag& segments,
                               const RftDragOverrides& overrides) {
  const PlateSettings settings = SettingsFromParameters(m, segments, overrides);
  const double width_m = settings.width_m == 0.0 ? StripWidth_m(m) : settings.width_m;
  double points = 0.0;
  for (double length_m : segments.SegmentLengths_m()) {
    points += CellsAlong(length_m, width_m, settings.points_across) * settings.points_across;
  }
  return points;
}

PlateFluid::PlateFluid(const mjModel* m, const RftDrag& segments, const PlateSettings& plates)
    : DenseResistanceFluid(m, segments, "plate fluid"), settings_(plates) {
  if (settings_.width_m == 0.0) settings_.width_m = StripWidth_m(m);
  settings_.Validate();
  const double spacing_m = settings_.width_m / settings_.points_across;
  blob_m_ = settings_.blob_over_spacing * spacing_m;
  const double mu = rft().config().viscosity_Pa_s;
  for (double length_m : rft().SegmentLengths_m()) {
    meshes_.push_back(RectangleMesh(length_m, settings_.width_m, settings_.points_across,
                                    settings_.quadrature_refinement));
    PlacedSurface own;
    own.mesh = &meshes_.back();
    self_blocks_.push_back(NearestNeighbourBlock(own, own, blob_m_, mu));
    if (settings_.richardson) {
      half_blob_self_blocks_.push_back(NearestNeighbourBlock(own, own, 0.5 * blob_m_, mu));
    }
  }
}

std::optional<double> PlateFluid::wall_z_m() const {
  if (!settings_.wall_distance_m) return std::nullopt;
  return -*settings_.wall_distance_m;
}

int PlateFluid::force_points() const {
  int n = 0;
  for (const SurfaceMesh& mesh : meshes_) n += static_cast<int>(mesh.force_points.size());
  return n;
}

Eigen::MatrixXd PlateFluid::Resistance(const std::vector<PlacedSurface>& plates,
                                       const Eigen::Vector3d& c, SurfaceSolve solve,
                                       bool* out_of_plane_left_out) const {
  return ExtrapolatedResistance(plates, body_count(), c, blob_m_, settings_.richardson,
                                rft().config().viscosity_Pa_s, wall_z_m(), self_blocks_,
                                half_blob_self_blocks_, solve, out_of_plane_left_out);
}

PlacedSurface PlateOnSegment(const Segment& segment, const SurfaceMesh* mesh, int body) {
  PlacedSurface plate;
  const Eigen::Vector3d t = segment.tangent_W.normalized();
  const Eigen::Vector3d w = (Eigen::Vector3d::UnitZ() - t.z() * t).normalized();
  plate.rotation << t, w.cross(t), w;
  plate.position = segment.center_W;
  plate.mesh = mesh;
  plate.body = body;
  return plate;
}

std::vector<PlacedSurface> PlateFluid::Plates(const mjModel* m, const mjData* d) const {
  const std::vector<Segment> segments = rft().Segments(m, d);
  std::vector<PlacedSurface> plates(segments.size());
  for (size_t i = 0; i < segments.size(); ++i) {
    plates[i] = PlateOnSegment(segments[i], &meshes_[i], body_of_geom(static_cast<int>(i)));
  }
  return plates;
}

Eigen::MatrixXd PlateFluid::ComputeResistance(const mjModel* m, const mjData* d,
                                              const Eigen::Vector3d& origin_W) const {
  return Resistance(Plates(m, d), origin_W);
}

Eigen::MatrixXd PlateFluid::ComputeInPlaneResistance(const mjModel* m, const mjData* d,
                                                     const Eigen::Vector3d& origin_W,
                                                     bool* out_of_plane_left_out) const {
  return Resistance(Plates(m, d), origin_W, SurfaceSolve::kInPlaneHalfWhenSymmetric,
                    out_of_plane_left_out);
}

double PlateFluid::TowingDrag_N(double speed_m_s) const {
  // The plates end to end along x, one body (near a wall, h above it).
  std::vector<PlacedSurface> plates(meshes_.size());
  double start_m = 0.0;
  const std::vector<double> lengths_m = rft().SegmentLengths_m();
  for (size_t i = 0; i < plates.size(); ++i) {
    plates[i].mesh = &meshes_[i];
    plates[i].position = Eigen::Vector3d(start_m + 0.5 * lengths_m[i], 0, 0);
    start_m += lengths_m[i];
  }
  return Resistance(plates, Eigen::Vector3d::Zero())(3, 3) * speed_m_s;
}

}  // namespace ipmc

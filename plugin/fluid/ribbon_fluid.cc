#include "plugin/fluid/ribbon_fluid.h"

#include <Eigen/LU>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/base/numbers.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/mjcf/spatial_algebra.h"

namespace ipmc {
namespace {

// Gauss-Legendre order on each panel, and the panels of a piece (fractions
// of its length), graded towards its ends, where the neighbouring piece's
// kernel is nearly singular at a kink.
constexpr int kGaussOrder = 8;
constexpr double kPanelBreaks[] = {0.0, 1.0 / 8, 0.5, 7.0 / 8, 1.0};

// A quadrature node of the ribbon.
struct Node {
  double s = 0.0;       // scaled arclength in [-1, 1]
  double weight = 0.0;  // its share of ds (scaled)
  Eigen::Vector3d point_W;  // on its body
  Eigen::Vector3d hydro_W;  // on the ribbon the fluid sees [m]
  Eigen::Vector3d tangent_W;
  Eigen::Vector3d width_W;
  int piece = 0;
  int body = 0;
};

std::vector<Node> Nodes(const std::vector<RibbonPiece>& pieces, double half_length_m) {
  using Gauss = boost::math::quadrature::gauss<double, kGaussOrder>;
  std::vector<Node> nodes;
  double along_m = 0.0;
  for (size_t p = 0; p < pieces.size(); ++p) {
    const RibbonPiece& piece = pieces[p];
    const Eigen::Vector3d t = piece.tangent_W.normalized();
    const Eigen::Vector3d w = (piece.width_axis_W - piece.width_axis_W.dot(t) * t).normalized();
    for (size_t k = 0; k + 1 < std::size(kPanelBreaks); ++k) {
      const double middle_m = 0.5 * (kPanelBreaks[k] + kPanelBreaks[k + 1]) * piece.length_m;
      const double half_m = 0.5 * (kPanelBreaks[k + 1] - kPanelBreaks[k]) * piece.length_m;
      for (size_t j = 0; j < Gauss::abscissa().size(); ++j) {
        const double x = Gauss::abscissa()[j];
        for (double sign : {-1.0, 1.0}) {
          if (x == 0.0 && sign < 0) continue;
          const double l_m = middle_m + sign * half_m * x;
          Node node;
          node.s = (along_m + l_m) / half_length_m - 1.0;
          node.weight = half_m * Gauss::weights()[j] / half_length_m;
          node.point_W = piece.start_W + l_m * t;
          node.hydro_W = piece.hydro_start_W + l_m * t;
          node.tangent_W = t;
          node.width_W = w;
          node.piece = static_cast<int>(p);
          node.body = piece.body;
          nodes.push_back(node);
        }
      }
    }
    along_m += piece.length_m;
  }
  return nodes;
}

// Lg(s) = ln(16 (1 - s^2) / (b^2 rho^2)) for the rectangle with elliptic
// caps beyond s_cap, where it is constant.
double LogTerm(double s, double b, double s_cap) {
  if (std::abs(s) >= s_cap) return std::log(16.0 * (1.0 - s_cap * s_cap) / (b * b));
  return std::log(16.0 * (1.0 - s * s) / (b * b));
}

// 8 pi mu U at every node (3N) for the force density P_n e_a (3M columns):
// the local term, the straight part's -2 H_n (I + t t) P_n, and the
// regular remainder over the other pieces.
Eigen::MatrixXd VelocityOfModes(const std::vector<Node>& nodes, const Eigen::MatrixXd& legendre,
                                double b, double s_cap, double half_length_m) {
  const int n_nodes = static_cast<int>(nodes.size());
  const int modes = static_cast<int>(legendre.cols());
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  // The remainder's kernel at nodes i, q of different pieces,
  //   w_q [(1 / d - 1 / |s - s'|) I - t t / |s - s'| + R R / d^3],
  // in its 8 scalar parts (the I part, the t t part, and R R's xx, yy, zz,
  // xy, xz, yz), summed against P_n(s_q) for every mode n at once: rows
  // 8 i .. 8 i + 7 of `remainder`, column n.
  constexpr int kParts = 8;
  using Parts = Eigen::Matrix<double, kParts, 1>;
  using PartsOfModes = Eigen::Matrix<double, kParts, Eigen::Dynamic, 0, kParts, kMaxRibbonModes>;
  Eigen::MatrixXd remainder(kParts * n_nodes, modes);
  for (int i = 0; i < n_nodes; ++i) {
    const Node& a = nodes[i];
    PartsOfModes sum = PartsOfModes::Zero(kParts, modes);
    for (int q = 0; q < n_nodes; ++q) {
      const Node& c = nodes[q];
      if (c.piece == a.piece) continue;  // the straight part, done below
      const Eigen::Vector3d r = (a.hydro_W - c.hydro_W) / half_length_m;
      const double inverse_distance = 1.0 / r.norm();
      const double inverse_ds = 1.0 / std::abs(a.s - c.s);
      const double k = c.weight * inverse_distance * inverse_distance * inverse_distance;
      Parts parts;
      parts << c.weight * (inverse_distance - inverse_ds), c.weight * inverse_ds,
          k * r.x() * r.x(), k * r.y() * r.y(), k * r.z() * r.z(), k * r.x() * r.y(),
          k * r.x() * r.z(), k * r.y() * r.z();
      sum.noalias() += parts * legendre.row(q);
    }
    remainder.middleRows<kParts>(kParts * i) = sum;
  }
  Eigen::MatrixXd velocity(3 * n_nodes, 3 * modes);
  for (int i = 0; i < n_nodes; ++i) {
    const Node& a = nodes[i];
    const Eigen::Matrix3d tt = a.tangent_W * a.tangent_W.transpose();
    const Eigen::Matrix3d local = LogTerm(a.s, b, s_cap) * (identity + tt) - 2.0 * tt +
                                  2.0 * a.width_W * a.width_W.transpose();
    double harmonic = 0.0;
    for (int n = 0; n < modes; ++n) {
      if (n > 0) harmonic += 1.0 / n;
      const auto v = remainder.block<kParts, 1>(kParts * i, n);
      Eigen::Matrix3d rr;
      rr << v[2], v[5], v[6], v[5], v[3], v[7], v[6], v[7], v[4];
      // The local term and the straight part's -2 H_n (I + t t) P_n.
      velocity.block<3, 3>(3 * i, 3 * n) =
          (local - 2.0 * harmonic * (identity + tt)) * legendre(i, n) + v[0] * identity -
          v[1] * tt + rr;
    }
  }
  return velocity;
}

void RequirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "ribbon fluid: " << what << " must be finite and > 0 (got " << value << ")";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

void RibbonSettings::Validate() const {
  if (modes < 1 || modes > kMaxRibbonModes) {
    throw std::invalid_argument("ribbon fluid: the Legendre modes must be in [1, " +
                                std::to_string(kMaxRibbonModes) + "] (got " +
                                std::to_string(modes) + ")");
  }
  RequirePositive(width_m, "the ribbon's width");
  RequirePositive(end_cap_m, "the ribbon's end cap");
  if (!(shape_tolerance_rad >= 0.0) || !std::isfinite(shape_tolerance_rad)) {
    throw std::invalid_argument("ribbon fluid: the shape tolerance must be finite and >= 0");
  }
}

Eigen::MatrixXd RibbonBodyResistance(const std::vector<RibbonPiece>& pieces, int bodies,
                                     const Eigen::Vector3d& c, const RibbonSettings& settings,
                                     double viscosity_Pa_s) {
  settings.Validate();
  double length_m = 0.0;
  for (const RibbonPiece& piece : pieces) length_m += piece.length_m;
  const double half_m = 0.5 * length_m;
  if (!(settings.end_cap_m <= half_m)) {
    throw std::invalid_argument("ribbon fluid: the end cap must be at most half the length");
  }
  const double b = 0.5 * settings.width_m / half_m;
  const double s_cap = 1.0 - settings.end_cap_m / half_m;
  const std::vector<Node> nodes = Nodes(pieces, half_m);
  const int n_nodes = static_cast<int>(nodes.size());
  const int modes = settings.modes;
  Eigen::MatrixXd legendre(n_nodes, modes);
  for (int i = 0; i < n_nodes; ++i) {
    for (int n = 0; n < modes; ++n) legendre(i, n) = boost::math::legendre_p(n, nodes[i].s);
  }
  const Eigen::MatrixXd velocity = VelocityOfModes(nodes, legendre, b, s_cap, half_m);
  // Galerkin: int P_m (operator f - 8 pi mu U) ds = 0 for every mode m.
  Eigen::MatrixXd galerkin = Eigen::MatrixXd::Zero(3 * modes, 3 * modes);
  Eigen::MatrixXd rigid = Eigen::MatrixXd::Zero(3 * modes, 6 * bodies);
  for (int i = 0; i < n_nodes; ++i) {
    Eigen::Matrix<double, 3, 6> motion;  // U = -[r - c]x w + v
    motion << -CrossMatrix(nodes[i].point_W - c), Eigen::Matrix3d::Identity();
    for (int m = 0; m < modes; ++m) {
      const double weight = nodes[i].weight * legendre(i, m);
      galerkin.middleRows<3>(3 * m) += weight * velocity.middleRows<3>(3 * i);
      rigid.block<3, 6>(3 * m, 6 * nodes[i].body) += (8.0 * kPi * viscosity_Pa_s * weight) * motion;
    }
  }
  const Eigen::MatrixXd coefficients = galerkin.partialPivLu().solve(rigid);
  // The wrench [torque about c; force] of f dl on each body.
  Eigen::MatrixXd resistance = Eigen::MatrixXd::Zero(6 * bodies, 6 * bodies);
  for (int i = 0; i < n_nodes; ++i) {
    Eigen::MatrixXd force = Eigen::MatrixXd::Zero(3, 6 * bodies);
    for (int n = 0; n < modes; ++n) force += legendre(i, n) * coefficients.middleRows<3>(3 * n);
    force *= nodes[i].weight * half_m;
    const int row = 6 * nodes[i].body;
    resistance.middleRows<3>(row) += CrossMatrix(nodes[i].point_W - c) * force;
    resistance.middleRows<3>(row + 3) += force;
  }
  return 0.5 * (resistance + resistance.transpose());  // reciprocal theorem
}

std::vector<RibbonPiece> StraightRibbon(const std::vector<double>& lengths_m) {
  std::vector<RibbonPiece> pieces;
  double start_m = 0.0;
  for (double length_m : lengths_m) {
    RibbonPiece piece;
    piece.start_W = piece.hydro_start_W = Eigen::Vector3d(start_m, 0, 0);
    piece.tangent_W = Eigen::Vector3d::UnitX();
    piece.width_axis_W = Eigen::Vector3d::UnitZ();
    piece.length_m = length_m;
    pieces.push_back(piece);
    start_m += length_m;
  }
  return pieces;
}

bool RibbonFluid::Chosen(const RftDrag& /*segments*/, const RftDragOverrides& overrides) {
  return overrides.ribbon.has_value();
}

std::unique_ptr<Fluid> RibbonFluid::Make(const mjModel* m, const RftDrag& segments,
                                         const RftDragOverrides& overrides) {
  return std::make_unique<RibbonFluid>(m, segments, *overrides.ribbon);
}

RibbonFluid::RibbonFluid(const mjModel* m, const RftDrag& segments, const RibbonSettings& ribbon)
    : DenseResistanceFluid(m, segments, "ribbon fluid"), settings_(ribbon) {
  if (settings_.width_m == 0.0) settings_.width_m = StripWidth_m(m);
  if (settings_.end_cap_m == 0.0) settings_.end_cap_m = 0.5 * settings_.width_m;
  settings_.Validate();
}

std::vector<RibbonPiece> RibbonFluid::Pieces(const mjModel* m, const mjData* d) const {
  const std::vector<Segment> segments = rft().Segments(m, d);
  std::vector<RibbonPiece> pieces;
  for (size_t i = 0; i < segments.size(); ++i) {
    RibbonPiece piece;
    piece.tangent_W = segments[i].tangent_W;
    piece.length_m = segments[i].length_m;
    piece.start_W = segments[i].center_W - 0.5 * piece.length_m * piece.tangent_W;
    // Laid end to end: the hinges' gaps closed.
    piece.hydro_start_W = pieces.empty() ? piece.start_W
                                         : Eigen::Vector3d(pieces.back().hydro_start_W +
                                                           pieces.back().length_m *
                                                               pieces.back().tangent_W);
    piece.width_axis_W = Eigen::Vector3d::UnitZ();  // the generated models' width
    piece.body = body_of_geom(static_cast<int>(i));
    pieces.push_back(piece);
  }
  return pieces;
}

Eigen::MatrixXd RibbonFluid::ComputeResistance(const mjModel* m, const mjData* d,
                                               const Eigen::Vector3d& origin_W) const {
  return RibbonBodyResistance(Pieces(m, d), body_count(), origin_W, settings_,
                              rft().config().viscosity_Pa_s);
}

double RibbonFluid::TowingDrag_N(double speed_m_s) const {
  const Eigen::MatrixXd r =
      RibbonBodyResistance(StraightRibbon(rft().SegmentLengths_m()), 1, Eigen::Vector3d::Zero(),
                           settings_, rft().config().viscosity_Pa_s);
  return r(3, 3) * speed_m_s;
}

}  // namespace ipmc

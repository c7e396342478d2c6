#include "plugin/fluid/ribbon_fluid.h"

#include <Eigen/LU>
#include <array>
#include <boost/math/quadrature/gauss.hpp>
#include <cmath>
#include <optional>
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
const std::vector<double> kPanelBreaks = {0.0, 1.0 / 8, 0.5, 7.0 / 8, 1.0};
// Between pieces apart (FarApart), where the kernel is smooth on both,
// one panel each: Gauss-Legendre's error there is below 1e-9 of the
// pair's part (the kernel's nearest singularity half a piece beyond the
// piece's end: (2 + sqrt 3)^-16).
const std::vector<double> kWholePiece = {0.0, 1.0};

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

// The quadrature nodes, piece by piece, on the panels `breaks` of each.
std::vector<Node> Nodes(const std::vector<RibbonPiece>& pieces, double half_length_m,
                        const std::vector<double>& breaks) {
  using Gauss = boost::math::quadrature::gauss<double, kGaussOrder>;
  std::vector<Node> nodes;
  double along_m = 0.0;
  for (size_t p = 0; p < pieces.size(); ++p) {
    const RibbonPiece& piece = pieces[p];
    const Eigen::Vector3d t = piece.tangent_W.normalized();
    const Eigen::Vector3d w = (piece.width_axis_W - piece.width_axis_W.dot(t) * t).normalized();
    for (size_t k = 0; k + 1 < breaks.size(); ++k) {
      const double middle_m = 0.5 * (breaks[k] + breaks[k + 1]) * piece.length_m;
      const double half_m = 0.5 * (breaks[k + 1] - breaks[k]) * piece.length_m;
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

std::vector<double> Weights(const std::vector<Node>& nodes) {
  std::vector<double> weights;
  for (const Node& node : nodes) weights.push_back(node.weight);
  return weights;
}

// Where each piece's nodes start in `nodes` (they come piece by piece),
// and one past the last node.
std::vector<int> PieceStarts(const std::vector<Node>& nodes) {
  std::vector<int> starts;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (i == 0 || nodes[i].piece != nodes[i - 1].piece) starts.push_back(static_cast<int>(i));
  }
  starts.push_back(static_cast<int>(nodes.size()));
  return starts;
}

// P_n(s_i) for n < modes: row i, column n. Bonnet's recurrence,
// (n + 1) P_{n+1} = (2 n + 1) s P_n - n P_{n-1}.
Eigen::MatrixXd LegendreAtNodes(const std::vector<Node>& nodes, int modes) {
  Eigen::MatrixXd legendre(nodes.size(), modes);
  for (size_t i = 0; i < nodes.size(); ++i) {
    const double s = nodes[i].s;
    legendre(i, 0) = 1.0;
    if (modes > 1) legendre(i, 1) = s;
    for (int n = 1; n + 1 < modes; ++n) {
      legendre(i, n + 1) = ((2 * n + 1) * s * legendre(i, n) - n * legendre(i, n - 1)) / (n + 1);
    }
  }
  return legendre;
}

// Lg(s) = ln(16 (1 - s^2) / (b^2 rho^2)) for the rectangle with elliptic
// caps beyond s_cap, where it is constant.
double LogTerm(double s, double b, double s_cap) {
  if (std::abs(s) >= s_cap) return std::log(16.0 * (1.0 - s_cap * s_cap) / (b * b));
  return std::log(16.0 * (1.0 - s * s) / (b * b));
}

// A quadrature of the ribbon: its nodes, w_i P_n(s_i) (row i, column n)
// and where each piece's nodes start (PieceStarts).
struct Quadrature {
  std::vector<Node> nodes;
  Eigen::MatrixXd legendre;
  Eigen::MatrixXd weighted;
  std::vector<int> starts;
};

Quadrature MakeQuadrature(const std::vector<RibbonPiece>& pieces, double half_length_m,
                          const std::vector<double>& breaks, int modes) {
  Quadrature quadrature;
  quadrature.nodes = Nodes(pieces, half_length_m, breaks);
  quadrature.legendre = LegendreAtNodes(quadrature.nodes, modes);
  const std::vector<double> weights = Weights(quadrature.nodes);
  quadrature.weighted =
      Eigen::VectorXd::Map(weights.data(), static_cast<Eigen::Index>(weights.size())).asDiagonal() *
      quadrature.legendre;
  quadrature.starts = PieceStarts(quadrature.nodes);
  return quadrature;
}

// Pieces p and q (on the ribbon the fluid sees) are apart if another lies
// between them and their centres are at least half the longer one farther
// apart than if they touched.
bool FarApart(const std::vector<RibbonPiece>& pieces, int p, int q) {
  if (std::abs(p - q) < 2) return false;
  const RibbonPiece &a = pieces[p], &c = pieces[q];
  const Eigen::Vector3d centre_a = a.hydro_start_W + 0.5 * a.length_m * a.tangent_W;
  const Eigen::Vector3d centre_c = c.hydro_start_W + 0.5 * c.length_m * c.tangent_W;
  return (centre_a - centre_c).norm() >=
         0.5 * (a.length_m + c.length_m) + 0.5 * std::max(a.length_m, c.length_m);
}

// galerkin.block<3, 3>(3 m, 3 n) += pattern * scalars(m, n) for all m, n.
void AddPattern(const Eigen::Matrix3d& pattern, const Eigen::MatrixXd& scalars,
                Eigen::MatrixXd* galerkin) {
  for (int n = 0; n < scalars.cols(); ++n) {
    for (int m = 0; m < scalars.rows(); ++m) {
      galerkin->block<3, 3>(3 * m, 3 * n) += scalars(m, n) * pattern;
    }
  }
}

// The Galerkin projection of 8 pi mu U for the force density P_n e_a,
// int P_m(s) 8 pi mu U(s) ds (3M x 3M, block (m, n) the 3 x 3 of e_a),
// from the quadrature `weighted` = w_i P_n(s_i). On each piece P (its own
// t, w): the local term Lg (I + t t) - 2 t t + 2 w w and the straight
// part's -2 H_n (I + t t) P_n, with the Gram matrices G = sum w P_m P_n and
// G_L = sum w Lg P_m P_n. Between pieces P and Q, the regular remainder
//   [(1 / d - 1 / |s - s'|) I - t_P t_P / |s - s'| + R R / d^3]
// in its 8 scalar parts (the I part, the t t part, R R's xx, yy, xy, zz,
// xz, yz), each projected as weighted_P^T K weighted_Q; the kernel is
// symmetric, so pair (Q, P) takes the transpose. Pieces far apart
// (FarApart) take the quadrature `whole`, one panel a piece, the others
// `graded`.
Eigen::MatrixXd GalerkinOperator(const std::vector<RibbonPiece>& ribbon, const Quadrature& graded,
                                 const Quadrature& whole, const RibbonArclengthPart& arclength,
                                 double b, double s_cap, double half_length_m) {
  const std::vector<Node>& nodes = graded.nodes;
  const Eigen::MatrixXd& weighted = graded.weighted;
  const Eigen::MatrixXd& legendre = graded.legendre;
  const int modes = static_cast<int>(legendre.cols());
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  Eigen::MatrixXd galerkin = Eigen::MatrixXd::Zero(3 * modes, 3 * modes);
  const std::vector<int>& starts = graded.starts;
  const int pieces = static_cast<int>(starts.size()) - 1;
  // The harmonic numbers H_n = 1 + 1/2 + ... + 1/n, H_0 = 0.
  Eigen::RowVectorXd harmonic = Eigen::RowVectorXd::Zero(modes);
  for (int n = 1; n < modes; ++n) harmonic[n] = harmonic[n - 1] + 1.0 / n;
  std::vector<Eigen::Matrix3d> tangents(pieces);
  for (int p = 0; p < pieces; ++p) {
    const int p0 = starts[p], np = starts[p + 1] - p0;
    const Node& node = nodes[p0];
    tangents[p] = node.tangent_W * node.tangent_W.transpose();
    Eigen::VectorXd log_term(np);
    for (int i = 0; i < np; ++i) log_term[i] = LogTerm(nodes[p0 + i].s, b, s_cap);
    const auto w = weighted.middleRows(p0, np);
    const Eigen::MatrixXd gram = w.transpose() * legendre.middleRows(p0, np);
    const Eigen::MatrixXd log_gram =
        w.transpose() * log_term.asDiagonal() * legendre.middleRows(p0, np);
    AddPattern(identity + tangents[p], log_gram - 2.0 * gram * harmonic.asDiagonal(), &galerkin);
    AddPattern(-2.0 * tangents[p] + 2.0 * node.width_W * node.width_W.transpose(), gram,
               &galerkin);
  }
  constexpr int kParts = 8;
  std::array<Eigen::Matrix3d, kParts> patterns;
  patterns[0] = identity;
  patterns[1].setZero();  // the t t part: per piece, below
  const auto outer = [](int a, int c) {
    Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
    e(a, c) = e(c, a) = 1.0;
    return e;
  };
  patterns[2] = outer(0, 0);
  patterns[3] = outer(1, 1);
  patterns[4] = outer(0, 1);
  patterns[5] = outer(2, 2);
  patterns[6] = outer(0, 2);
  patterns[7] = outer(1, 2);
  // The parts side by side, np x (parts nq): one product W_P^T [K_0 K_1
  // ...] for all of them, then each part's block times W_Q.
  Eigen::MatrixXd kernel, left;
  const double inverse_half_length = 1.0 / half_length_m;
  // A ribbon whose centreline lies in a plane z = const has R_z = 0: the
  // parts with z (zz, xz, yz) vanish and are left out.
  bool planar = true;
  for (const Node& node : nodes) planar = planar && node.hydro_W.z() == nodes[0].hydro_W.z();
  const int parts = planar ? 5 : kParts;
  // The projections summed before their patterns are added: per part
  // (its pattern the same for every pair), and the t t part per piece.
  std::array<Eigen::MatrixXd, kParts> part_sums;
  for (Eigen::MatrixXd& sum : part_sums) sum.setZero(modes, modes);
  std::vector<Eigen::MatrixXd> tangent_sums(pieces, Eigen::MatrixXd::Zero(modes, modes));
  Eigen::MatrixXd projected;
  for (int p = 0; p < pieces; ++p) {
    for (int q = p + 1; q < pieces; ++q) {
      const Quadrature& pair = FarApart(ribbon, p, q) ? whole : graded;
      const int p0 = pair.starts[p], np = pair.starts[p + 1] - p0;
      const int q0 = pair.starts[q], nq = pair.starts[q + 1] - q0;
      // The kernel's shape-dependent parts: 1 / d (slot 0) and R R / d^3
      // (part k >= 2 in slot k - 1); the 1 / |s - s'| of the I and t t
      // parts is the arclength part, the same for every shape.
      kernel.resize(np, (parts - 1) * nq);
      for (int c = 0; c < nq; ++c) {
        for (int a = 0; a < np; ++a) {
          const Node& na = pair.nodes[p0 + a];
          const Node& nc = pair.nodes[q0 + c];
          const Eigen::Vector3d r = (na.hydro_W - nc.hydro_W) * inverse_half_length;
          const double inverse_distance = 1.0 / r.norm();
          const double k = inverse_distance * inverse_distance * inverse_distance;
          kernel(a, c) = inverse_distance;
          kernel(a, nq + c) = k * r.x() * r.x();
          kernel(a, 2 * nq + c) = k * r.y() * r.y();
          kernel(a, 3 * nq + c) = k * r.x() * r.y();
          if (planar) continue;
          kernel(a, 4 * nq + c) = k * r.z() * r.z();
          kernel(a, 5 * nq + c) = k * r.x() * r.z();
          kernel(a, 6 * nq + c) = k * r.y() * r.z();
        }
      }
      left.noalias() = pair.weighted.middleRows(p0, np).transpose() * kernel;
      const Eigen::MatrixXd& inverse_ds = arclength.Projection(p, q, &pair == &whole);
      tangent_sums[p] += inverse_ds;
      tangent_sums[q] += inverse_ds.transpose();
      for (int part = 0; part < parts; ++part) {
        if (part == 1) continue;
        const int slot = part == 0 ? 0 : part - 1;
        projected.noalias() = left.middleCols(slot * nq, nq) * pair.weighted.middleRows(q0, nq);
        if (part == 0) projected -= inverse_ds;
        part_sums[part] += projected + projected.transpose();
      }
    }
  }
  for (int part = 0; part < parts; ++part) {
    if (part != 1) AddPattern(patterns[part], part_sums[part], &galerkin);
  }
  for (int p = 0; p < pieces; ++p) AddPattern(-tangents[p], tangent_sums[p], &galerkin);
  return galerkin;
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
  if (!(secant_reach_rad >= 0.0) || !std::isfinite(secant_reach_rad)) {
    throw std::invalid_argument("ribbon fluid: the secant's reach must be finite and >= 0");
  }
  if (!(fit_tolerance >= 0.0) || !std::isfinite(fit_tolerance)) {
    throw std::invalid_argument("ribbon fluid: the fit's tolerance must be finite and >= 0");
  }
}

RibbonArclengthPart::RibbonArclengthPart(const std::vector<double>& lengths_m, int modes)
    : pieces_(static_cast<int>(lengths_m.size())), modes_(modes) {
  const std::vector<RibbonPiece> straight = StraightRibbon(lengths_m);
  double length_m = 0.0;
  for (double piece_m : lengths_m) length_m += piece_m;
  graded_.resize(pieces_ * pieces_);
  whole_.resize(pieces_ * pieces_);
  for (bool whole : {false, true}) {
    const Quadrature quadrature =
        MakeQuadrature(straight, 0.5 * length_m, whole ? kWholePiece : kPanelBreaks, modes);
    for (int p = 0; p < pieces_; ++p) {
      for (int q = p + 1; q < pieces_; ++q) {
        const int p0 = quadrature.starts[p], np = quadrature.starts[p + 1] - p0;
        const int q0 = quadrature.starts[q], nq = quadrature.starts[q + 1] - q0;
        Eigen::MatrixXd kernel(np, nq);
        for (int c = 0; c < nq; ++c) {
          for (int a = 0; a < np; ++a) {
            const double ds = quadrature.nodes[p0 + a].s - quadrature.nodes[q0 + c].s;
            kernel(a, c) = 1.0 / std::abs(ds);
          }
        }
        (whole ? whole_ : graded_)[p * pieces_ + q] =
            quadrature.weighted.middleRows(p0, np).transpose() * kernel *
            quadrature.weighted.middleRows(q0, nq);
      }
    }
  }
}

const Eigen::MatrixXd& RibbonArclengthPart::Projection(int p, int q, bool whole) const {
  return (whole ? whole_ : graded_)[p * pieces_ + q];
}

Eigen::MatrixXd RibbonBodyResistance(const std::vector<RibbonPiece>& pieces, int bodies,
                                     const Eigen::Vector3d& c, const RibbonSettings& settings,
                                     double viscosity_Pa_s, const RibbonArclengthPart* arclength) {
  settings.Validate();
  double length_m = 0.0;
  for (const RibbonPiece& piece : pieces) length_m += piece.length_m;
  const double half_m = 0.5 * length_m;
  if (!(settings.end_cap_m <= half_m)) {
    throw std::invalid_argument("ribbon fluid: the end cap must be at most half the length");
  }
  const double b = 0.5 * settings.width_m / half_m;
  const double s_cap = 1.0 - settings.end_cap_m / half_m;
  const int modes = settings.modes;
  const Quadrature graded = MakeQuadrature(pieces, half_m, kPanelBreaks, modes);
  const Quadrature whole = MakeQuadrature(pieces, half_m, kWholePiece, modes);
  const std::vector<Node>& nodes = graded.nodes;
  const int n_nodes = static_cast<int>(nodes.size());
  const Eigen::MatrixXd& weighted = graded.weighted;
  // Galerkin: int P_m (operator f - 8 pi mu U) ds = 0 for every mode m.
  std::optional<RibbonArclengthPart> own_arclength;
  if (!arclength) {
    std::vector<double> lengths_m;
    for (const RibbonPiece& piece : pieces) lengths_m.push_back(piece.length_m);
    arclength = &own_arclength.emplace(lengths_m, modes);
  }
  const Eigen::MatrixXd galerkin =
      GalerkinOperator(pieces, graded, whole, *arclength, b, s_cap, half_m);
  // The projected rigid motions, int P_m 8 pi mu U ds with U = -[r - c]x w
  // + v on each body: 8 pi mu [-[M1_m - M0_m c]x, M0_m I] from the body's
  // moments M0_m = sum w_i P_m(s_i), M1_m = sum w_i P_m(s_i) r_i.
  Eigen::MatrixXd moment0 = Eigen::MatrixXd::Zero(modes, bodies);
  Eigen::MatrixXd moment1 = Eigen::MatrixXd::Zero(3 * modes, bodies);
  for (int i = 0; i < n_nodes; ++i) {
    for (int m = 0; m < modes; ++m) {
      moment0(m, nodes[i].body) += weighted(i, m);
      moment1.block<3, 1>(3 * m, nodes[i].body) += weighted(i, m) * nodes[i].point_W;
    }
  }
  const double scale = 8.0 * kPi * viscosity_Pa_s;
  Eigen::MatrixXd rigid = Eigen::MatrixXd::Zero(3 * modes, 6 * bodies);
  for (int body = 0; body < bodies; ++body) {
    for (int m = 0; m < modes; ++m) {
      const Eigen::Vector3d arm = moment1.block<3, 1>(3 * m, body) - moment0(m, body) * c;
      rigid.block<3, 3>(3 * m, 6 * body) = -scale * CrossMatrix(arm);
      rigid.block<3, 3>(3 * m, 6 * body + 3) = scale * moment0(m, body) * Eigen::Matrix3d::Identity();
    }
  }
  const Eigen::MatrixXd coefficients = galerkin.partialPivLu().solve(rigid);
  // The wrench [torque about c; force] of f dl on each body, f = sum_n P_n
  // f_n: sum over its nodes of [[r - c]x; I] w_i L P_n(s_i) f_n, which is
  // rigid^T f_n L / (8 pi mu) (the same moments).
  const Eigen::MatrixXd resistance = (half_m / scale) * (rigid.transpose() * coefficients);
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

namespace {

// The parameter (FluidParameter, fluid_model.h).
FluidParameter Modes() {
  return SetsResolution(IntegerParameter(
      "ribbon_modes", "ipmc_fluid_ribbon_modes", kDefaultRibbonModes, 1, kMaxRibbonModes, 6,
      "Legendre modes of each component of the ribbon's force density along the whole strip "
      "(slender-ribbon theory; from 10 on they resolve wavelengths near the strip's width, "
      "where the theory's resistance stops being positive: docs/FLUIDS.md)"));
}

const CacheParameters& Cache() {
  static const CacheParameters cache("ribbon", "the ribbon's resistance", "Cost on flexible links");
  return cache;
}

}  // namespace

std::vector<FluidParameter> RibbonFluid::Parameters() {
  return {Modes(), Cache().ShapeToleranceRad(), Cache().SecantReachRad(), Cache().FitTolerance()};
}

std::unique_ptr<Fluid> RibbonFluid::Make(const mjModel* m, const RftDrag& segments,
                                         const RftDragOverrides& overrides) {
  const auto value = [&](const FluidParameter& p) {
    return *FluidParameterValue(m, overrides, "ribbon fluid", p);
  };
  RibbonSettings ribbon;
  ribbon.modes = static_cast<int>(value(Modes()));
  ribbon.shape_tolerance_rad = value(Cache().ShapeToleranceRad());
  ribbon.secant_reach_rad = value(Cache().SecantReachRad());
  ribbon.fit_tolerance = value(Cache().FitTolerance());
  return std::make_unique<RibbonFluid>(m, segments, ribbon);
}

RibbonFluid::RibbonFluid(const mjModel* m, const RftDrag& segments, const RibbonSettings& ribbon)
    : DenseResistanceFluid(m, segments, "ribbon fluid"), settings_(ribbon) {
  if (settings_.width_m == 0.0) settings_.width_m = StripWidth_m(m);
  if (settings_.end_cap_m == 0.0) settings_.end_cap_m = 0.5 * settings_.width_m;
  settings_.Validate();
  arclength_.emplace(segments.SegmentLengths_m(), settings_.modes);
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
                              rft().config().viscosity_Pa_s, &*arclength_);
}

double RibbonFluid::TowingDrag_N(double speed_m_s) const {
  const Eigen::MatrixXd r =
      RibbonBodyResistance(StraightRibbon(rft().SegmentLengths_m()), 1, Eigen::Vector3d::Zero(),
                           settings_, rft().config().viscosity_Pa_s, &*arclength_);
  return r(3, 3) * speed_m_s;
}

}  // namespace ipmc

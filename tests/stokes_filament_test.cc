// The Stokes-flow step (ipmc::Step with ipmc_dynamics = stokes) against the linear
// elastohydrodynamics of a passive elastic filament whose base angle is
// driven, theta(0, t) = eps cos(omega t), in RFT drag (Lauga, "Floppy
// swimming", PRE 75, 041916, 2007; Wiggins & Goldstein, PRL 80, 3879, 1998):
//   xi_n y_t = -E I y_xxxx,  y(0) = 0, y_x(0) = eps cos(omega t),
//   y_xx(L) = y_xxx(L) = 0,
// whose periodic solution y = Re(Y(x) e^(i omega t)) solves
// Y'''' = -i (Sp / L)^4 Y with the sperm number Sp = L (xi_n omega / E I)^(1/4),
// and whose mean propulsive force is (to second order in eps)
//   <F_x> = (xi_n - xi_t) int_0^L <y_t y_x> dx
//         = (xi_n - xi_t) / 2 int_0^L Re(i omega Y conj(Y')) dx.
// The discrete chain: n rigid segments of l = L / n joined by hinges of
// stiffness E I / l (E I / (l / 2) at the base, whose other side is the
// driven clamp), as the model generator builds a link
// (plugin/actuators/ipmc_actuators.h); the clamp's angle is a very stiff
// hinge whose spring reference follows the drive. The tip's complex
// amplitude and the mean force converge to the theory as n grows, second
// order (docs/DYNAMICS.md, "Validation", has the whole table). Relative
// errors measured at 4000 steps per period, tip amplitude / mean force:
//   Sp  n = 4          8              16             32             64
//   1   4.35e-3/.0885  1.09e-3/.0225  2.86e-4/.0058  1.09e-4/.0015  8.63e-5/.0005
//   2   4.30e-2/.153   1.12e-2/.0409  3.02e-3/.0110  1.11e-3/.0034  7.72e-4/.0015
//   5   2.51e-1/.581   7.32e-2/.192   1.95e-2/.0522  5.42e-3/.0140  1.97e-3/.0042
//   10  6.49e-1/.946   2.11e-1/.564   5.93e-2/.185   1.65e-2/.0501  5.50e-3/.0134
// about 0.17 (Sp / n)^2 on the tip and 0.51 (Sp / n)^2 on the force: 1 % at
// n = 32 for Sp = 10 would need constants below 0.10, which neither the
// polygon through the exact curve (0.28 on the force) nor any of the end
// treatments tried below reaches.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/simulation.h"

namespace ipmc {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = 3.14159265358979323846;

// The paper's strip (README, "Flexible links"): E I [N m^2], xi_n, xi_t
// [N s/m^2] (xi_t = xi_n / 2, the slender-body ratio), L [m].
constexpr double kBendingStiffness = 9.77e-7;
constexpr double kXiNormal = 2.58e-3;
constexpr double kXiTangential = 0.5 * kXiNormal;
constexpr double kLength_m = 31e-3;
constexpr double kDriveAngle_rad = 0.01;  // eps: small, the theory is linear

double Omega_rad_s(double sperm_number) {
  return std::pow(sperm_number, 4) * kBendingStiffness / (kXiNormal * std::pow(kLength_m, 4));
}

// The linear theory: Y(x) = sum_m a_m exp(r_m x'), r_m^4 = -i k^4,
// k = Sp / L, with x' = x for the roots decaying from the base and
// x' = x - L for those growing towards the tip (well conditioned for any Sp).
class LinearFilament {
 public:
  explicit LinearFilament(double sperm_number) : k_(sperm_number / kLength_m) {
    Eigen::Matrix4cd a;
    Eigen::Vector4cd b(0, kDriveAngle_rad, 0, 0);
    for (int m = 0; m < 4; ++m) {
      root_[m] = k_ * std::polar(1.0, -kPi / 8 + m * kPi / 2);
      shift_[m] = root_[m].real() > 0 ? kLength_m : 0.0;
      for (int order = 0; order < 2; ++order) {  // Y(0) = 0, Y'(0) = eps
        a(order, m) = std::pow(root_[m], order) * std::exp(-root_[m] * shift_[m]);
      }
      for (int order = 2; order < 4; ++order) {  // Y''(L) = Y'''(L) = 0
        a(order, m) = std::pow(root_[m], order) * std::exp(root_[m] * (kLength_m - shift_[m]));
      }
    }
    coefficient_ = a.fullPivLu().solve(b);
  }
  Complex Derivative(double x, int order) const {
    Complex y = 0;
    for (int m = 0; m < 4; ++m) {
      y += coefficient_[m] * std::pow(root_[m], order) * std::exp(root_[m] * (x - shift_[m]));
    }
    return y;
  }
  // <F_x> [N] by Simpson's rule on 2000 intervals.
  double MeanForce_N(double omega) const {
    const int intervals = 2000;
    double sum = 0;
    for (int i = 0; i <= intervals; ++i) {
      const double x = kLength_m * i / intervals;
      const double weight = (i == 0 || i == intervals) ? 1 : (i % 2 ? 4 : 2);
      const Complex integrand =
          Complex(0, omega) * Derivative(x, 0) * std::conj(Derivative(x, 1));
      sum += weight * integrand.real();
    }
    return (kXiNormal - kXiTangential) / 2 * sum * kLength_m / intervals / 3;
  }
  // The same force on the polygon of n straight segments through the
  // theory's own shape at the nodes x_i = i L / n: what a chain of rigid
  // segments would feel if its joints lay exactly on the continuum's curve.
  double PolygonMeanForce_N(double omega, int segments) const {
    std::vector<double> nodes_m;
    for (int j = 0; j <= segments; ++j) nodes_m.push_back(kLength_m * j / segments);
    return PolygonMeanForce_N(omega, nodes_m);
  }
  // The same through the theory's shape at any nodes 0 = x_0 < ... = L.
  double PolygonMeanForce_N(double omega, const std::vector<double>& nodes_m) const {
    double sum = 0;
    for (size_t j = 0; j + 1 < nodes_m.size(); ++j) {
      const double l = nodes_m[j + 1] - nodes_m[j];
      const Complex y0 = Derivative(nodes_m[j], 0), y1 = Derivative(nodes_m[j + 1], 0);
      sum += (Complex(0, omega) * 0.5 * (y0 + y1) * std::conj((y1 - y0) / l)).real() * l;
    }
    return (kXiNormal - kXiTangential) / 2 * sum;
  }

 private:
  double k_;
  Complex root_[4];
  double shift_[4];
  Eigen::Vector4cd coefficient_;
};

std::string Num(double value) {
  std::ostringstream out;
  out.precision(12);
  out << value;
  return out.str();
}

// How the chain treats its ends: the first and last segments' lengths as
// fractions of the others', and the base hinge's stiffness as a multiple
// of E I / (l_0 / 2). Each hinge between two segments has E I over the
// distance between their midpoints. The default is the generator's chain.
struct ChainEnds {
  double first = 1.0, last = 1.0, base_factor = 1.0;
};

std::vector<double> SegmentLengths_m(int segments, const ChainEnds& ends) {
  const double unit = kLength_m / (segments - 2 + ends.first + ends.last);
  std::vector<double> lengths(segments, unit);
  lengths.front() = ends.first * unit;
  lengths.back() = ends.last * unit;
  return lengths;
}

// The driven chain in Stokes mode (the drive hinge's stiffness 1e6 times a
// segment's: its angle follows the reference within 1e-6 relative).
std::string ChainMjcf(int segments, double timestep_s, const ChainEnds& ends) {
  const double l = kLength_m / segments;
  const std::vector<double> lengths = SegmentLengths_m(segments, ends);
  std::ostringstream xml;
  xml << "<mujoco>\n  <option timestep=\"" << Num(timestep_s)
      << "\" gravity=\"0 0 0\"><flag contact=\"disable\"/></option>\n"
      << "  <custom>\n"
      << "    <numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"1e-3\"/>\n"
      << "    <text name=\"ipmc_rft_coefficients\" data=\"direct\"/>\n"
      << "    <numeric name=\"ipmc_rft_xi_normal_N_s_m2\" data=\"" << Num(kXiNormal) << "\"/>\n"
      << "    <numeric name=\"ipmc_rft_xi_tangential_N_s_m2\" data=\"" << Num(kXiTangential)
      << "\"/>\n"
      << "    <text name=\"ipmc_dynamics\" data=\"stokes\"/>\n  </custom>\n  <worldbody>\n"
      << "    <body name=\"clamp\">\n"
      << "      <inertial pos=\"0 0 0\" mass=\"1e-6\" diaginertia=\"1e-12 1e-12 1e-12\"/>\n"
      << "      <joint name=\"drive\" type=\"hinge\" axis=\"0 0 1\" stiffness=\""
      << Num(1e6 * kBendingStiffness / l) << "\"/>\n";
  for (int s = 0; s < segments; ++s) {
    const double share = s == 0 ? 0.5 * lengths[0] / ends.base_factor
                                : 0.5 * (lengths[s - 1] + lengths[s]);
    xml << "<body name=\"s" << s << "\" pos=\"" << (s == 0 ? 0.0 : lengths[s - 1]) << " 0 0\">\n"
        << "<joint type=\"hinge\" axis=\"0 0 1\" stiffness=\"" << Num(kBendingStiffness / share)
        << "\"/>\n<geom name=\"g" << s << "\" type=\"box\" pos=\"" << Num(0.5 * lengths[s])
        << " 0 0\" size=\"" << Num(0.5 * lengths[s]) << " 1e-4 1e-3\" density=\"1e7\"/>\n";
  }
  for (int s = 0; s < segments; ++s) xml << "</body>\n";
  xml << "    </body>\n  </worldbody>\n</mujoco>\n";
  return xml.str();
}

struct ChainResponse {
  Complex tip;           // complex amplitude of the tip's y [m]
  double mean_force_N;   // <F_x> of the drag on the filament
};

// Starts from the theory's shape at t = 0 (so no slow transient of the
// first bending mode), runs `periods`, and projects the last one.
ChainResponse RunChain(int segments, double sperm_number, int steps_per_period, int periods,
                       const ChainEnds& ends) {
  const double omega = Omega_rad_s(sperm_number);
  const double period_s = 2 * kPi / omega;
  const double h = period_s / steps_per_period;
  Simulation sim(LoadModelString(ChainMjcf(segments, h, ends)), "driven filament");
  mjModel* m = sim.model();
  mjData* d = sim.data();
  const LinearFilament theory(sperm_number);
  const std::vector<double> lengths = SegmentLengths_m(segments, ends);
  const double l = lengths.back();
  // Segment s lies at the theory's slope angle at its middle, relative to
  // the one before it.
  d->qpos[0] = kDriveAngle_rad;
  double previous = kDriveAngle_rad, start_m = 0;
  for (int s = 0; s < segments; ++s) {
    const double angle = std::atan(theory.Derivative(start_m + 0.5 * lengths[s], 1).real());
    start_m += lengths[s];
    d->qpos[1 + s] = angle - previous;
    previous = angle;
  }
  EXPECT_TRUE(IsAttached(d) && FluidOf(d).drag);
  const int last_geom = m->ngeom - 1;
  ChainResponse response{0.0, 0.0};
  for (int period = 0; period < periods; ++period) {
    for (int step = 1; step <= steps_per_period; ++step) {
      const double t_end = (period * steps_per_period + step) * h;
      m->qpos_spring[0] = kDriveAngle_rad * std::cos(omega * t_end);
      std::vector<double> start(d->qpos, d->qpos + m->nq);
      sim.Step(false);
      if (period + 1 < periods) continue;
      // The tip at t_end (positions q_(n+1)).
      mj_kinematics(m, d);
      const mjtNum* xmat = d->geom_xmat + 9 * last_geom;
      const double tip_y = d->geom_xpos[3 * last_geom + 1] + 0.5 * l * xmat[3];
      response.tip += tip_y * std::exp(Complex(0, -omega * t_end)) * (2.0 / steps_per_period);
      // The drag at the step's midpoint (q_n + q_(n+1)) / 2 with its
      // velocity v = (q_(n+1) - q_n) / h (d->qvel, the velocity the step
      // solved for): centred, so the sum over a period has no O(h) bias
      // (at the end point, v . q sums to h/2 <v^2>). The fluid's force on
      // the filament is the sum of its forces on the bodies.
      std::vector<double> end(d->qpos, d->qpos + m->nq);
      for (int i = 0; i < m->nq; ++i) d->qpos[i] = 0.5 * (start[i] + end[i]);
      double force_x = 0;
      for (const BodyFluidForce& body : FluidForces(m, d)) force_x += body.force_N[0];
      mju_copy(d->qpos, end.data(), m->nq);
      response.mean_force_N += force_x / steps_per_period;
    }
  }
  return response;
}

struct Errors {
  double tip, force;
  double polygon_force;  // of the polygon through the theory's nodes
};

Errors RelativeErrors(int segments, double sperm_number, int steps_per_period,
                      const ChainEnds& ends = {}) {
  const LinearFilament theory(sperm_number);
  const Complex tip = theory.Derivative(kLength_m, 0);
  const double force = theory.MeanForce_N(Omega_rad_s(sperm_number));
  const ChainResponse chain = RunChain(segments, sperm_number, steps_per_period, 2, ends);
  const double polygon = theory.PolygonMeanForce_N(Omega_rad_s(sperm_number), segments);
  return {std::abs(chain.tip - tip) / std::abs(tip),
          std::abs(chain.mean_force_N - force) / std::abs(force),
          std::abs(polygon - force) / std::abs(force)};
}

// Steps per drive period: backward Euler's own error is about
// omega h / 2 = pi / steps, 0.08 % here.
constexpr int kStepsPerPeriod = 4000;

// Prints the table docs/DYNAMICS.md quotes ("Validation"):
//   sperm number, n, tip amplitude error, mean force error, and the mean
//   force error of the polygon through the theory's nodes.
TEST(StokesFilamentTest, ConvergesToLinearTheoryWithSegments) {
  std::printf("Sp n tip_error force_error polygon_force_error\n");
  for (const double sperm_number : {0.11, 1.0, 2.0, 5.0, 10.0}) {
    for (const int n : {4, 8, 16, 32, 64, 80}) {
      const Errors e = RelativeErrors(n, sperm_number, kStepsPerPeriod);
      std::printf("%.2f %d %.3e %.3e %.3e\n", sperm_number, n, e.tip, e.force, e.polygon_force);
      // Second order in the segment length against the decay length L / Sp
      // of the driven wave: measured tip error <= 0.28 (Sp / n)^2 plus
      // backward Euler's floor at 4000 steps per period (up to 7.4e-4, at
      // Sp = 2), force error <= 1.6 max(1, Sp)^2 / n^2 plus its floor (the
      // n = 80 rows; docs/DYNAMICS.md); tolerances twice those.
      const double h = std::max(1.0, sperm_number) / n;
      EXPECT_LT(e.tip, 0.6 * h * h + 1.5e-3) << "Sp " << sperm_number << " n " << n;
      EXPECT_LT(e.force, 3.2 * h * h + 5e-4) << "Sp " << sperm_number << " n " << n;
    }
  }
  // Within 1 % (shape and force) at n = 32 up to Sp = 2, the shape up to
  // Sp = 5; at n = 64 the shape up to Sp = 10 and the force up to Sp = 5;
  // at n = 80 both up to Sp = 10 (docs/DYNAMICS.md: n >= 8 Sp for the
  // force, half of whose error is the polygon's own).
  EXPECT_LT(RelativeErrors(32, 2.0, kStepsPerPeriod).force, 0.01);
  EXPECT_LT(RelativeErrors(32, 5.0, kStepsPerPeriod).tip, 0.01);
  const Errors fine = RelativeErrors(80, 10.0, kStepsPerPeriod);
  EXPECT_LT(fine.tip, 0.01);
  EXPECT_LT(fine.force, 0.01);
}

// The polygon through the exact curve's nodes already misses the mean
// force by about 0.27 (Sp / n)^2 (the interpolation error of the product
// y_t y_x on straight segments), so no chain of n rigid segments, however
// its joints are placed or its hinges tuned, gets within 1 % at Sp = 10
// below n = 53; the chain's own error is about twice that.
TEST(StokesFilamentTest, PolygonForceErrorIsSecondOrder) {
  for (const double sperm_number : {2.0, 10.0}) {
    const LinearFilament theory(sperm_number);
    const double omega = Omega_rad_s(sperm_number);
    const double force = theory.MeanForce_N(omega);
    for (const int n : {16, 32, 64}) {
      const double error = std::abs(theory.PolygonMeanForce_N(omega, n) / force - 1);
      const double scaled = error * n * n / (sperm_number * sperm_number);
      std::printf("Sp %.0f, n %d: polygon force error %.3e = %.3f (Sp / n)^2\n", sperm_number, n,
                  error, scaled);
      EXPECT_GT(scaled, 0.2);  // measured 0.274-0.284: second order, not smaller
      EXPECT_LT(scaled, 0.35);
    }
  }
}

// Nor does grading the segments towards the driven base, where the wave
// decays over L / Sp: at Sp = 10 the polygon of 32 segments whose lengths
// grow geometrically from the base, the last g times the first, through
// the theory's nodes misses the mean force by (measured) 2.750 % (g = 1),
// 1.700 % (2), 1.234 % (4), 1.136 % (8), 1.280 % (16): never within 1 %,
// before the chain's own error is added.
TEST(StokesFilamentTest, GradedPolygonStaysAboveOnePercentAtSpTen) {
  const double sperm_number = 10.0;
  const LinearFilament theory(sperm_number);
  const double omega = Omega_rad_s(sperm_number);
  const double force = theory.MeanForce_N(omega);
  const int n = 32;
  double best = 1.0;
  for (const double g : {1.0, 2.0, 4.0, 8.0, 16.0}) {
    const double ratio = std::pow(g, 1.0 / (n - 1));  // of consecutive lengths
    std::vector<double> nodes_m{0.0};
    double length = 1.0;
    for (int j = 0; j < n; ++j, length *= ratio) nodes_m.push_back(nodes_m.back() + length);
    for (double& x : nodes_m) x *= kLength_m / nodes_m.back();  // scaled to L
    const double error = std::abs(theory.PolygonMeanForce_N(omega, nodes_m) / force - 1);
    std::printf("Sp 10, n 32, last / first segment %.0f: polygon force error %.3e\n", g, error);
    best = std::min(best, error);
  }
  EXPECT_GT(best, 0.0105);  // measured 1.136e-2 at g = 8
  EXPECT_LT(best, 0.0125);
}

// The chain's own error does not fall below second order with a smaller
// constant by treating its ends differently: at Sp = 10, the hardest case,
// half-length segments at the driven base, at the free end or at both keep
// the error second order with constants of 0.13-0.17 (tip) and 0.33-0.53
// (force) times (Sp / n)^2 (measured; docs/DYNAMICS.md), where 1 % at
// n = 32 would need less than 0.098; a base hinge of E I / l instead of
// E I / (l / 2) (the clamp's slope imposed a whole segment away) makes it
// first order. The bounds are the measured range widened by about 1.5.
TEST(StokesFilamentTest, EndTreatmentsKeepTheSecondOrderConstant) {
  const double sperm_number = 10.0;
  struct Variant {
    const char* name;
    ChainEnds ends;
  };
  const Variant second_order[] = {{"generator's chain", {1.0, 1.0, 1.0}},
                                  {"half-length base segment", {0.5, 1.0, 1.0}},
                                  {"half-length tip segment", {1.0, 0.5, 1.0}},
                                  {"half-length end segments", {0.5, 0.5, 1.0}}};
  for (const Variant& variant : second_order) {
    for (const int n : {16, 32}) {
      const Errors e = RelativeErrors(n, sperm_number, kStepsPerPeriod, variant.ends);
      const double scale = n * n / (sperm_number * sperm_number);
      std::printf("ends %s, n %d: tip %.3e = %.3f (Sp / n)^2, force %.3e = %.3f (Sp / n)^2\n",
                  variant.name, n, e.tip, e.tip * scale, e.force, e.force * scale);
      EXPECT_GT(e.tip * scale, 0.09) << variant.name << " n " << n;
      EXPECT_LT(e.tip * scale, 0.26) << variant.name << " n " << n;
      EXPECT_GT(e.force * scale, 0.22) << variant.name << " n " << n;
      EXPECT_LT(e.force * scale, 0.8) << variant.name << " n " << n;
    }
  }
  const ChainEnds soft_base{1.0, 1.0, 0.5};
  const double coarse = RelativeErrors(16, sperm_number, kStepsPerPeriod, soft_base).tip;
  const double fine = RelativeErrors(32, sperm_number, kStepsPerPeriod, soft_base).tip;
  std::printf("ends base hinge E I / l: tip %.3e at n 16, %.3e at n 32\n", coarse, fine);
  EXPECT_LT(coarse / fine, 2.5);  // measured 1.75: first order
  EXPECT_GT(fine, 0.1);
}

}  // namespace
}  // namespace ipmc

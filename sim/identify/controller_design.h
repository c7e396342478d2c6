// Controller design for one IPMC link (paper section 5.2).
//
// (a) Fractional integrator C_I(s) = K / s^lambda (eq. 13) from the
// specifications "gain crossover w_c, phase margin PM" on a plant P given
// as a frequency function. With L = C_I P:
//   phase condition: arg L(j w_c) = -180 deg + PM, and arg C_I = -90 lambda
//     deg, so  lambda = (arg P(j w_c) + 180 deg - PM) / 90 deg;
//   gain condition: |L(j w_c)| = 1, so  K = w_c^lambda / |P(j w_c)|.
// arg P is unwrapped along a logarithmic grid from 1e-4 w_c up to w_c
// (sim/linear/frequency_response.h), so plants whose phase passes -180 deg
// below w_c are handled. For eq. 7 with w_c = 5 rad/s, PM = 75 deg:
// arg P(j5) = -52.02 deg, |P(j5)| = 0.17632 mm/V, lambda = 0.5887,
// K = 14.63 (the paper prints 0.62 and 15.62, which give a crossover of
// 5.075 rad/s and a phase margin of 72.1 deg).
//
// (b) PID C(s) = Kp + Ki/s + Kd s (eq. 10) tuned against the reference
// model 1/((s/w_c)^gamma + 1) (eq. 9; default w_c = 5 rad/s, gamma = 1.16)
// by minimising eq. 11 over a finite horizon H (default 2 s):
//   J(Kp, Ki, Kd) = int_0^H (1/2 + t/2) |y_r(t) - y(t)| dt,
// y the unit-step response of the unity-feedback loop. The loop is
// simulated as controllers/closed_loop.h does (and agrees with
// SimulateClosedLoopStep + ReferenceModelCost to rounding): the plant is
// advanced exactly over each sample by its zero-order-hold discretisation,
// the linear PID (no clamp, ideal derivative, backward Euler) runs at the
// sample period (default 0.1 ms, 10 kHz, where J at the paper's gains is
// within 2e-5 of the continuous loop's 0.08678 at H = 2 s), and J is the
// trapezoidal rule on the samples. A loop whose output leaves 1e6 times
// the step, or becomes non-finite, costs +infinity.
// Minimisation: Nelder-Mead (NLopt, below) on the logarithms of the three
// gains (so they stay positive), from several deterministic starts; the
// best result is kept. The plant for (b) should realise s^-0.5 accurately over
// the horizon: AccurateLinkPlant uses 20 Oustaloup pairs on [1e-5, 1e5]
// rad/s, as the closed-loop tests do.
//
// Bad input throws std::invalid_argument with one line naming the field.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "controllers/closed_loop.h"
#include "sim/linear/frequency_response.h"
#include "controllers/pid.h"
#include "controllers/reference_model.h"
#include "sim/linear/state_space.h"
#include "sim/linear/ipmc_link_model.h"

namespace ipmc {

// ------------------------------------------------ fractional integrator ---

struct FractionalIntegratorDesign {
  double gain = 0;              // K [V/(mm s^lambda)]
  double order = 0;             // lambda
  double plant_magnitude = 0;   // |P(j w_c)|
  double plant_phase_deg = 0;   // arg P(j w_c), unwrapped from low frequency
};

// Throws std::invalid_argument unless w_c is finite and > 0 and PM in
// (0, 180) deg; std::domain_error if the specification needs lambda
// outside (0, 1] (eq. 13's range) or the plant's response is zero or not
// finite on the grid.
FractionalIntegratorDesign DesignFractionalIntegrator(const FrequencyFunction& plant,
                                                      double crossover_rad_s,
                                                      double phase_margin_deg);

// The design and the margins of its exact open loop K s^-lambda P.
struct FractionalLoopDesign {
  FractionalIntegratorDesign design;
  StabilityMargins margins;
};
FractionalLoopDesign DesignFractionalLoop(const FrequencyFunction& plant, double crossover_rad_s,
                                          double phase_margin_deg);

// ----------------------------------------------------------- Nelder-Mead ---

// Unconstrained minimisation of f: R^n -> R by NLopt's Nelder-Mead simplex
// (NLOPT_LN_NELDERMEAD; J. A. Nelder, R. Mead, Comput. J. 7, 308, 1965;
// reflection 1, expansion 2, contraction 1/2, shrink 1/2). The initial
// simplex is the start and the start moved by initial_step along each
// axis. It stops (converged) as soon as the simplex's values span less
// than f_tolerance (best to worst), or every vertex lies within
// x_tolerance, in each coordinate, of the centroid of all but the worst;
// or (not converged) after max_evaluations evaluations. Non-finite values
// count as +infinity.
struct NelderMeadOptions {
  int max_evaluations = 1000;  // >= n + 1
  double f_tolerance = 1e-9;   // >= 0; 0 disables the test
  double x_tolerance = 1e-6;   // >= 0; 0 disables the test
  double initial_step = 0.25;  // != 0
  void Validate() const;       // std::invalid_argument naming the field
};

struct NelderMeadResult {
  Eigen::VectorXd x;
  double value = 0;
  int evaluations = 0;
  bool converged = false;
};

// Throws std::invalid_argument for an empty or non-finite start, bad
// options, or a start where f is not finite.
NelderMeadResult MinimizeNelderMead(const std::function<double(const Eigen::VectorXd&)>& f,
                                    const Eigen::VectorXd& start,
                                    const NelderMeadOptions& options = {});

// ---------------------------------------------------------- PID tuning ---

// Defaults: the paper's eq. 12, PidController::Config's.
struct PidGains {
  double kp = PidController::Config{}.kp;  // [V/mm]
  double ki = PidController::Config{}.ki;  // [V/(mm s)]
  double kd = PidController::Config{}.kd;  // [V s/mm]
};

// Deterministic starts of the default tuning: the paper's eq. 12 and four
// points spread over two decades around it.
std::vector<PidGains> DefaultPidStarts();

struct PidTuningOptions {
  ReferenceModel::Config reference;  // w_c = 5 rad/s, gamma = 1.16
  double horizon_s = 2.0;            // H, a whole number of sample periods
  double sample_period_s = 1e-4;     // finite, > 0
  std::vector<PidGains> starts;      // empty: DefaultPidStarts(); gains > 0
  // The PID's derivative filter Tf [s] in the tuning loop (0: the ideal
  // derivative of eq. 10).
  double derivative_filter_s = 0.0;
  // On log gains; stops on the simplex size alone. NLopt ends at the first
  // test met: with an f test of 1e-9 too, the five starts ended up to 2e-9
  // above the minimum J with Kd 3e-4 apart; on x alone 2e-11 and 3e-5.
  NelderMeadOptions search{600, 0.0, 1e-5, 0.3};
  // Called before each evaluation of J and while the reference response
  // is computed (a few ms apart); what it throws ends the tuning, e.g. a
  // caller's stop request. Empty: never called.
  std::function<void()> check_stop;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

// J of eq. 11 for given gains on one plant; the reference response, the
// plant's discretisation and the quadrature weights are computed once.
class PidStepCost {
 public:
  // Throws std::invalid_argument for an invalid plant or options.
  PidStepCost(const StateSpace& plant, const PidTuningOptions& options);
  // J, or +infinity if the loop diverges. Throws std::invalid_argument for
  // negative or non-finite gains.
  double operator()(const PidGains& gains) const;
  int samples() const { return samples_; }

 private:
  DiscreteStateSpace hold_;  // the plant's zero-order-hold discretisation
  double sample_period_s_ = 0;
  double derivative_filter_s_ = 0;  // Tf [s]
  int samples_ = 0;                // N, the horizon is N T
  std::vector<double> reference_;  // y_r(k T), k = 0..N
  std::vector<double> weight_;     // trapezoid weight times (1/2 + t/2)
};

struct PidTuningRun {
  PidGains start;
  PidGains gains;
  double start_cost = 0;
  double cost = 0;
  int evaluations = 0;
  bool converged = false;
};

struct PidTuningResult {
  PidGains gains;  // the best over the runs
  double cost = 0;
  std::vector<PidTuningRun> runs;
};

// Throws std::invalid_argument for a bad plant or options, or a start
// where J is not finite (the loop diverges).
PidTuningResult TunePid(const StateSpace& plant, const PidTuningOptions& options = {});

// Time-domain realisation of s^-0.5 (plant) and s^-lambda (fractional
// controller) in the tuning and the step responses: two Oustaloup pairs
// per decade over ten decades, so the approximation is far below the
// other errors over any horizon of interest (1/w_b = 1e5 s).
constexpr int kAccurateOustaloupPairs = 20;
constexpr double kAccurateBandLow_rad_s = 1e-5;
constexpr double kAccurateBandHigh_rad_s = 1e5;

// P = s^-0.5 G for `params` with the s^-0.5 block realised by
// kAccurateOustaloupPairs pairs on [kAccurateBandLow_rad_s,
// kAccurateBandHigh_rad_s].
StateSpace AccurateLinkPlant(IpmcLinkParams params);

// ---------------------------------------------------- derivative filter ---

// The PID's filtered derivative as it runs (controllers/pid.h),
//   D_k = (Tf D_(k-1) + Kd (y_k - y_(k-1))) / (Tf + T),
// driven by white measurement noise of RMS sigma [mm] per sample is
// D = H(z) n with H(z) = g (1 - z^-1) / (1 - a z^-1), a = Tf / (Tf + T),
// g = Kd / (Tf + T). Its impulse response h_0 = g, h_k = -g (1 - a) a^(k-1)
// has sum h_k^2 = 2 g^2 / (1 + a), so the derivative's noise voltage is
//   sigma_D = Kd sigma sqrt(2 / ((Tf + T) (2 Tf + T)))  [V RMS]:
// Kd sigma sqrt(2) / T for the ideal derivative (Tf = 0, a difference of
// two samples), Kd sigma / Tf for Tf >> T, the derivative's high-frequency
// gain Kd / Tf = Kd N / Td that the filter Tf = Td / N limits (Astrom &
// Murray, Feedback Systems, 2008, sec. 10.5; Astrom & Hagglund, Advanced
// PID Control, 2006, sec. 3.3: N typically 2 to 20). Throws
// std::invalid_argument for a negative or non-finite argument or T <= 0.
double DerivativeNoiseRms_V(double kd, double filter_s, double sample_period_s, double noise_mm);

// The smallest Tf with sigma_D <= bound_V: solving (Tf + T) (2 Tf + T) =
// 2 R^2, R = Kd sigma / bound, gives Tf = (sqrt(T^2 + 16 R^2) - 3 T) / 4,
// and Tf = 0 where the ideal derivative is within the bound (R <= T /
// sqrt 2). Throws std::invalid_argument as above or for bound_V <= 0.
double DerivativeFilterForNoise_s(double kd, double sample_period_s, double noise_mm,
                                  double bound_V);

// The PID tuned for the link `params` (on its AccurateLinkPlant), J at the
// paper's gains (eq. 12, PidGains{}) for comparison, and the margins of
// the tuned continuous PID's open loop (Kp + Ki/s + Kd s / (Tf s + 1)) P
// with the tuning's Tf and P = `plant` (the link's exact or fitted
// response).
struct PidLoopDesign {
  PidTuningResult tuned;
  double paper_cost = 0;
  StabilityMargins margins;
};
PidLoopDesign DesignPidLoop(const IpmcLinkParams& params, const FrequencyFunction& plant,
                            const PidTuningOptions& tuning);

}  // namespace ipmc

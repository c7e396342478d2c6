// IPMC actuators coupled to MuJoCo. Link q is a chain of n >= 1 rigid
// sub-segments of length l = L_q / n: its root hinge (named in ipmc_links)
// and n - 1 interior hinges, each with its motor "ipmc_<joint>". The
// hinges' own stiffness k_i and damping c_i (MJCF) supply
// -k_i theta_i - c_i dtheta_i/dt; the IPMC adds the active moment
// k_i theta0_i, so that
//   tau_i = k_i (theta0_i - theta_i) - c_i dtheta_i/dt.
// The hinges carry the strip's bending stiffness for their share s_i of
// the length, k_i = E I / s_i (discrete elastic rods weight each hinge by
// its Voronoi length): s_0 = l_0 / 2 for the root hinge, whose other side
// is the stiff junction (the previous link's rigid end, or the clamp),
// s_i = (l_(i-1) + l_i) / 2 inside, and the last hinge's share reaches the
// tip, s_(n-1) = l_(n-2) / 2 + l_(n-1), so that the shares add up to the
// link's length (the generator's layout, sim/core/model_generator.h:
// s = l / 2, l, ..., l with a last sub-segment of l / 2). The natural
// angles theta0_i = kappa s_i are the link's free shape, an arc of
// curvature kappa, so the active moment k_i theta0_i = E I kappa is the
// same at every hinge of the link: the IPMC's uniform electro-active
// moment. kappa is the curvature whose free chain puts the link's tip at
// the model's free tip deflection delta_free_q [mm] relative to the link's
// root tangent:
//   sum_j l_j sin(kappa c_j) = delta_free_q,  c_j = s_0 + ... + s_j,
// the midpoint rule of the arc's integral of sin(kappa s) ds, with the
// last sub-segment at the tip's angle kappa L: the free shape and the
// tip's direction converge to the arc's as 1/n^2. For n = 1 (s_0 = L / 2)
// this is the rigid link's theta0 = asin(delta_free_q / L_q). A deflection
// beyond the chain's reach
// is clamped to it (for n = 1, theta0 = +-pi/2); the first clamp of a
// coupling is reported through mju_warning.
// delta_free_q is the output of the link's model P_q(s) = s^-0.5 G_q(s)
// (sim/linear/ipmc_link_model.h) driven by its voltage, advanced in
// mjcb_control (plugin/actuators/ipmc_actuator_bank.h) exactly under the
// voltages' zero-order hold, or by CVODE.
//
// MJCF fields:
//   text    ipmc_links           root hinges of links 1..n, in order
//   numeric ipmc_segments_per_link  sub-segments per link, [1, 64] (default 1):
//                                the n - 1 interior hinges of a link are the
//                                first hinges of the n - 1 bodies that follow
//                                its root hinge's body, one child each
//   text    ipmc_plants          uniform (default: every link eq. 7's plant,
//                                the paper's simulation) | table2 (link q
//                                gets Table 2's row q); either scaled to the
//                                link's length (ScaleLinkToLength)
//   text    ipmc_model           g1 (eq. 5, default) | g2 (eq. 6)
//   text    ipmc_actuation       distributed (default) | single (link 1 only;
//                                the other links are passive)
//   numeric ipmc_a0_mm_per_V, ipmc_b1, ipmc_b2_s2, ipmc_alpha
//                                per-link overrides (n values) of the
//                                assigned, length-scaled parameters
//   numeric ipmc_integrator_band_rad_s  [w_b, w_h] of the s^-0.5 block
//   numeric ipmc_integrator_pairs       its number of zero/pole pairs
//   text    ipmc_actuator_integration   exact (default: the link models advanced
//                                exactly over each interval, the voltages
//                                held; plugin/actuators/zero_order_hold.h) |
//                                cvode (integrated by CVODE)
//   numeric ipmc_cvode_rel_tol          CVODE's relative tolerance, [1e-14, 1e-2]
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "ipmc_swim/ipmc_swim.h"
#include "plugin/actuators/ipmc_actuator_bank.h"
#include "sim/linear/ipmc_link_model.h"

namespace ipmc {

inline CvodeOptions DefaultCvodeOptions() {
  CvodeOptions options;
  options.rel_tol = 1e-6;
  return options;
}

// One IPMC link as a chain of hinges in the model.
struct LinkChain {
  std::vector<int> joints;             // root hinge first
  std::vector<int> motors;             // ipmc_<joint> of each
  std::vector<double> segment_length_m;  // one per hinge, in order
  double length_m = 0;                 // their sum
};

// The free shape of a link's chain: sub-segment j (lengths l_j) lies at
// the angle kappa c_j to the link's root tangent, c_j = sum_{i <= j} s_i,
// with the hinges' shares s_0 = l_0 / 2, s_i = (l_(i-1) + l_i) / 2 and
// s_(n-1) = l_(n-2) / 2 + l_(n-1) (n >= 2: the last sub-segment lies at
// the tip's angle kappa L), so the tip's deflection from that tangent is
// f(kappa) = sum_j l_j sin(kappa c_j). If all but the last sub-segment are
// equal (the generator's layout) f and df/dkappa are evaluated in closed
// form, so a curvature costs the same whatever the number of sub-segments.
class ChainShape {
 public:
  explicit ChainShape(const std::vector<double>& segment_length_m);

  double Share_m(size_t hinge) const { return share_m_[hinge]; }
  // f(kappa) [m] for a curvature kappa [1/m].
  double TipDeflection_m(double kappa_1_m) const;
  // The largest |f|, reached at the first maximum of f (for n = 1: L).
  double Reach_m() const { return reach_m_; }
  // The kappa in [-kappa_reach, kappa_reach] with f(kappa) = deflection_m
  // (for n = 1: asin(deflection / L) / (L / 2)); a deflection beyond the
  // reach gives +-kappa_reach and sets *clamped. `guess_1_m` starts the
  // Newton iteration (the last value: a few iterations per step).
  double Curvature_1_m(double deflection_m, double guess_1_m, bool* clamped) const;

 private:
  double Slope(double kappa_1_m) const;  // df/dkappa

  std::vector<double> segment_length_m_, share_m_, cumulative_share_m_;
  double max_curvature_1_m_ = 0, reach_m_ = 0;
  // All but the last sub-segment equal (within 1e-9, the model file's
  // digits): f and f' in closed form.
  bool uniform_ = false;
  double uniform_length_m_ = 0, uniform_span_m_ = 0, end_length_m_ = 0, total_length_m_ = 0;
};

// Settings that a program may impose over the model's fields.
struct IpmcActuatorsOverrides {
  std::optional<PlantAssignment> plants;
  // Over the model's ipmc_dynamics (ipmc_swim/fields.h); also
  // applies to a model with drag and no actuators.
  std::optional<Dynamics> dynamics;
  // The joints' physical damping c per dof [N m s/rad] when the step
  // model's dof_damping holds the inertial step's c_eff instead (the
  // coupling sets it: MakeStepModel); empty: no first-order hold
  // (IpmcActuators::Update).
  std::vector<double> physical_damping;
};

struct IpmcActuatorsConfig {
  std::vector<std::string> joints;     // root hinges, one per link
  std::vector<LinkChain> chains;       // one per link
  std::vector<IpmcLinkParams> links;
  PlantAssignment plants = PlantAssignment::kUniform;
  Actuation actuation = Actuation::kDistributed;
  // 1e-6 keeps the deflection error far below the link models' own
  // accuracy (0.06 dB) and halves the cost of each voltage change.
  CvodeOptions cvode = DefaultCvodeOptions();
  // The voltages are held between the controller's samples, so the exact
  // zero-order-hold advance is the solution itself, and costs one
  // matrix-vector product per link and step where CVODE restarts its
  // steps at each voltage change; cvode keeps the integrator the link
  // models were validated with.
  ActuatorIntegration integration = ActuatorIntegration::kExact;
  // SetVoltages refuses |voltage| above this (ipmc_voltage_limit_V).
  double voltage_limit_V = kDefaultVoltageLimit_V;
  // IpmcActuatorsOverrides::physical_damping; the first-order hold of the
  // inertial step needs it and flexible links (ipmc_segments_per_link > 1).
  std::vector<double> physical_damping;
  bool first_order_hold = false;

  // nullopt if the model has no ipmc_links field; throws
  // std::invalid_argument naming the field on a malformed one.
  static std::optional<IpmcActuatorsConfig> FromModel(
      const mjModel* m, const IpmcActuatorsOverrides& overrides = {});
};

// The custom fields IpmcActuatorsConfig::FromModel reads.
const std::vector<std::string>& IpmcActuatorFields();

class IpmcActuators {
 public:
  explicit IpmcActuators(IpmcActuatorsConfig config);

  int Links() const { return static_cast<int>(config_.chains.size()); }
  const std::vector<std::string>& joints() const { return config_.joints; }
  const std::vector<LinkChain>& chains() const { return config_.chains; }
  const std::vector<IpmcLinkParams>& link_params() const { return config_.links; }
  PlantAssignment plants() const { return config_.plants; }
  Actuation actuation() const { return config_.actuation; }

  // Voltages from d->time on [V]; in single actuation links 2..n are held
  // at 0 V. Throws std::invalid_argument on a wrong count or a non-finite
  // value (naming the link).
  // Throws std::invalid_argument for a wrong count, a non-finite voltage
  // or one outside [-voltage_limit_V, voltage_limit_V].
  void SetVoltages(const mjData* d, const std::vector<double>& voltage_V);
  double VoltageLimit_V() const { return config_.voltage_limit_V; }
  const std::vector<double>& Voltages_V() const { return voltage_V_; }

  // Advances the link models to d->time and writes the active moments
  // into d->ctrl. Called from mjcb_control. Inside an inertial step
  // (BeginInertialStep) of a model with first_order_hold, the moment each
  // hinge gets is instead the one that makes the step's relaxation of the
  // massless hinge exact for a rest angle that moves linearly from t_n to
  // t_n + h (a first-order hold): with the moments f_n and f_(n+1) of the
  // link models at the step's ends, the step's damping c_s (c_eff) and the
  // physical c,
  //   f = f_n + w (f_(n+1) - f_n),  w = (c_s - c) / (k h),
  // and the link models are advanced to t_n + h, where the step leaves
  // d->time. Derivation: with e = theta - theta0 and theta0 = theta0_n + s t,
  // c de/dt = -k e - c s gives over the step e_(n+1) = e* + r (e_n - e*),
  // r = exp(-k h / c), e* = -c s / k; MuJoCo's massless step,
  // c_s (theta_(n+1) - theta_n) / h = f - k theta_n, with c_s = k h / (1 - r)
  // matches it for f / k = theta0_n + s (c_s - c) / k.
  // w tends to 1/2 + k h / (12 c) for k h / c << 1 (the step's midpoint) and
  // to 1 - c / (k h) for k h / c >> 1 (the step's end less the hinge's lag
  // c / k).
  void Update(const mjModel* m, mjData* d);
  // Brackets MuJoCo's Euler or implicit step of an inertial model
  // (ipmc::Step), inside which Update applies the first-order hold.
  void BeginInertialStep(const mjModel* m);
  void EndInertialStep() { inertial_step_ = false; }
  // Whether Update applies the first-order hold in inertial steps.
  bool FirstOrderHold() const { return config_.first_order_hold; }
  // The link models' moments k_i theta0_i at the last first-order-hold
  // step's start and end, per motor [N m] (empty before one).
  const std::vector<double>& StepStartMoments_N_m() const { return step_start_moment_N_m_; }
  const std::vector<double>& StepEndMoments_N_m() const { return step_end_moment_N_m_; }
  // IpmcActuatorsConfig::physical_damping (per dof, may be empty).
  const std::vector<double>& PhysicalDamping() const { return config_.physical_damping; }

  // The state the next Update depends on (ipmc_swim.h: SaveState). Makes
  // the bank restart at the saved time, so that this coupling and every
  // one restored from the result continue identically.
  CouplingState SaveState();
  // Sets the state saved by SaveState from a coupling of the same model.
  // Throws std::invalid_argument naming the field on a wrong size, a
  // non-finite value, a negative clamp_count or time_s > d->time; changes
  // nothing then.
  void RestoreState(const mjData* d, const CouplingState& state);
  // The state of a new coupling at d->time: zero link states and
  // voltages, zero curvatures, no clamps counted.
  void ResetState(const mjData* d);

  // The state's home in mjData (ipmc_swim.h, "State"): StateSize() values
  // of d->userdata from `offset`: t_x, the bank's x, the held voltages,
  // the curvatures and the clamp count.
  int StateSize() const { return 2 + bank_->States() + 2 * Links(); }
  // Writes the state there.
  void StoreState(const mjData* d, int offset) const;
  // Takes the state StoreState wrote there (for d or for another mjData of
  // the same model, copied into d), with RestoreState's checks.
  void LoadState(const mjData* d, int offset);

  // The links' free tip deflections at the last update [mm].
  std::vector<double> FreeTipDeflection_mm() const { return bank_->FreeTipDeflection_mm(); }
  double FreeTipDeflection_mm(int link) const { return bank_->FreeTipDeflection_mm(link); }
  // Link lengths L_q [m].
  const std::vector<double>& LinkLengths_m() const { return length_m_; }
  // How often a free deflection was beyond the link's reach and clamped.
  long ClampCount() const { return clamp_count_; }

 private:
  // Advances the bank to d->time; an earlier d->time resets the state
  // (ResetState) and is reported through mju_warning.
  void AdvanceTo(const mjData* d);
  // Link q's active moments k_i theta0_i into moment_N_m (per motor);
  // counts and reports a clamp if count_clamps.
  void FreeShapeMoments(const mjModel* m, const mjData* d, int q, double deflection_mm,
                        bool count_clamps, std::vector<double>* moment_N_m);
  // Update within an inertial step: the first-order hold above.
  void UpdateFirstOrderHold(const mjModel* m, mjData* d);

  IpmcActuatorsConfig config_;
  std::vector<double> length_m_;
  std::vector<ChainShape> shapes_;
  // The state (CouplingState) besides the bank's:
  std::vector<double> curvature_1_m_;  // last kappa of each link (Newton's start)
  std::vector<double> voltage_V_;      // held voltages, passive links at 0 V
  long clamp_count_ = 0;
  std::unique_ptr<IpmcActuatorBank> bank_;
  bool inertial_step_ = false;  // inside BeginInertialStep / EndInertialStep
  std::vector<double> step_start_moment_N_m_, step_end_moment_N_m_;
  std::vector<double> scratch_moment_N_m_;  // Update's moments, per motor
};

}  // namespace ipmc

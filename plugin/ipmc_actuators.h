// IPMC actuators coupled to MuJoCo: each driven hinge q gets the active
// moment k_q theta_free_q through its motor "ipmc_<joint>", while the
// hinge's own stiffness and damping (MJCF) supply -k_q theta_q - c_q
// dtheta_q/dt, so that
//   tau_q = k_q (theta_free_q - theta_q) - c_q dtheta_q/dt,
//   theta_free_q = asin(delta_free_q / L_q), clamped to +-pi/2,
// where delta_free_q [mm] is the free tip deflection of the link's model
// P_q(s) = s^-0.5 G_q(s) (plugin/ipmc_link_model.h) driven by its voltage,
// integrated by CVODE (plugin/ipmc_actuator_bank.h) in mjcb_control.
//
// MJCF fields:
//   text    ipmc_links           hinge joints driven by links 1..n, in order;
//                                each needs a motor named ipmc_<joint>
//   text    ipmc_model           g1 (eq. 5, default) | g2 (eq. 6)
//   text    ipmc_actuation       distributed (default) | single (link 1 only;
//                                the other links are passive hinges)
//   numeric ipmc_a0_mm_per_V, ipmc_b1, ipmc_b2_s2, ipmc_alpha
//                                per-link overrides of Table 2 (n values)
//   numeric ipmc_integrator_band_rad_s  [w_b, w_h] of the s^-0.5 block
//   numeric ipmc_integrator_pairs       its number of zero/pole pairs
//   numeric ipmc_cvode_rel_tol          CVODE's relative tolerance, [1e-14, 1e-2]
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plugin/ipmc_actuator_bank.h"
#include "plugin/ipmc_link_model.h"

namespace ipmc {

enum class Actuation { kDistributed, kSingle };

inline CvodeOptions DefaultCvodeOptions() {
  CvodeOptions options;
  options.rel_tol = 1e-6;
  return options;
}

struct IpmcActuatorsConfig {
  std::vector<std::string> joints;
  std::vector<IpmcLinkParams> links;
  Actuation actuation = Actuation::kDistributed;
  // 1e-6 keeps the deflection error far below the link models' own
  // accuracy (0.06 dB) and halves the cost of each voltage change.
  CvodeOptions cvode = DefaultCvodeOptions();

  // nullopt if the model has no ipmc_links field; throws
  // std::invalid_argument naming the field on a malformed one.
  static std::optional<IpmcActuatorsConfig> FromModel(const mjModel* m);
};

class IpmcActuators {
 public:
  IpmcActuators(const mjModel* m, IpmcActuatorsConfig config);

  int Links() const { return static_cast<int>(hinges_.size()); }
  const std::vector<std::string>& joints() const { return config_.joints; }
  Actuation actuation() const { return config_.actuation; }

  // Voltages from d->time on [V]; in single actuation links 2..n are held
  // at 0 V. Throws std::invalid_argument on a wrong count or a non-finite
  // value (naming the link).
  void SetVoltages(const mjData* d, const std::vector<double>& voltage_V);
  const std::vector<double>& Voltages_V() const { return voltage_V_; }

  // Advances the link models to d->time and writes the active moments
  // into d->ctrl. Called from mjcb_control.
  void Update(const mjModel* m, mjData* d);

  // The links' free tip deflections at the last update [mm].
  std::vector<double> FreeTipDeflection_mm() const { return bank_->FreeTipDeflection_mm(); }
  double FreeTipDeflection_mm(int link) const { return bank_->FreeTipDeflection_mm(link); }
  // Link lengths L_q [m] used for theta_free = asin(delta / L).
  const std::vector<double>& LinkLengths_m() const { return length_m_; }
  // How often theta_free had to be clamped to +-pi/2.
  long ClampCount() const { return clamp_count_; }

 private:
  void AdvanceTo(const mjData* d);

  struct Hinge {
    int joint;
    int motor;
  };
  IpmcActuatorsConfig config_;
  std::vector<Hinge> hinges_;
  std::vector<double> length_m_;
  std::vector<double> voltage_V_;
  std::unique_ptr<IpmcActuatorBank> bank_;
  long clamp_count_ = 0;
};

}  // namespace ipmc

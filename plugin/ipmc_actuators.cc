#include "plugin/ipmc_actuators.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plugin/custom_fields.h"

namespace ipmc {
namespace {

constexpr char kAttrLinks[] = "ipmc_links";
constexpr char kAttrModel[] = "ipmc_model";
constexpr char kAttrActuation[] = "ipmc_actuation";
constexpr char kAttrBand[] = "ipmc_integrator_band_rad_s";
constexpr char kAttrPairs[] = "ipmc_integrator_pairs";
constexpr char kAttrRelTol[] = "ipmc_cvode_rel_tol";
constexpr double kHalfPi = 1.5707963267948966;
constexpr double kMmToM = 1e-3;

// Applies a per-link numeric override `name` (n values) through `set`.
template <typename Setter>
void OverridePerLink(const mjModel* m, const char* name, std::vector<IpmcLinkParams>& links,
                     Setter set) {
  const std::optional<std::vector<double>> values = FindCustomVector(m, name);
  if (!values) return;
  if (values->size() != links.size()) {
    throw std::invalid_argument(std::string("ipmc actuators: ") + name + " must hold " +
                                std::to_string(links.size()) + " values, one per link (got " +
                                std::to_string(values->size()) + ")");
  }
  for (size_t q = 0; q < links.size(); ++q) set(links[q], (*values)[q]);
}

}  // namespace

std::optional<IpmcActuatorsConfig> IpmcActuatorsConfig::FromModel(const mjModel* m) {
  const std::optional<std::string> joints = FindCustomText(m, kAttrLinks);
  if (!joints) return std::nullopt;
  IpmcActuatorsConfig config;
  config.joints = SplitWords(*joints);
  if (config.joints.empty()) {
    throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrLinks +
                                " must name at least one hinge");
  }
  IpmcModelKind kind = IpmcModelKind::kG1;
  if (auto model = FindCustomText(m, kAttrModel)) {
    if (*model == "g2") {
      kind = IpmcModelKind::kG2;
    } else if (*model != "g1") {
      throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrModel +
                                  " must be g1 or g2 (got '" + *model + "')");
    }
  }
  if (auto actuation = FindCustomText(m, kAttrActuation)) {
    if (*actuation == "single") {
      config.actuation = Actuation::kSingle;
    } else if (*actuation != "distributed") {
      throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrActuation +
                                  " must be distributed or single (got '" + *actuation + "')");
    }
  }
  for (size_t q = 0; q < config.joints.size(); ++q) {
    // Table 2 for links 1-3; further links repeat link 3 unless overridden.
    config.links.push_back(PaperLinkParams(static_cast<int>(std::min<size_t>(q, 2)) + 1, kind));
  }
  OverridePerLink(m, "ipmc_a0_mm_per_V", config.links,
                  [](IpmcLinkParams& p, double v) { p.a0_mm_per_V = v; });
  OverridePerLink(m, "ipmc_b1", config.links, [](IpmcLinkParams& p, double v) { p.b1 = v; });
  OverridePerLink(m, "ipmc_b2_s2", config.links,
                  [](IpmcLinkParams& p, double v) { p.b2_s2 = v; });
  OverridePerLink(m, "ipmc_alpha", config.links,
                  [](IpmcLinkParams& p, double v) { p.alpha = v; });
  if (auto band = FindCustomVector(m, kAttrBand)) {
    if (band->size() != 2) {
      throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrBand +
                                  " must hold two values [w_b, w_h] in rad/s");
    }
    for (IpmcLinkParams& p : config.links) {
      p.integrator.w_low_rad_s = (*band)[0];
      p.integrator.w_high_rad_s = (*band)[1];
    }
  }
  if (auto pairs = FindCustomScalar(m, kAttrPairs)) {
    for (IpmcLinkParams& p : config.links) p.integrator.n = static_cast<int>(*pairs);
  }
  if (auto rel_tol = FindCustomScalar(m, kAttrRelTol)) config.cvode.rel_tol = *rel_tol;
  try {
    config.cvode.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrRelTol + ": " + e.what());
  }
  for (size_t q = 0; q < config.links.size(); ++q) {
    try {
      config.links[q].Validate();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("ipmc actuators: link " + std::to_string(q + 1) + ": " +
                                  e.what());
    }
  }
  return config;
}

IpmcActuators::IpmcActuators(const mjModel* m, IpmcActuatorsConfig config)
    : config_(std::move(config)) {
  for (const std::string& name : config_.joints) {
    const int joint = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    if (joint < 0 || m->jnt_type[joint] != mjJNT_HINGE) {
      throw std::invalid_argument(std::string("ipmc actuators: ") + kAttrLinks + " names '" +
                                  name + "', which is not a hinge of the model");
    }
    const int motor = mj_name2id(m, mjOBJ_ACTUATOR, ("ipmc_" + name).c_str());
    if (motor < 0) {
      throw std::invalid_argument("ipmc actuators: hinge '" + name + "' needs a motor named ipmc_" +
                                  name);
    }
    // The link is the first box geom of the hinge's body; its length is
    // 2 size[0] (the RFT segment convention).
    const int body = m->jnt_bodyid[joint];
    double length_m = 0.0;
    for (int g = m->body_geomadr[body]; g < m->body_geomadr[body] + m->body_geomnum[body]; ++g) {
      if (m->geom_type[g] == mjGEOM_BOX) {
        length_m = 2.0 * m->geom_size[3 * g];
        break;
      }
    }
    if (!(length_m > 0.0)) {
      throw std::invalid_argument("ipmc actuators: the body of hinge '" + name +
                                  "' has no box geom giving the link length");
    }
    hinges_.push_back({joint, motor});
    length_m_.push_back(length_m);
  }
  voltage_V_.assign(hinges_.size(), 0.0);
  bank_ = IpmcActuatorBank::Create(config_.links, config_.cvode);
}

void IpmcActuators::AdvanceTo(const mjData* d) {
  if (d->time < bank_->Time_s()) {
    bank_->Reset(d->time);  // mjData was reset or rewound
    bank_->SetVoltages(voltage_V_);
  } else if (d->time > bank_->Time_s()) {
    bank_->AdvanceTo(d->time);
  }
}

void IpmcActuators::SetVoltages(const mjData* d, const std::vector<double>& voltage_V) {
  if (voltage_V.size() != hinges_.size()) {
    throw std::invalid_argument("ipmc actuators: got " + std::to_string(voltage_V.size()) +
                                " voltages for " + std::to_string(hinges_.size()) + " links");
  }
  for (size_t q = 0; q < voltage_V.size(); ++q) {
    if (!std::isfinite(voltage_V[q])) {
      throw std::invalid_argument("ipmc actuators: voltage of link " + std::to_string(q + 1) +
                                  " is not finite");
    }
  }
  AdvanceTo(d);  // the old voltages hold up to now
  voltage_V_ = voltage_V;
  if (config_.actuation == Actuation::kSingle) {
    for (size_t q = 1; q < voltage_V_.size(); ++q) voltage_V_[q] = 0.0;
  }
  bank_->SetVoltages(voltage_V_);
}

void IpmcActuators::Update(const mjModel* m, mjData* d) {
  AdvanceTo(d);
  for (size_t q = 0; q < hinges_.size(); ++q) {
    const double deflection_mm = bank_->FreeTipDeflection_mm(static_cast<int>(q));
    const double ratio = deflection_mm * kMmToM / length_m_[q];
    double theta_free_rad = 0.0;
    if (std::abs(ratio) >= 1.0) {
      if (clamp_count_++ == 0) {
        std::fprintf(stderr,
                     "warning: ipmc link %zu: free deflection %.3g mm exceeds its length; "
                     "theta_free clamped to +-pi/2\n",
                     q + 1, deflection_mm);
      }
      theta_free_rad = std::copysign(kHalfPi, ratio);
    } else {
      theta_free_rad = std::asin(ratio);
    }
    if (config_.actuation == Actuation::kSingle && q > 0) theta_free_rad = 0.0;
    d->ctrl[hinges_[q].motor] = m->jnt_stiffness[hinges_[q].joint] * theta_free_rad;
  }
}

}  // namespace ipmc

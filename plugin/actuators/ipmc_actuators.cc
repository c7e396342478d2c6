#include "plugin/actuators/ipmc_actuators.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plugin/mjcf/custom_fields.h"
#include "plugin/mjcf/geom_axes.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

// The bound of the Oustaloup realisation's pairs (ipmc_integrator_pairs).
constexpr int kMaxIntegratorPairs = 100;
constexpr double kMmToM = 1e-3;

[[noreturn]] void Fail(const std::string& message) {
  throw std::invalid_argument("ipmc actuators: " + message);
}

// Applies a per-link numeric override `name` (n values) through `set`.
template <typename Setter>
void OverridePerLink(const mjModel* m, const char* name, std::vector<IpmcLinkParams>& links,
                     Setter set) {
  const std::optional<std::vector<double>> values = FindCustomVector(m, name);
  if (!values) return;
  if (values->size() != links.size()) {
    Fail(std::string(name) + " must hold " + std::to_string(links.size()) +
         " values, one per link (got " + std::to_string(values->size()) + ")");
  }
  for (size_t q = 0; q < links.size(); ++q) set(links[q], (*values)[q]);
}

int SegmentsPerLink(const mjModel* m) {
  const std::optional<double> value = FindCustomScalar(m, kAttrSegments);
  if (!value) return 1;
  if (*value != std::floor(*value) || *value < 1 || *value > kMaxSegmentsPerLink) {
    Fail(std::string(kAttrSegments) + " must be an integer in [1, " +
         std::to_string(kMaxSegmentsPerLink) + "] (got " + std::to_string(*value) + ")");
  }
  return static_cast<int>(*value);
}

// The first hinge joint of `body`, or -1.
int FirstHinge(const mjModel* m, int body) {
  for (int j = m->body_jntadr[body]; j >= 0 && j < m->body_jntadr[body] + m->body_jntnum[body];
       ++j) {
    if (m->jnt_type[j] == mjJNT_HINGE) return j;
  }
  return -1;
}

// The only child of `body`, or -1 if it has none or several.
int OnlyChild(const mjModel* m, int body) {
  int child = -1;
  for (int b = body + 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] != body) continue;
    if (child >= 0) return -1;
    child = b;
  }
  return child;
}

// Length of the sub-segment carried by `body`: its first box geom's side
// along its axis (SlenderAxis: the RFT segment convention).
double SegmentLength_m(const mjModel* m, int body, const std::string& joint_name) {
  for (int g = m->body_geomadr[body]; g >= 0 && g < m->body_geomadr[body] + m->body_geomnum[body];
       ++g) {
    if (m->geom_type[g] != mjGEOM_BOX) continue;
    const int axis = SlenderAxis(m, g);
    if (axis >= 0) return SlenderLength_m(m, g, axis);
  }
  Fail("the body of hinge '" + joint_name + "' has no box geom giving the segment length");
}

int RequireMotor(const mjModel* m, const std::string& joint_name) {
  const int motor = mj_name2id(m, mjOBJ_ACTUATOR, IpmcMotorName(joint_name).c_str());
  if (motor < 0) Fail("hinge '" + joint_name + "' needs a motor named " + IpmcMotorName(joint_name));
  return motor;
}

// Link chain from its root hinge: the root hinge's body and the n - 1
// bodies that follow it, one child each, each with a hinge of its own.
// Interior hinges are never another link's root hinge.
LinkChain FindChain(const mjModel* m, const std::string& root_name, int segments,
                    const std::vector<std::string>& roots) {
  const int root = mj_name2id(m, mjOBJ_JOINT, root_name.c_str());
  if (root < 0 || m->jnt_type[root] != mjJNT_HINGE) {
    Fail(std::string(kAttrLinks) + " names '" + root_name + "', which is not a hinge of the model");
  }
  LinkChain chain;
  int body = m->jnt_bodyid[root];
  int joint = root;
  for (int s = 0; s < segments; ++s) {
    if (s > 0) {
      body = OnlyChild(m, body);
      joint = body < 0 ? -1 : FirstHinge(m, body);
      if (joint >= 0 && std::find(roots.begin(), roots.end(),
                                  std::string(m->names + m->name_jntadr[joint])) != roots.end()) {
        joint = -1;
      }
      if (joint < 0) {
        Fail("link '" + root_name + "' needs " + std::to_string(segments) + " sub-segments (" +
             kAttrSegments + "), but sub-segment " + std::to_string(s + 1) +
             " is not a single child body with a hinge of its own");
      }
    }
    const std::string name = m->names + m->name_jntadr[joint];
    chain.joints.push_back(joint);
    chain.motors.push_back(RequireMotor(m, name));
    chain.segment_length_m.push_back(SegmentLength_m(m, body, name));
    chain.length_m += chain.segment_length_m.back();
  }
  return chain;
}

IpmcModelKind ModelKind(const mjModel* m) {
  const std::optional<std::string> model = FindCustomText(m, kAttrModel);
  if (!model || *model == "g1") return IpmcModelKind::kG1;
  if (*model == "g2") return IpmcModelKind::kG2;
  Fail(std::string(kAttrModel) + " must be g1 or g2 (got '" + *model + "')");
}

PlantAssignment Plants(const mjModel* m) {
  const std::optional<std::string> word = FindCustomText(m, kAttrPlants);
  if (!word) return PlantAssignment::kUniform;
  if (const std::optional<PlantAssignment> plants = ParsePlantAssignment(*word)) return *plants;
  Fail(std::string(kAttrPlants) + " must be uniform or table2 (got '" + *word + "')");
}

ActuatorIntegration IntegrationOf(const mjModel* m) {
  const std::optional<std::string> word = FindCustomText(m, kAttrIntegration);
  if (!word) return ActuatorIntegration::kExact;
  if (const std::optional<ActuatorIntegration> integration = ParseActuatorIntegration(*word)) {
    return *integration;
  }
  Fail(std::string(kAttrIntegration) + " must be exact or cvode (got '" + *word + "')");
}

Actuation ActuationOf(const mjModel* m) {
  const std::optional<std::string> actuation = FindCustomText(m, kAttrActuation);
  if (!actuation || *actuation == "distributed") return Actuation::kDistributed;
  if (*actuation == "single") return Actuation::kSingle;
  Fail(std::string(kAttrActuation) + " must be distributed or single (got '" + *actuation + "')");
}

}  // namespace

ChainShape::ChainShape(const std::vector<double>& segment_length_m)
    : segment_length_m_(segment_length_m) {
  const size_t n = segment_length_m_.size();
  double cumulative_m = 0.0;
  for (size_t j = 0; j < n; ++j) {
    double share_m = j == 0 ? 0.5 * segment_length_m_[0]
                            : 0.5 * (segment_length_m_[j - 1] + segment_length_m_[j]);
    if (j > 0 && j == n - 1) share_m += 0.5 * segment_length_m_[j];  // reaches the tip
    share_m_.push_back(share_m);
    cumulative_m += share_m;
    cumulative_share_m_.push_back(cumulative_m);
  }
  const double first_m = segment_length_m_[0];
  const auto equal_to_first = [first_m](double l) {
    return std::abs(l - first_m) <= 1e-9 * first_m;
  };
  uniform_ = n > 1 && std::all_of(segment_length_m_.begin(), segment_length_m_.end() - 1,
                                  equal_to_first);
  if (uniform_) {
    uniform_length_m_ = first_m;
    uniform_span_m_ = first_m * static_cast<double>(n - 1);
    end_length_m_ = segment_length_m_.back();
    total_length_m_ = cumulative_m;
  }
  // f(kappa) rises while every cumulative angle kappa c_j is below pi and
  // f' = sum l_j c_j cos(kappa c_j) > 0; f' falls on [0, pi / c_last], so
  // its root there (bisection) is the reach's curvature.
  double lo = 0.0, hi = kPi / cumulative_share_m_.back();
  if (segment_length_m_.size() == 1) {
    lo = 0.5 * hi;  // L sin(kappa L / 2) peaks at kappa L / 2 = pi / 2
  } else {
    for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (Slope(mid) > 0 ? lo : hi) = mid;
    }
  }
  max_curvature_1_m_ = lo;
  reach_m_ = TipDeflection_m(lo);
}

// All but the last sub-segment equal (c_j = (j + 1/2) l for j < n - 1,
// the span of those m = n - 1 sub-segments S = m l, the last one of length
// e at c = L): the sum of sines of an arithmetic progression,
// f = l sin^2(kappa S / 2) / sin(kappa l / 2) + e sin(kappa L), and its
// derivative, in a few operations whatever n.
double ChainShape::TipDeflection_m(double kappa_1_m) const {
  if (uniform_) {
    if (kappa_1_m == 0.0) return 0.0;
    const double half_span = std::sin(0.5 * kappa_1_m * uniform_span_m_);
    return uniform_length_m_ * half_span * half_span /
               std::sin(0.5 * kappa_1_m * uniform_length_m_) +
           end_length_m_ * std::sin(kappa_1_m * total_length_m_);
  }
  double y_m = 0.0;
  for (size_t j = 0; j < segment_length_m_.size(); ++j) {
    y_m += segment_length_m_[j] * std::sin(kappa_1_m * cumulative_share_m_[j]);
  }
  return y_m;
}

double ChainShape::Slope(double kappa_1_m) const {
  if (uniform_) {
    const double l = uniform_length_m_, span_m = uniform_span_m_, length_m = total_length_m_;
    const double end_slope = end_length_m_ * length_m * std::cos(kappa_1_m * length_m);
    if (kappa_1_m == 0.0) return 0.5 * span_m * span_m + end_slope;
    const double big_s = std::sin(0.5 * kappa_1_m * span_m);
    const double big_c = std::cos(0.5 * kappa_1_m * span_m);
    const double small_s = std::sin(0.5 * kappa_1_m * l);
    const double small_c = std::cos(0.5 * kappa_1_m * l);
    return l * big_s * (span_m * big_c - 0.5 * l * big_s * small_c / small_s) / small_s +
           end_slope;
  }
  double slope = 0.0;
  for (size_t j = 0; j < segment_length_m_.size(); ++j) {
    slope += segment_length_m_[j] * cumulative_share_m_[j] * std::cos(kappa_1_m * cumulative_share_m_[j]);
  }
  return slope;
}

double ChainShape::Curvature_1_m(double deflection_m, double guess_1_m, bool* clamped) const {
  *clamped = std::abs(deflection_m) >= reach_m_;
  if (*clamped) return std::copysign(max_curvature_1_m_, deflection_m);
  if (segment_length_m_.size() == 1) {
    return std::asin(deflection_m / segment_length_m_[0]) / share_m_[0];
  }
  // Newton from the last value, kept inside the monotone branch; f is
  // odd, so solve for |deflection| and restore the sign.
  const double target_m = std::abs(deflection_m);
  double lo = 0.0, hi = max_curvature_1_m_;
  double kappa = std::min(std::abs(guess_1_m), hi);
  for (int i = 0; i < 100; ++i) {
    const double residual_m = TipDeflection_m(kappa) - target_m;
    (residual_m < 0 ? lo : hi) = kappa;
    if (std::abs(residual_m) <= 1e-15 * reach_m_) break;
    double next = kappa - residual_m / Slope(kappa);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == kappa) break;
    kappa = next;
  }
  return std::copysign(kappa, deflection_m);
}

std::optional<IpmcActuatorsConfig> IpmcActuatorsConfig::FromModel(
    const mjModel* m, const IpmcActuatorsOverrides& overrides) {
  const std::optional<std::string> joints = FindCustomText(m, kAttrLinks);
  if (!joints) return std::nullopt;
  IpmcActuatorsConfig config;
  config.joints = SplitWords(*joints);
  if (config.joints.empty()) Fail(std::string(kAttrLinks) + " must name at least one hinge");
  for (size_t q = 0; q < config.joints.size(); ++q) {
    for (size_t r = 0; r < q; ++r) {
      if (config.joints[r] == config.joints[q]) {
        Fail(std::string(kAttrLinks) + " names '" + config.joints[q] +
             "' twice (each link drives its own hinge)");
      }
    }
  }
  const int segments = SegmentsPerLink(m);
  for (const std::string& joint : config.joints) {
    config.chains.push_back(FindChain(m, joint, segments, config.joints));
  }
  const IpmcModelKind kind = ModelKind(m);
  config.plants = overrides.plants ? *overrides.plants : Plants(m);
  config.actuation = ActuationOf(m);
  for (size_t q = 0; q < config.chains.size(); ++q) {
    config.links.push_back(AssignedLinkParams(config.plants, static_cast<int>(q) + 1, kind,
                                              config.chains[q].length_m));
  }
  OverridePerLink(m, kAttrA0, config.links,
                  [](IpmcLinkParams& p, double v) { p.a0_mm_per_V = v; });
  OverridePerLink(m, kAttrB1, config.links, [](IpmcLinkParams& p, double v) { p.b1 = v; });
  OverridePerLink(m, kAttrB2, config.links,
                  [](IpmcLinkParams& p, double v) { p.b2_s2 = v; });
  OverridePerLink(m, kAttrAlpha, config.links,
                  [](IpmcLinkParams& p, double v) { p.alpha = v; });
  if (auto band = FindCustomVector(m, kAttrBand)) {
    if (band->size() != 2) Fail(std::string(kAttrBand) + " must hold two values [w_b, w_h] in rad/s");
    for (IpmcLinkParams& p : config.links) {
      p.integrator.w_low_rad_s = (*band)[0];
      p.integrator.w_high_rad_s = (*band)[1];
    }
  }
  if (auto pairs = FindCustomInteger(m, kAttrPairs, 1, kMaxIntegratorPairs)) {
    for (IpmcLinkParams& p : config.links) p.integrator.n = *pairs;
  }
  config.integration = IntegrationOf(m);
  if (!overrides.physical_damping.empty() &&
      overrides.physical_damping.size() != static_cast<size_t>(m->nv)) {
    Fail("physical_damping must hold one value per dof (" + std::to_string(m->nv) + "), got " +
         std::to_string(overrides.physical_damping.size()));
  }
  config.physical_damping = overrides.physical_damping;
  // Flexible links only: a rigid link's hinge (k h / c = 0.156 in the
  // paper's model at 0.5 ms) keeps the moment held at the step's start,
  // which its step relaxes without the jumps' dissipation (docs/ENERGY.md).
  config.first_order_hold = !config.physical_damping.empty() && segments > 1;
  if (auto rel_tol = FindCustomScalar(m, kAttrRelTol)) config.cvode.rel_tol = *rel_tol;
  if (auto limit = FindCustomScalar(m, kAttrVoltageLimit)) {
    if (!std::isfinite(*limit) || !(*limit > 0.0)) {
      Fail(std::string(kAttrVoltageLimit) + " must be finite and > 0 V (got " +
           FormatShortest(*limit) + ")");
    }
    config.voltage_limit_V = *limit;
  }
  try {
    config.cvode.Validate();
  } catch (const std::invalid_argument& e) {
    Fail(std::string(kAttrRelTol) + ": " + e.what());
  }
  for (size_t q = 0; q < config.links.size(); ++q) {
    try {
      config.links[q].Validate();
    } catch (const std::invalid_argument& e) {
      Fail("link " + std::to_string(q + 1) + ": " + e.what());
    }
  }
  return config;
}

int ModelLinkCount(const mjModel* m) {
  const std::optional<IpmcActuatorsConfig> config = IpmcActuatorsConfig::FromModel(m);
  return config ? static_cast<int>(config->chains.size()) : 0;
}

Actuation ModelActuation(const mjModel* m) {
  const std::optional<IpmcActuatorsConfig> config = IpmcActuatorsConfig::FromModel(m);
  return config ? config->actuation : Actuation::kDistributed;
}

const std::vector<std::string>& IpmcActuatorFields() {
  static const std::vector<std::string> fields = {
      kAttrLinks, kAttrSegments, kAttrPlants, kAttrModel, kAttrActuation, kAttrBand,
      kAttrPairs, kAttrRelTol,   kAttrIntegration, kAttrA0, kAttrB1, kAttrB2, kAttrAlpha,
      kAttrVoltageLimit};
  return fields;
}

IpmcActuators::IpmcActuators(IpmcActuatorsConfig config) : config_(std::move(config)) {
  for (const LinkChain& chain : config_.chains) {
    length_m_.push_back(chain.length_m);
    shapes_.emplace_back(chain.segment_length_m);
  }
  curvature_1_m_.assign(config_.chains.size(), 0.0);
  voltage_V_.assign(config_.chains.size(), 0.0);
  bank_ = IpmcActuatorBank::Create(config_.links, config_.cvode, config_.integration);
}

void IpmcActuators::AdvanceTo(const mjData* d) {
  if (!std::isfinite(d->time)) {
    Fail(std::string("d->time is ") + (std::isnan(d->time) ? "NaN" : "infinite") +
         " (it must be finite)");
  }
  // A host that sets d->time = n h after each step (against the drift of
  // summing h) can land a rounding below the time the first-order hold
  // advanced the links to (t + h): the same time, not a step back.
  const double rounding_s = 1e-12 * std::max(1.0, std::abs(bank_->Time_s()));
  if (d->time < bank_->Time_s() - rounding_s) {
    // mj_resetData, an earlier d->time or an older mjData copied into d,
    // without RestoreState or ResetState: the link models cannot go back,
    // so they restart from rest, and the program hears of it.
    const double from_s = bank_->Time_s();
    ResetState(d);
    char message[320];
    std::snprintf(message, sizeof(message),
                  "ipmc: d->time went back from %.9g s to %.9g s without ipmc::RestoreState or "
                  "ipmc::ResetState; the IPMC link models restart from rest (0 V) at %.9g s",
                  from_s, d->time, d->time);
    mju_warning(message);
  } else if (d->time > bank_->Time_s()) {
    bank_->AdvanceTo(d->time);
  }
}

CouplingState IpmcActuators::SaveState() {
  bank_->Restart();
  CouplingState state;
  state.time_s = bank_->Time_s();
  const Eigen::VectorXd& x = bank_->State();
  state.actuator_state.assign(x.data(), x.data() + x.size());
  state.voltage_V = voltage_V_;
  state.curvature_1_m = curvature_1_m_;
  state.clamp_count = clamp_count_;
  return state;
}

void IpmcActuators::RestoreState(const mjData* d, const CouplingState& state) {
  const auto require_size = [](const char* field, size_t got, size_t needed, const char* what) {
    if (got != needed) {
      Fail(std::string("RestoreState: ") + field + " must hold " + std::to_string(needed) +
           " values, " + what + " (got " + std::to_string(got) + ")");
    }
  };
  const auto require_finite = [](const char* field, const std::vector<double>& values) {
    for (size_t i = 0; i < values.size(); ++i) {
      if (!std::isfinite(values[i])) {
        Fail(std::string("RestoreState: ") + field + "[" + std::to_string(i) + "] must be finite");
      }
    }
  };
  require_size("actuator_state", state.actuator_state.size(),
               static_cast<size_t>(bank_->States()), "the link models' states");
  require_size("voltage_V", state.voltage_V.size(), voltage_V_.size(), "one per link");
  require_size("curvature_1_m", state.curvature_1_m.size(), curvature_1_m_.size(), "one per link");
  require_finite("actuator_state", state.actuator_state);
  require_finite("voltage_V", state.voltage_V);
  require_finite("curvature_1_m", state.curvature_1_m);
  for (size_t q = 0; q < state.voltage_V.size(); ++q) {
    if (std::abs(state.voltage_V[q]) > config_.voltage_limit_V) {
      Fail("RestoreState: voltage_V[" + std::to_string(q) + "] = " +
           FormatShortest(state.voltage_V[q]) + " V is outside the model's range [-" +
           FormatShortest(config_.voltage_limit_V) + ", " +
           FormatShortest(config_.voltage_limit_V) + "] V (" + kAttrVoltageLimit + ")");
    }
  }
  if (state.clamp_count < 0) {
    Fail("RestoreState: clamp_count must be >= 0 (got " + std::to_string(state.clamp_count) + ")");
  }
  if (!std::isfinite(state.time_s) || state.time_s > d->time) {
    char message[200];
    std::snprintf(message, sizeof(message),
                  "RestoreState: time_s must be finite and <= d->time = %.17g s (got %.17g s); "
                  "copy the saved mjData into d first",
                  d->time, state.time_s);
    Fail(message);
  }
  voltage_V_ = state.voltage_V;
  if (config_.actuation == Actuation::kSingle) {
    for (size_t q = 1; q < voltage_V_.size(); ++q) voltage_V_[q] = 0.0;
  }
  bank_->SetVoltages(voltage_V_);
  bank_->SetState(state.time_s, Eigen::Map<const Eigen::VectorXd>(
                                    state.actuator_state.data(),
                                    static_cast<Eigen::Index>(state.actuator_state.size())));
  curvature_1_m_ = state.curvature_1_m;
  clamp_count_ = state.clamp_count;
}

void IpmcActuators::StoreState(const mjData* d, int offset) const {
  // d->userdata is the program's buffer, not part of const mjData.
  double* block = d->userdata + offset;
  *block++ = bank_->Time_s();
  const Eigen::VectorXd& x = bank_->State();
  block = std::copy(x.data(), x.data() + x.size(), block);
  block = std::copy(voltage_V_.begin(), voltage_V_.end(), block);
  block = std::copy(curvature_1_m_.begin(), curvature_1_m_.end(), block);
  *block = static_cast<double>(clamp_count_);
}

void IpmcActuators::LoadState(const mjData* d, int offset) {
  const double* block = d->userdata + offset;
  const size_t states = static_cast<size_t>(bank_->States()), links = voltage_V_.size();
  CouplingState state;
  state.time_s = block[0];
  state.actuator_state.assign(block + 1, block + 1 + states);
  state.voltage_V.assign(block + 1 + states, block + 1 + states + links);
  state.curvature_1_m.assign(block + 1 + states + links, block + 1 + states + 2 * links);
  state.clamp_count = static_cast<long>(block[1 + states + 2 * links]);
  RestoreState(d, state);
}

void IpmcActuators::ResetState(const mjData* d) {
  voltage_V_.assign(voltage_V_.size(), 0.0);
  bank_->SetVoltages(voltage_V_);
  bank_->Reset(d->time);
  curvature_1_m_.assign(curvature_1_m_.size(), 0.0);
  clamp_count_ = 0;
}

void IpmcActuators::SetVoltages(const mjData* d, const std::vector<double>& voltage_V) {
  if (voltage_V.size() != config_.chains.size()) {
    Fail("got " + std::to_string(voltage_V.size()) + " voltages for " +
         std::to_string(config_.chains.size()) + " links");
  }
  for (size_t q = 0; q < voltage_V.size(); ++q) {
    if (!std::isfinite(voltage_V[q])) Fail("voltage of link " + std::to_string(q + 1) + " is not finite");
    if (std::abs(voltage_V[q]) > config_.voltage_limit_V) {
      Fail("voltage of link " + std::to_string(q + 1) + " is " + FormatShortest(voltage_V[q]) +
           " V, outside the model's range [-" + FormatShortest(config_.voltage_limit_V) + ", " +
           FormatShortest(config_.voltage_limit_V) + "] V (" + kAttrVoltageLimit + ")");
    }
  }
  AdvanceTo(d);  // the old voltages hold up to now
  voltage_V_ = voltage_V;
  if (config_.actuation == Actuation::kSingle) {
    for (size_t q = 1; q < voltage_V_.size(); ++q) voltage_V_[q] = 0.0;
  }
  bank_->SetVoltages(voltage_V_);
}

void IpmcActuators::FreeShapeMoments(const mjModel* m, const mjData* d, int q,
                                     double deflection_mm, bool count_clamps,
                                     std::vector<double>* moment_N_m) {
  const LinkChain& chain = config_.chains[q];
  const ChainShape& shape = shapes_[q];
  bool clamped = false;
  double kappa_1_m = 0.0;
  if (config_.actuation == Actuation::kDistributed || q == 0) {
    kappa_1_m = shape.Curvature_1_m(deflection_mm * kMmToM, curvature_1_m_[q], &clamped);
  }
  if (clamped && count_clamps && clamp_count_++ == 0) {
    char message[200];
    std::snprintf(message, sizeof(message),
                  "ipmc link %d: free deflection %.6g mm at t = %.6g s exceeds the link's reach "
                  "%.6g mm; clamped (reported once per coupling)",
                  q + 1, deflection_mm, d->time, shape.Reach_m() / kMmToM);
    mju_warning(message);
  }
  curvature_1_m_[q] = kappa_1_m;
  for (size_t i = 0; i < chain.joints.size(); ++i) {
    (*moment_N_m)[chain.motors[i]] =
        m->jnt_stiffness[chain.joints[i]] * kappa_1_m * shape.Share_m(i);
  }
}

void IpmcActuators::BeginInertialStep(const mjModel* m) {
  inertial_step_ = config_.first_order_hold &&
                   (m->opt.integrator == mjINT_EULER || m->opt.integrator == mjINT_IMPLICIT);
}

void IpmcActuators::UpdateFirstOrderHold(const mjModel* m, mjData* d) {
  step_start_moment_N_m_.assign(m->nu, 0.0);
  step_end_moment_N_m_.assign(m->nu, 0.0);
  for (int q = 0; q < Links(); ++q) {
    // The step's start is the last step's end: its clamp was counted there.
    FreeShapeMoments(m, d, q, bank_->FreeTipDeflection_mm(q), false, &step_start_moment_N_m_);
  }
  const double h = m->opt.timestep;
  bank_->AdvanceTo(d->time + h);
  for (int q = 0; q < Links(); ++q) {
    FreeShapeMoments(m, d, q, bank_->FreeTipDeflection_mm(q), true, &step_end_moment_N_m_);
  }
  for (const LinkChain& chain : config_.chains) {
    for (size_t i = 0; i < chain.joints.size(); ++i) {
      const int joint = chain.joints[i], motor = chain.motors[i];
      const double spring_step = m->jnt_stiffness[joint] * h;  // k h
      const int dof = m->jnt_dofadr[joint];
      const double weight =
          spring_step > 0 ? (m->dof_damping[dof] - config_.physical_damping[dof]) / spring_step
                          : 0.5;
      d->ctrl[motor] = step_start_moment_N_m_[motor] +
                       weight * (step_end_moment_N_m_[motor] - step_start_moment_N_m_[motor]);
    }
  }
}

void IpmcActuators::Update(const mjModel* m, mjData* d) {
  AdvanceTo(d);
  if (inertial_step_) {
    inertial_step_ = false;  // once per step: the step's forward pass
    UpdateFirstOrderHold(m, d);
    return;
  }
  std::vector<double>& moment_N_m = scratch_moment_N_m_;
  moment_N_m.assign(m->nu, 0.0);
  for (int q = 0; q < Links(); ++q) {
    FreeShapeMoments(m, d, q, bank_->FreeTipDeflection_mm(q), true, &moment_N_m);
  }
  for (const LinkChain& chain : config_.chains) {
    for (int motor : chain.motors) d->ctrl[motor] = moment_N_m[motor];
  }
}

}  // namespace ipmc

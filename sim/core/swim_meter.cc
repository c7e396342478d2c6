#include "sim/core/swim_meter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ipmc_swim/ipmc_swim.h"
#include "ipmc_swim/point_velocity.h"

namespace ipmc {
namespace {

constexpr double kMToMm = 1e3;
constexpr int kRootBody = 1;

}  // namespace

SwimMeter::SwimMeter(const mjModel* m, const mjData* d) {
  for (int q = 1;; ++q) {
    LinkTip tip;
    tip.site = mj_name2id(m, mjOBJ_SITE, ("tip" + std::to_string(q)).c_str());
    if (tip.site < 0) break;
    tips_.push_back(tip);
  }
  if (tips_.empty() && d != nullptr) tips_ = LinkTips(m, d, "the swim meter's model");
}

BodyPose SwimMeter::Pose(const mjData* d) const {
  BodyPose pose;
  pose.t_s = d->time;
  pose.com_x_mm = d->subtree_com[3 * kRootBody] * kMToMm;
  pose.com_y_mm = d->subtree_com[3 * kRootBody + 1] * kMToMm;
  pose.head_x_mm = d->xpos[3 * kRootBody] * kMToMm;
  pose.head_y_mm = d->xpos[3 * kRootBody + 1] * kMToMm;
  const mjtNum* xmat = d->xmat + 9 * kRootBody;
  pose.yaw_rad = std::atan2(xmat[3], xmat[0]);
  for (const LinkTip& tip : tips_) {
    double tip_m[3];
    tip.Position_W(d, tip_m);
    pose.tip_x_mm.push_back(tip_m[0] * kMToMm);
    pose.tip_y_mm.push_back(tip_m[1] * kMToMm);
  }
  return pose;
}

void SwimMeter::Start(const mjData* d) {
  run_start_ = cycle_start_ = Pose(d);
  cycle_starts_.clear();
  metrics_ = SwimMetrics();
}

void SwimMeter::Start(const mjModel* m, const mjData* d, double frequency_Hz,
                      double controller_rate_Hz) {
  Start(d);
  metrics_.step = MeasureStepResolution(m, d, std::abs(frequency_Hz));
  metrics_.controller_rate_Hz = controller_rate_Hz;
}

double SwimMetrics::LargestReynolds() const {
  return std::max({reynolds_tip, reynolds_swim, reynolds_oscillatory});
}

void SwimMeter::Observe(const mjModel* m, const mjData* d) {
  if (tips_.empty()) return;
  const LinkTip& tip = tips_.back();
  double tip_m[3];
  tip.Position_W(d, tip_m);
  mjtNum velocity_W[3];
  PointVelocity_W(m, d, tip.Body(m), tip_m, velocity_W);
  const double velocity_y_m_s = velocity_W[1];
  metrics_.peak_lateral_tip_speed_mm_s =
      std::max(metrics_.peak_lateral_tip_speed_mm_s, std::abs(velocity_y_m_s) * kMToMm);
}

void SwimMeter::EndCycle(const mjData* d) {
  const BodyPose end = Pose(d);
  metrics_.per_cycle.push_back({-(end.com_x_mm - cycle_start_.com_x_mm),
                                end.com_y_mm - cycle_start_.com_y_mm,
                                -(end.head_x_mm - cycle_start_.head_x_mm),
                                end.head_y_mm - cycle_start_.head_y_mm});
  cycle_starts_.push_back(cycle_start_);
  cycle_start_ = end;
}

SwimMetrics SwimMeter::Finish(const mjData* d, int from_cycle,
                              double wavelength_mm, double frequency_Hz) const {
  SwimMetrics metrics = metrics_;
  metrics.frequency_Hz = std::abs(frequency_Hz);
  const BodyPose end = Pose(d);
  // Cycle `from_cycle` began at the start of the run (cycle 1), at the
  // start recorded when it ended, or at the start of the cycle running.
  const size_t first = static_cast<size_t>(std::max(1, from_cycle) - 1);
  const BodyPose* start = &run_start_;
  if (first > 0 && first < cycle_starts_.size()) start = &cycle_starts_[first];
  if (first > 0 && first == cycle_starts_.size()) start = &cycle_start_;
  metrics.from_cycle = start == &run_start_ ? 1 : from_cycle;
  const double elapsed_s = end.t_s - start->t_s;
  if (elapsed_s > 0.0) {
    metrics.mean_speed_along_mm_s = -(end.com_x_mm - start->com_x_mm) / elapsed_s;
  }
  const FluidFacts fluid = IsAttached(d) ? FluidOf(d) : FluidFacts{};
  if (!fluid.drag) {
    metrics.warnings = FluidWarnings(metrics, wavelength_mm);
    return metrics;
  }
  double body_length_m = 0.0, longest_m = 0.0;
  for (double length_m : fluid.segment_length_m) {
    body_length_m += length_m;
    longest_m = std::max(longest_m, length_m);
  }
  metrics.body_length_mm = body_length_m * kMToMm;
  metrics.viscosity_Pa_s = fluid.viscosity_Pa_s;
  metrics.longest_segment_mm = longest_m * kMToMm;
  const double width_m = fluid.strip_width_m;
  const double rho_over_mu = fluid.density_kg_m3 / fluid.viscosity_Pa_s;
  metrics.reynolds_tip = rho_over_mu * metrics.peak_lateral_tip_speed_mm_s / kMToMm * width_m;
  metrics.reynolds_swim =
      rho_over_mu * std::abs(metrics.mean_speed_along_mm_s) / kMToMm * body_length_m;
  constexpr double kTwoPi = 6.283185307179586;
  metrics.reynolds_oscillatory =
      rho_over_mu * kTwoPi * metrics.frequency_Hz * width_m * width_m / 4.0;
  metrics.step = WithSwimStepError(metrics.step, metrics.peak_lateral_tip_speed_mm_s,
                                   metrics.body_length_mm, metrics.mean_speed_along_mm_s);
  metrics.warnings = FluidWarnings(metrics, wavelength_mm);
  return metrics;
}

std::vector<std::string> FluidWarnings(const SwimMetrics& swim, double wavelength_mm) {
  std::vector<std::string> warnings =
      StepResolutionWarnings(swim.step, swim.controller_rate_Hz);
  const double reynolds = swim.LargestReynolds();
  if (reynolds > kReynoldsWarning) {
    // Every Reynolds number here goes as rho f / mu at a given wave shape.
    std::ostringstream msg;
    msg << std::setprecision(3) << "Reynolds numbers " << swim.reynolds_tip << " (tip), "
        << swim.reynolds_swim << " (swim)";
    if (swim.reynolds_oscillatory > 0.0) msg << ", " << swim.reynolds_oscillatory << " (oscillatory)";
    msg << ": above " << kReynoldsWarning
        << ", where the liquid's inertia matters and every fluid model here (Stokes flow, Re << "
           "1) does not hold, so the swim and the powers are not predictions; Re = "
        << kReynoldsStokes << " needs";
    const double viscosity_Pa_s = swim.viscosity_Pa_s * reynolds / kReynoldsStokes;
    msg << " a viscosity of " << viscosity_Pa_s << " Pa s";
    if (swim.frequency_Hz > 0.0) {
      msg << " at " << swim.frequency_Hz << " Hz, or " << swim.frequency_Hz * kReynoldsStokes / reynolds
          << " Hz in this liquid";
    }
    msg << " (docs/REGIME.md)";
    warnings.push_back(msg.str());
  }
  if (wavelength_mm > 0.0 && swim.longest_segment_mm > 0.0 &&
      wavelength_mm / swim.longest_segment_mm < kMinSegmentsPerWavelength) {
    std::ostringstream msg;
    msg << "the wave (wavelength " << std::setprecision(4) << wavelength_mm << " mm) spans "
        << std::setprecision(3) << wavelength_mm / swim.longest_segment_mm
        << " drag segments of " << swim.longest_segment_mm << " mm, fewer than "
        << kMinSegmentsPerWavelength
        << " per wavelength: the links cannot represent it (more segments_per_link or links)";
    warnings.push_back(msg.str());
  }
  return warnings;
}

void RequireFiniteMetrics(const SwimMetrics& swim, const std::string& what) {
  const auto require = [&](double value, const std::string& name) {
    if (!std::isfinite(value)) {
      throw std::runtime_error(what + ": " + name + " is not finite (the run diverged)");
    }
  };
  for (std::size_t k = 0; k < swim.per_cycle.size(); ++k) {
    const Displacement_mm& c = swim.per_cycle[k];
    const std::string cycle = "cycle " + std::to_string(k + 1) + "'s displacement";
    for (double value : {c.com_along, c.com_across, c.head_along, c.head_across}) {
      require(value, cycle);
    }
  }
  require(swim.mean_speed_along_mm_s, "the mean speed");
  require(swim.peak_lateral_tip_speed_mm_s, "the peak tip speed");
  require(swim.reynolds_tip, "the Reynolds number");
  require(swim.reynolds_swim, "the Reynolds number");
}

}  // namespace ipmc

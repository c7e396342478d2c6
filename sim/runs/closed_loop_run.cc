#include "sim/runs/closed_loop_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "controllers/controller_names.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "sim/core/link_sensors.h"
#include "sim/core/step_count.h"

namespace ipmc {

LinkGeometry ModelLinkGeometry(const Simulation& sim) {
  const mjModel* m = sim.model();
  const mjData* d = sim.data();
  const std::string& source = sim.source();
  LinkGeometry geometry;
  if (!IsAttached(d) || LinkCount(d) == 0) {
    throw std::runtime_error(source + ": model has no IPMC actuators (custom text ipmc_links)");
  }
  // Each link's root hinge, then the last link's tip (LinkTips).
  std::vector<double> hinge_x_mm;
  for (int q = 0; q < LinkCount(d); ++q) {
    hinge_x_mm.push_back(d->xanchor[3 * LinkJoints(d, q).front()] * 1e3);
  }
  const std::vector<LinkTip> tips = LinkTips(m, d, source);
  double tip_m[3];
  tips.back().Position_W(d, tip_m);
  hinge_x_mm.push_back(tip_m[0] * 1e3);
  for (size_t q = 0; q + 1 < hinge_x_mm.size(); ++q) {
    geometry.pitch_mm.push_back(hinge_x_mm[q + 1] - hinge_x_mm[q]);
  }
  for (int q = 0; q < LinkCount(d); ++q) geometry.length_mm.push_back(LinkLength_m(d, q) * 1e3);
  return geometry;
}

long StepsPerSample(double sample_rate_Hz, double dt_s, const std::string& source) {
  const double ratio = 1.0 / (sample_rate_Hz * dt_s);
  const long steps = std::lround(ratio);
  if (steps < 1 || std::abs(ratio - steps) > 1e-6) {
    std::ostringstream msg;
    msg << source << ": controller.sample_rate_Hz " << sample_rate_Hz
        << " must divide the step rate " << 1.0 / dt_s << " Hz";
    throw std::runtime_error(msg.str());
  }
  return steps;
}

namespace {

// Calls a RunHeartbeat once kHeartbeatInterval_s of wall time has gone
// since the last call (the clock is read every kStride steps: a step takes
// microseconds at the least).
class HeartbeatClock {
 public:
  explicit HeartbeatClock(const RunHeartbeat& heartbeat)
      : heartbeat_(heartbeat), last_(std::chrono::steady_clock::now()) {}
  void Tick(double t_s) {
    if (!heartbeat_ || ++steps_ % kStride != 0) return;
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_).count() < kHeartbeatInterval_s) return;
    last_ = now;
    heartbeat_(t_s);
  }

 private:
  static constexpr long kStride = 16;
  const RunHeartbeat& heartbeat_;
  std::chrono::steady_clock::time_point last_;
  long steps_ = 0;
};

}  // namespace

void RequireSamplesPerWaveCycle(const ScenarioConfig& scenario, double period_s,
                                double sample_period_s) {
  // Exactly, not after rounding to whole steps: 9.9 samples are too few.
  const double samples = period_s / sample_period_s;
  if (samples >= kMinSamplesPerWaveCycle * (1.0 - 1e-12)) return;
  throw std::invalid_argument(FormatText(
      "%s: waveform.frequency_Hz %.6g gives %.4g controller samples per wave cycle at %.6g Hz "
      "(controller.sample_rate_Hz); a cycle takes at least %ld controller samples: at most "
      "%.6g Hz",
      scenario.source.c_str(), scenario.waveform.frequency_Hz, samples, 1.0 / sample_period_s,
      kMinSamplesPerWaveCycle, 1.0 / (kMinSamplesPerWaveCycle * sample_period_s)));
}

std::vector<double> LinkReferences_mm(const ScenarioConfig& scenario,
                                      const LinkGeometry& geometry, double t_s) {
  const double period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);
  const DiscreteWave wave = DiscretiseWave(scenario.waveform, geometry, t_s);
  const double ramp = StartRamp(t_s, scenario.waveform.start_ramp_cycles * period_s);
  std::vector<double> reference(wave.relative_deflection_mm.size());
  for (size_t q = 0; q < reference.size(); ++q) {
    reference[q] = ramp * wave.relative_deflection_mm[q];
  }
  return reference;
}

void CheckLinkGains(const ScenarioConfig& scenario, int links) {
  const ControllerScenario::LinkGains& each = scenario.controller.link_gains;
  const std::pair<const char*, const std::vector<double>*> arrays[] = {
      {"controller.link_kp", &each.kp},     {"controller.link_ki", &each.ki},
      {"controller.link_kd", &each.kd},     {"controller.link_gain", &each.gain},
      {"controller.link_order", &each.order}};
  for (const auto& [key, values] : arrays) {
    if (!values->empty() && static_cast<int>(values->size()) != links) {
      throw std::runtime_error(scenario.source + ": " + key + " must hold one value per link (" +
                               std::to_string(links) + "; got " +
                               std::to_string(values->size()) + ")");
    }
  }
}

int MetricsFromCycle(const ScenarioConfig& scenario) {
  if (scenario.metrics.from_cycle > 0) return scenario.metrics.from_cycle;
  const double after_ramp = std::ceil(std::max(0.0, scenario.waveform.start_ramp_cycles)) + 1.0;
  return static_cast<int>(
      std::min(after_ramp, static_cast<double>(std::max(1, scenario.run.cycles))));
}

ClosedLoopResult SimulateScenario(const ScenarioConfig& scenario, const SampleObserver& observer,
                                  const RunHeartbeat& heartbeat) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  return StepClosedLoop(*sim, scenario, observer, heartbeat);
}

namespace {

// A run's timing: the time step, the controller's sample and the wave
// cycle in steps, and which samples are recorded.
struct ClosedLoopTiming {
  double dt_s = 0.0;
  double period_s = 0.0;
  long steps_per_sample = 0;
  double sample_period_s = 0.0;
  long steps_per_cycle = 0;
  long samples_per_cycle = 0;
  long record_every = 0;  // a recorded sample every this many controller samples
};

// The timing of `scenario` on model `m` with `links` links; throws, naming
// the scenario's key, if a controller sample or a wave cycle takes too few
// steps or the run is too long or too large to record.
ClosedLoopTiming PlanTiming(const ScenarioConfig& scenario, const mjModel* m, int links) {
  ClosedLoopTiming timing;
  const double dt = m->opt.timestep;
  timing.dt_s = dt;
  timing.period_s = 1.0 / std::abs(scenario.waveform.frequency_Hz);
  CheckedStepCount(1.0 / scenario.controller.sample_rate_Hz, dt, 1,
                   scenario.source + ": one controller sample (controller.sample_rate_Hz)");
  timing.steps_per_sample = StepsPerSample(scenario.controller.sample_rate_Hz, dt, scenario.source);
  timing.sample_period_s = timing.steps_per_sample * dt;
  RequireSamplesPerWaveCycle(scenario, timing.period_s, timing.sample_period_s);
  // At least kMinSamplesPerWaveCycle controller samples per wave cycle.
  timing.steps_per_cycle = CheckedStepCount(
      timing.period_s, dt, kMinSamplesPerWaveCycle * timing.steps_per_sample,
      scenario.source + ": one wave cycle (waveform.frequency_Hz), at least " +
          std::to_string(kMinSamplesPerWaveCycle) + " controller samples,");
  timing.samples_per_cycle = timing.steps_per_cycle / timing.steps_per_sample;
  timing.record_every =
      std::max<long>(1, timing.samples_per_cycle / std::max(1, scenario.output.samples_per_cycle));
  const double recorded =
      static_cast<double>(scenario.run.cycles) * timing.samples_per_cycle / timing.record_every;
  CheckRunSize(static_cast<double>(scenario.run.cycles) * timing.steps_per_cycle,
               recorded * RecordedSampleBytes(m->nq, links), scenario.run.allow_long,
               scenario.source + ": the run (cycles x waveform.frequency_Hz)");
  return timing;
}

// Each link's tracking metrics (LinkTracking) over the measured cycles:
// IAE and ITAE, the largest error and reference, the RMS and peak voltage,
// the fraction of samples at the clamp and the peak active moment.
class LinkTrackingMeter {
 public:
  LinkTrackingMeter(int links, int driven, bool clamped, double v_max_V, double sample_period_s)
      : links_(links),
        driven_(driven),
        clamped_(clamped),
        v_max_V_(v_max_V),
        sample_period_s_(sample_period_s),
        tracking_(links),
        sum_v2_(links, 0.0),
        clamped_samples_(links, 0) {}

  // One controller sample at `t_s` of every link.
  void AddSample(double t_s, const std::vector<double>& reference_mm,
                 const std::vector<double>& measured_mm, const std::vector<double>& volts) {
    for (int q = 0; q < links_; ++q) {
      const double error = reference_mm[q] - measured_mm[q];
      LinkTracking& track = tracking_[q];
      track.Add(t_s, error, sample_period_s_);
      track.max_abs_error_mm = std::max(track.max_abs_error_mm, std::abs(error));
      track.max_abs_reference_mm = std::max(track.max_abs_reference_mm, std::abs(reference_mm[q]));
      sum_v2_[q] += volts[q] * volts[q];
      track.peak_voltage_V = std::max(track.peak_voltage_V, std::abs(volts[q]));
      if (clamped_ && q < driven_ && std::abs(volts[q]) >= v_max_V_ * (1.0 - 1e-12)) {
        ++clamped_samples_[q];
      }
    }
    ++samples_;
  }

  // The active moments after a step, each link's read at its root hinge.
  void ObserveMoments(const mjData* d, const std::vector<int>& root_dofs) {
    for (size_t q = 0; q < root_dofs.size() && q < tracking_.size(); ++q) {
      double& peak = tracking_[q].peak_moment_Nm;
      peak = std::max(peak, std::abs(d->qfrc_actuator[root_dofs[q]]));
    }
  }

  std::vector<LinkTracking> Finish() {
    for (int q = 0; q < links_; ++q) {
      tracking_[q].rms_voltage_V = std::sqrt(sum_v2_[q] / std::max<long>(1, samples_));
      tracking_[q].clamped_fraction =
          static_cast<double>(clamped_samples_[q]) / std::max<long>(1, samples_);
    }
    return tracking_;
  }

 private:
  int links_, driven_;
  bool clamped_;
  double v_max_V_, sample_period_s_;
  std::vector<LinkTracking> tracking_;
  std::vector<double> sum_v2_;
  std::vector<long> clamped_samples_;
  long samples_ = 0;
};

// The result's description of the run, before its samples and metrics.
ClosedLoopResult StartResult(const ScenarioConfig& scenario, const mjModel* m,
                             const ClosedLoopTiming& timing, int links) {
  const bool pid = scenario.controller.kind == ControllerKind::kPid;
  ClosedLoopResult result;
  result.controller = pid ? controller_names::kPid : controller_names::kFractional;
  result.actuation = scenario.actuation;
  result.clamp_enabled =
      pid ? scenario.controller.pid.clamp_enabled : scenario.controller.fractional.clamp_enabled;
  result.v_max_V = pid ? scenario.controller.pid.v_max : scenario.controller.fractional.v_max;
  if (scenario.drive.OpenLoop()) {
    // The open-loop drive in the controller's place ("sine", "csv"), unclamped.
    result.controller = ChoiceText(kDriveModeNames, scenario.drive.mode);
    result.open_loop = true;
    result.clamp_enabled = false;
    result.v_max_V = 0.0;
  }
  result.period_s = timing.period_s;
  result.timestep_s = timing.dt_s;
  result.links.resize(links);
  result.states = RecordedStates::For(m);
  result.notes = scenario.notes;
  return result;
}

// The result's metrics once the last cycle is stepped: the swim, its
// warnings, the energy and the clamps reached.
void FinishResult(const ScenarioConfig& scenario, const ClosedLoopTiming& timing, int from_cycle,
                  Simulation& sim, SwimMeter& meter, EnergyMeter& energy,
                  ClosedLoopResult& result) {
  mjData* d = sim.data();
  result.swim = meter.Finish(d, from_cycle, scenario.waveform.wavelength_mm,
                             scenario.waveform.frequency_Hz);
  if (scenario.output.samples_per_cycle > timing.samples_per_cycle) {
    // Not silently fewer rows than asked for.
    result.swim.warnings.push_back(FormatText(
        "%s: output.samples_per_cycle %d is more than the %ld controller samples of a wave cycle "
        "(controller.sample_rate_Hz / waveform.frequency_Hz): recorded every sample, %ld a cycle",
        scenario.source.c_str(), scenario.output.samples_per_cycle, timing.samples_per_cycle,
        timing.samples_per_cycle));
  }
  RequireFiniteMetrics(result.swim, sim.source());
  result.energy = energy.Finish(result.swim, timing.period_s, from_cycle);
  result.from_cycle_given = scenario.metrics.from_cycle > 0;
  result.startup_included = from_cycle - 1 < scenario.waveform.start_ramp_cycles;
  result.reach_clamps = ClampCount(d);
}

}  // namespace

ClosedLoopResult StepClosedLoop(Simulation& sim, const ScenarioConfig& scenario,
                                const SampleObserver& observer, const RunHeartbeat& heartbeat,
                                const LinkReferenceSource& references) {
  scenario.waveform.Validate();
  mjModel* m = sim.model();
  mjData* d = sim.data();
  const LinkSensors sensors(m, d, sim.source());
  const int links = sensors.Links();
  const LinkGeometry geometry = ModelLinkGeometry(sim);
  const int driven = scenario.actuation == Actuation::kSingle ? 1 : links;
  const bool open_loop = scenario.drive.OpenLoop();
  std::vector<LinkController> controllers;
  CheckLinkGains(scenario, links);
  if (!open_loop) {
    for (int q = 0; q < driven; ++q) controllers.emplace_back(scenario, q);
  }
  const ClosedLoopTiming timing = PlanTiming(scenario, m, links);
  const OpenLoopVoltages drive(scenario.drive, scenario.waveform.frequency_Hz,
                               scenario.waveform.start_ramp_cycles * timing.period_s, links,
                               scenario.source);

  const int from_cycle = MetricsFromCycle(scenario);
  ClosedLoopResult result = StartResult(scenario, m, timing, links);
  LinkTrackingMeter tracking(links, driven, result.clamp_enabled, result.v_max_V,
                             timing.sample_period_s);
  std::vector<double> volts(links, 0.0), reference(links, 0.0), measured(links, 0.0);
  long samples = 0;
  SwimMeter meter(m, d);
  meter.Start(m, d, scenario.waveform.frequency_Hz, scenario.controller.sample_rate_Hz);
  EnergyMeter energy(m, d);
  // Each link's active moment is read at its root hinge.
  std::vector<int> root_dofs;
  for (const std::vector<int>& dofs : energy.LinkDofs()) root_dofs.push_back(dofs.front());
  energy.MeasureElectrical(scenario.metrics.electrical, geometry.length_mm);
  HeartbeatClock beat(heartbeat);
  for (int cycle = 0; cycle < scenario.run.cycles; ++cycle) {
    // The link metrics are taken over the cycles from MetricsFromCycle.
    const bool measuring = cycle + 1 >= from_cycle;
    for (long step = 0; step < timing.steps_per_cycle; ++step) {
      if (step % timing.steps_per_sample == 0) {
        const double t = d->time;
        if (open_loop) {
          // No references: the link metrics measure the deflections themselves.
          const std::vector<double> given = drive.At(t);
          for (int q = 0; q < links; ++q) {
            measured[q] = sensors.RelativeDeflection_mm(d, q);
            volts[q] = q < driven ? given[q] : 0.0;
          }
        } else {
          reference = references ? references(t) : LinkReferences_mm(scenario, geometry, t);
          if (static_cast<int>(reference.size()) != links) {
            throw std::invalid_argument(sim.source() + ": " + std::to_string(reference.size()) +
                                        " references for " + std::to_string(links) + " links");
          }
          for (int q = 0; q < links; ++q) {
            measured[q] = sensors.RelativeDeflection_mm(d, q);
            volts[q] = q < driven ? controllers[q].Update(reference[q] - measured[q]) : 0.0;
          }
        }
        if (measuring) tracking.AddSample(t, reference, measured, volts);
        SetVoltages(d, volts.data(), links);
        if (samples % timing.record_every == 0) {
          result.samples.push_back({meter.Pose(d), reference, measured, volts});
          result.states.Record(d);
          if (observer) observer(m, d, result.samples.back());
        }
        ++samples;
      }
      // The sensors are read at the next sample, from this step's values.
      const long next = step + 1 == timing.steps_per_cycle ? 0 : step + 1;
      sim.Step(next % timing.steps_per_sample == 0);
      beat.Tick(d->time);
      meter.Observe(m, d);
      energy.Observe(m, d);
      if (measuring) tracking.ObserveMoments(d, root_dofs);
    }
    meter.EndCycle(d);
    energy.EndCycle(m, d);
  }
  result.links = tracking.Finish();
  FinishResult(scenario, timing, from_cycle, sim, meter, energy, result);
  return result;
}

}  // namespace ipmc

// Closed-loop swimming (paper section 5): every driven IPMC link has its
// own controller (the PID of eq. 12 or the fractional integrator of eq. 14),
// sampled at a fixed rate, which reads the link's measured relative tip
// deflection from the sensors (sim/core/link_sensors.h) and tracks the link's
// reference from the discretised travelling wave (sim/core/waveform.h); its
// clamped voltage drives the link through ipmc::SetVoltages and is held
// until the next sample. In single actuation only link 1 is driven (it
// tracks its own reference); the other links get 0 V and are passive.
// The references fade in over the scenario's start ramp. In open loop
// (drive.mode "sine" or "csv", sim/core/drive_keys.h) the drive's voltages
// take the controllers' place at the same samples, the references are 0
// and the links' IAE and ITAE measure the deflections themselves.
//
// Tracking indices per link, over the cycles from MetricsFromCycle (by
// default the cycles after the start ramp; rectangle rule at the sample rate),
// e = r - y [mm]:
//   IAE = int |e| dt [mm s],  ITAE = int t |e| dt [mm s^2]  (t from the run's start)
// plus the RMS and peak voltage and the fraction of samples at the clamp;
// the mean speed and the energy's means are over the same cycles, the
// per-cycle tables keep every cycle.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "controllers/closed_loop.h"
#include "sim/core/energy.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/simulation.h"
#include "sim/core/swim_meter.h"
#include "sim/runs/recorded_states.h"

namespace ipmc {

// IAE and ITAE (TrackingIndices), and the rest of the link's tracking.
struct LinkTracking : TrackingIndices {
  double max_abs_error_mm = 0.0;
  double max_abs_reference_mm = 0.0;
  double rms_voltage_V = 0.0;
  double peak_voltage_V = 0.0;
  // The largest |active moment| E I kappa of the link's IPMC, the same at
  // each of its hinges (plugin/actuators/ipmc_actuators.h) [N m].
  double peak_moment_Nm = 0.0;
  double clamped_fraction = 0.0;
};

struct ClosedLoopSample {
  BodyPose pose;
  std::vector<double> reference_mm, measured_mm, voltage_V;
};

struct ClosedLoopResult {
  // The controller's kind ("pid", "fractional"), or in open loop the
  // drive's mode ("sine", "csv"; sim/core/drive_keys.h).
  std::string controller;
  bool open_loop = false;
  Actuation actuation = Actuation::kDistributed;
  bool clamp_enabled = false;  // the voltages clamped to +-v_max_V
  double v_max_V = 0.0;
  double period_s = 0.0;
  double timestep_s = 0.0;
  std::vector<LinkTracking> links;
  SwimMetrics swim;
  EnergyMetrics energy;
  // Why the metrics start at swim.from_cycle (MetricsFromCycle): true when
  // the scenario's metrics.from_cycle chose it, else the start ramp did;
  // startup_included when no cycle follows the ramp, so the metric cycles
  // hold the start-up.
  bool from_cycle_given = false;
  bool startup_included = false;
  // How often a link's free deflection went beyond the link's reach and
  // was clamped (IpmcActuators::ClampCount).
  long reach_clamps = 0;
  // The scenario reader's notes (ScenarioConfig::notes).
  std::vector<std::string> notes;
  std::vector<ClosedLoopSample> samples;
  RecordedStates states;  // the model's qpos at every recorded sample
};

// Called with every recorded sample (output.samples_per_cycle per cycle),
// for example to render a frame of the model's current state.
using SampleObserver =
    std::function<void(const mjModel* m, const mjData* d, const ClosedLoopSample& sample)>;
// Called between recorded samples with the simulated time, at least every
// kHeartbeatInterval_s of wall time whatever the time step, so that a stop
// request (it may throw) is seen soon even when samples are far apart.
using RunHeartbeat = std::function<void(double t_s)>;
constexpr double kHeartbeatInterval_s = 0.1;

// Link q's controller (0-based), whichever kind the scenario names, with
// that link's gains where the scenario gives them per link
// (CheckLinkGains first).
class LinkController {
 public:
  LinkController(const ScenarioConfig& scenario, int q) {
    if (scenario.controller.kind == ControllerKind::kPid) {
      pid_ = std::make_unique<PidController>(scenario.controller.LinkPid(q));
    } else {
      fractional_ = std::make_unique<FractionalIntegrator>(scenario.controller.LinkFractional(q));
    }
  }
  double Update(double error_mm) {
    return pid_ ? pid_->Update(error_mm) : fractional_->Update(error_mm);
  }

 private:
  std::unique_ptr<PidController> pid_;
  std::unique_ptr<FractionalIntegrator> fractional_;
};

// Throws std::runtime_error naming the scenario and key unless every
// controller.link_* array the scenario gives holds one value per link.
void CheckLinkGains(const ScenarioConfig& scenario, int links);

// Throws std::invalid_argument naming waveform.frequency_Hz unless a wave
// period of period_s holds at least kMinSamplesPerWaveCycle controller
// samples of sample_period_s (exactly: 9.9 are refused).
void RequireSamplesPerWaveCycle(const ScenarioConfig& scenario, double period_s,
                                double sample_period_s);

// The first cycle (1-based) of a run's link metrics, mean speed and mean
// powers: metrics.from_cycle if the scenario gives it; else the first
// cycle that starts after the start ramp, ceil(start_ramp_cycles) + 1 (2
// for the paper's quarter period), or the last cycle if no cycle does.
int MetricsFromCycle(const ScenarioConfig& scenario);

// A scenario made into a run: loads its model (LoadScenarioSimulation) and
// steps it (StepClosedLoop). Throws std::runtime_error naming the file on
// bad input or divergence.
ClosedLoopResult SimulateScenario(const ScenarioConfig& scenario,
                                  const SampleObserver& observer = {},
                                  const RunHeartbeat& heartbeat = {});

// Every link's reference [mm] at the sample time t [s], in place of the
// scenario's wave (LinkReferences_mm): e.g. a step on one link with the
// others held at rest (`step --bench`). One value per link.
using LinkReferenceSource = std::function<std::vector<double>(double t_s)>;

// The closed-loop stepping loop on an existing simulation (its time step
// and fluid as they are): controllers, references (the scenario's wave,
// or `references` if given), metrics.
ClosedLoopResult StepClosedLoop(Simulation& sim, const ScenarioConfig& scenario,
                                const SampleObserver& observer = {},
                                const RunHeartbeat& heartbeat = {},
                                const LinkReferenceSource& references = {});

// The segment pitches of a model at rest (each IPMC link's root hinge, and
// the last link's tip: LinkTips, sim/core/link_sensors.h) and its links'
// lengths, which the references are projected on. Throws
// std::runtime_error naming the model if it has no IPMC links.
LinkGeometry ModelLinkGeometry(const Simulation& sim);

// Every link's reference at t [mm]: the discretised wave faded in by the
// start ramp.
std::vector<double> LinkReferences_mm(const ScenarioConfig& scenario,
                                      const LinkGeometry& geometry, double t_s);

// Physics steps per controller sample; throws std::runtime_error naming
// `source` unless the sample period is a whole number of steps dt_s.
long StepsPerSample(double sample_rate_Hz, double dt_s, const std::string& source);

}  // namespace ipmc

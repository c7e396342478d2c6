#include "sim/runs/bench_run.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "ipmc_swim/fields.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/core/step_count.h"
#include "sim/core/link_sensors.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr char kWho[] = "bench";

// FieldError "bench: FIELD must be finite and > 0, got V" unless it is.
void RequirePositive(double value, const char* field) { RequireFinitePositive(kWho, field, value); }

// `what` (a step count's or run size's check on `field`) as a FieldError
// naming the field.
template <typename F>
auto NamingField(const char* field, const std::string& allowed, F&& f) {
  try {
    return f();
  } catch (const FieldError&) {
    throw;
  } catch (const std::invalid_argument& error) {
    throw FieldError(error.what(), field, allowed);
  }
}

}  // namespace

void BenchSignal::Validate() const {
  if (!std::isfinite(amplitude_V) || std::abs(amplitude_V) > kDefaultVoltageLimit_V) {
    ThrowOption(kWho, "amplitude_V",
                "finite and within [-" + FormatShortest(kDefaultVoltageLimit_V) + ", " +
                    FormatShortest(kDefaultVoltageLimit_V) + "] V",
                FormatShortest(amplitude_V));
  }
  RequirePositive(duration_s, "duration_s");
  RequirePositive(sample_rate_Hz, "sample_rate_Hz");
  if (kind == Kind::kSine) {
    RequirePositive(frequency_Hz, "frequency_Hz");
  } else {
    RequirePositive(start_Hz, "start_Hz");
    if (!(end_Hz > start_Hz) || !(end_Hz < 0.5 * sample_rate_Hz)) {
      ThrowOption(kWho, "end_Hz",
                  "in (start_Hz, sample_rate_Hz / 2) = (" + FormatShortest(start_Hz) + ", " +
                      FormatShortest(0.5 * sample_rate_Hz) + ")",
                  FormatShortest(end_Hz));
    }
  }
  if (driven_links.empty()) {
    throw FieldError("bench: driven_links is empty", "driven_links", "at least one link");
  }
}

double BenchSignal::VoltageAt(double t_s) const {
  if (kind == Kind::kSine) return amplitude_V * std::sin(kTwoPi * frequency_Hz * t_s);
  const double sweep_Hz_s = (end_Hz - start_Hz) / duration_s;
  return amplitude_V * std::sin(kTwoPi * (start_Hz * t_s + 0.5 * sweep_Hz_s * t_s * t_s));
}

BenchRecord RunBench(Simulation& sim, const BenchSignal& signal, double record_from_s,
                     const BenchProgress& progress) {
  signal.Validate();
  mjModel* m = sim.model();
  mjData* d = sim.data();
  const LinkSensors sensors(m, d, sim.source());
  const int links = sensors.Links();
  for (int link : signal.driven_links) {
    if (link < 1 || link > links) {
      throw FieldError("bench: driven link " + std::to_string(link) + " is outside [1, " +
                           std::to_string(links) + "]",
                       "driven_links", "links of the model, 1-based");
    }
  }
  const double dt = m->opt.timestep;
  const std::string whole_steps = "a whole number of time steps per sample";
  NamingField("sample_rate_Hz", whole_steps, [&] {
    return CheckedStepCount(1.0 / signal.sample_rate_Hz, dt, 1, "bench: one sample (sample_rate_Hz)");
  });
  const double steps_per_sample_real = 1.0 / (signal.sample_rate_Hz * dt);
  const long steps_per_sample = std::lround(steps_per_sample_real);
  if (steps_per_sample < 1 || std::abs(steps_per_sample_real - steps_per_sample) > 1e-6) {
    std::ostringstream msg;
    msg << "bench: sample_rate_Hz " << signal.sample_rate_Hz
        << " must divide the model's step rate " << 1.0 / dt << " Hz";
    throw FieldError(msg.str(), "sample_rate_Hz", whole_steps);
  }
  const std::string size_limit = "within the run size limits, or allow_long";
  const long steps = NamingField("duration_s", size_limit, [&] {
    return CheckedStepCount(signal.duration_s, dt, steps_per_sample,
                            "bench: the experiment (duration_s)");
  });
  // Per sample: the time and four values of every link.
  NamingField("duration_s", size_limit, [&] {
    CheckRunSize(static_cast<double>(steps),
                 (1.0 + 4.0 * links) * sizeof(double) * steps / steps_per_sample,
                 signal.allow_long, "bench: the experiment (duration_s)");
  });
  BenchRecord record;
  record.voltage_V.resize(links);
  record.relative_mm.resize(links);
  record.tip_lateral_mm.resize(links);
  record.free_mm.resize(links);
  std::vector<double> volts(links, 0.0);
  for (long step = 0; step < steps; ++step) {
    const bool sample = step % steps_per_sample == 0;
    if (!sample) {
      sim.Step(false);
      continue;
    }
    const double t_s = d->time;
    const double voltage = signal.VoltageAt(t_s);
    for (int link : signal.driven_links) volts[link - 1] = voltage;
    SetVoltages(d, volts.data(), links);
    // MuJoCo computes the sensors within the step from the state at its
    // start, t_s, and the control callback advances the link models to
    // t_s: read after the step, every recorded value describes the sample
    // time itself, whatever the time step.
    sim.Step(true);
    if (t_s >= record_from_s) {
      record.t_s.push_back(t_s);
      for (int q = 0; q < links; ++q) {
        record.voltage_V[q].push_back(LinkVoltage_V(d, q));
        record.relative_mm[q].push_back(sensors.RelativeDeflection_mm(d, q));
        record.tip_lateral_mm[q].push_back(sensors.TipLateral_mm(d, q));
        record.free_mm[q].push_back(LinkFreeDeflection_mm(d, q));
      }
    }
    if (progress) progress(t_s);
  }
  return record;
}

NamedColumns BenchColumns(const BenchRecord& record) {
  NamedColumns columns = {{columns::kTime, record.t_s}};
  for (size_t q = 0; q < record.voltage_V.size(); ++q) {
    const int link = static_cast<int>(q + 1);
    columns.push_back({columns::Voltage(link), record.voltage_V[q]});
    columns.push_back({columns::Relative(link), record.relative_mm[q]});
    columns.push_back({columns::TipLateral(link), record.tip_lateral_mm[q]});
    columns.push_back({columns::Free(link), record.free_mm[q]});
  }
  return columns;
}

std::string BenchCsv(const BenchRecord& record) { return NamedColumnsCsv(BenchColumns(record), 10); }

}  // namespace ipmc

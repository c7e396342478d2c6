#include "sim/cli/run_print.h"

#include <cstdio>
#include <string>
#include <vector>

#include "sim/io/columns.h"

namespace ipmc {

void PrintSwimMetrics(const SwimMetrics& swim) { PrintSwimMetrics(swim, swim.warnings); }

void PrintSwimMetrics(const SwimMetrics& swim, const std::vector<std::string>& warnings) {
  std::printf("%5s %14s %14s %14s %14s\n", "cycle", "com_along_mm", "com_across_mm",
              "head_along_mm", "head_across_mm");
  for (size_t k = 0; k < swim.per_cycle.size(); ++k) {
    const Displacement_mm& c = swim.per_cycle[k];
    std::printf("%5zu %14.6g %14.6g %14.6g %14.6g\n", k + 1, c.com_along, c.com_across,
                c.head_along, c.head_across);
  }
  std::printf("mean speed along the swimming axis: %.6g mm/s\n", swim.mean_speed_along_mm_s);
  std::printf("Reynolds number: %.3g (peak lateral tip speed x width), %.3g (mean speed x length)",
              swim.reynolds_tip, swim.reynolds_swim);
  if (swim.reynolds_oscillatory > 0.0) {
    std::printf(", %.3g (oscillatory, omega w^2 / (4 nu))", swim.reynolds_oscillatory);
  }
  std::printf("\n");
  for (const std::string& warning : warnings) {
    std::fprintf(stderr, "warning: %s\n", warning.c_str());
  }
}

void PrintMetricCycles(const ClosedLoopResult& result) {
  std::printf("link metrics, mean speed and mean powers over %s\n",
              MetricCyclesText(result).c_str());
}

void PrintStartup(const ClosedLoopResult& result) {
  const StartupCycles startup = StartupOf(result);
  if (startup.cycles == 0) return;
  const std::string cycles =
      startup.cycles == 1 ? "cycle 1" : "cycles 1-" + std::to_string(startup.cycles);
  std::printf("start-up (%s, left out of the means): centre of mass %.6g mm along, actuators "
              "%.6g W\n",
              cycles.c_str(), startup.com_along_mm, startup.actuator_power_W);
}

namespace {

// "link 1 P1 W, link 2 P2 W, ..."
std::string LinkPowers(const std::vector<double>& power_W) {
  std::string links;
  for (size_t q = 0; q < power_W.size(); ++q) {
    char part[64];
    std::snprintf(part, sizeof(part), "%slink %zu %.4g W", q == 0 ? "" : ", ", q + 1, power_W[q]);
    links += part;
  }
  return links;
}

}  // namespace

void PrintEnergy(const EnergyMetrics& energy) {
  std::printf("%5s %16s %14s %21s %16s %16s %20s %21s\n", "cycle", columns::kActuatorPower,
              columns::kFluidPower, columns::kHingeDampingPower, columns::kSteppingPower,
              columns::kElasticEnergy,
              columns::kLighthillEfficiency, columns::kCostOfTransport);
  for (size_t k = 0; k < energy.per_cycle.size(); ++k) {
    const EnergyCycle& c = energy.per_cycle[k];
    std::printf("%5zu %16.6g %14.6g %21.6g %16.6g %16.6g %20.6g %21.6g\n", k + 1,
                c.actuator_power_W_total, c.fluid_power_W, c.hinge_damping_power_W,
                c.stepping_power_W,
                c.elastic_energy_J, c.lighthill_efficiency, c.cost_of_transport_J_m);
  }
  const std::string links = LinkPowers(energy.actuator_power_W);
  std::printf("mean power over cycles %d-%zu: actuators %.6g W (%s), fluid %.6g W, hinge "
              "damping %.6g W, time stepping %.6g W\n",
              energy.from_cycle, energy.per_cycle.size(), energy.actuator_power_W_total,
              links.c_str(), energy.fluid_power_W, energy.hinge_damping_power_W,
              energy.stepping_power_W);
  std::printf("Lighthill efficiency %.6g, cost of transport %.6g J/m, hinges' elastic energy "
              "%.6g J\n",
              energy.lighthill_efficiency, energy.cost_of_transport_J_m, energy.elastic_energy_J);
  if (!energy.electrical) return;
  std::printf("%5s %18s %28s\n", "cycle", columns::kElectricalPower,
              columns::kElectromechanicalEfficiency);
  for (size_t k = 0; k < energy.per_cycle.size(); ++k) {
    const EnergyCycle& c = energy.per_cycle[k];
    std::printf("%5zu %18.6g %28.6g\n", k + 1, c.electrical_power_W_total,
                c.electromechanical_efficiency);
  }
  const std::string electrical_links = LinkPowers(energy.electrical_power_W);
  std::printf("mean electrical power over cycles %d-%zu: %.6g W (%s), electromechanical "
              "efficiency %.6g\n",
              energy.from_cycle, energy.per_cycle.size(), energy.electrical_power_W_total,
              electrical_links.c_str(), energy.electromechanical_efficiency);
}

void PrintWritten(const std::string& dir, const RunFileFormats& formats) {
  std::string format_files;
  if (formats.mat) format_files += std::string(", ") + kRunMatFile;
  if (formats.hdf5) format_files += std::string(", ") + kRunHdf5File;
  std::printf("wrote %s/timeseries.csv, states.csv, model.xml%s and summary.json\n", dir.c_str(),
              format_files.c_str());
}

}  // namespace ipmc

#include "sim/cli/table5_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "controllers/fractional_integrator.h"
#include "controllers/pid.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/data_paths.h"
#include "sim/core/fan_out.h"
#include "sim/core/simulation.h"
#include "sim/core/waveform.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc {
namespace {

std::string StartDescription(const Table5Reading& reading) {
  if (reading.start_ramp_cycles == 0.0) {
    return "references start at their t = 0 values (a step)";
  }
  return "references faded in over " + FormatDouble(reading.start_ramp_cycles, 6) + " cycles";
}

std::string LoopDescription(Table5Loop loop) {
  return loop == Table5Loop::kMultibody
             ? "multibody (the MuJoCo run of `run`)"
             : "transfer functions (each link's plant alone, no body)";
}

void PrintTable(const Table5Values& here, const Table5Values& paper,
                const Table5Reading& reading, const ScenarioConfig& setting) {
  const double period_s = 1.0 / std::abs(setting.waveform.frequency_Hz);
  std::printf("Table 5 (paper, section 5.3): tracking of each link's relative tip deflection\n");
  const std::string scenario = std::filesystem::path(setting.source).filename().string();
  std::printf("  setting scenarios/%s; linear loop (no clamp); plants %s; loop %s\n",
              scenario.c_str(), PlantAssignmentName(reading.plants),
              LoopDescription(reading.loop).c_str());
  std::printf("  horizon %d cycles (%g s); %s\n", reading.cycles, reading.cycles * period_s,
              StartDescription(reading).c_str());
  std::printf("  C_I: eq. 15 as printed; PID: eq. 12 (%g + %g/s + %g s); sampled at %g Hz\n",
              setting.controller.pid.kp, setting.controller.pid.ki, setting.controller.pid.kd,
              setting.controller.sample_rate_Hz);
  std::printf("%-5s %4s %12s %10s %9s %12s %10s %9s\n", "index", "link", "C_I_here", "C_I_paper",
              "C_I_err_%", "PID_here", "PID_paper", "PID_err_%");
  for (const Table5Row& row : Table5Rows(here, paper)) {
    std::printf("%-5s %4d %12.6g %10.6g %+9.1f %12.6g %10.6g %+9.1f\n", row.index, row.link,
                row.fractional_here, row.fractional_paper,
                100.0 * RelativeError(row.fractional_here, row.fractional_paper), row.pid_here,
                row.pid_paper, 100.0 * RelativeError(row.pid_here, row.pid_paper));
  }
  std::printf("IAE = int |e| dt [mm s], ITAE = int t |e| dt [mm s^2], e = r - y [mm]; "
              "err = (here - paper) / paper\n");
}

}  // namespace

void AddTable5Command(CLI::App& app, Table5Args& args) {
  AddTableCommand(app, Table5Options(), args);
}

int RunTable5CommandLine(const Table5Args& args) {
  if (!args.Chosen()) return -1;
  const Table5Outcome outcome = TranslatingFieldErrors(
      Table5Options(), [&] { return RunTable5Command(args.spec, args.Given()); });
  PrintTable(outcome.here, outcome.paper, outcome.reading, outcome.setting);
  return 0;
}

}  // namespace ipmc

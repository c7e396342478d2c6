// ipmc-swim command-line program.
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "sim/cli/bench_command.h"
#include "sim/cli/bode_command.h"
#include "sim/cli/design_command.h"
#include "sim/cli/export_command.h"
#include "sim/cli/gait_command.h"
#include "sim/cli/generate_command.h"
#include "sim/cli/resistance_command.h"
#include "sim/cli/optimize_command.h"
#include "sim/cli/options_command.h"
#include "sim/cli/pipeline_command.h"
#include "sim/cli/run_command.h"
#include "sim/cli/step_command.h"
#include "sim/cli/command.h"
#include "sim/cli/interrupt.h"
#include "sim/base/error.h"
#include "sim/batch/sweep.h"
#include "sim/cli/run_watch.h"
#include "sim/core/gait.h"
#include "sim/io/files.h"
#include "sim/io/toml.h"
#include "sim/runs/bench_run.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/cli/identify_command.h"
#include "sim/cli/plot_command.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_overrides.h"
#include "sim/cli/keys_command.h"
#include "sim/cli/sweep_command.h"
#include "sim/cli/table5_command.h"
#include "sim/cli/converge_command.h"
#include "sim/cli/render_command.h"
#include "sim/cli/view_command.h"
#include "sim/core/data_paths.h"

namespace {

// MuJoCo's warnings, held back so that a failing run prints one line.
std::vector<std::string>& MujocoWarnings() {
  static std::vector<std::string> warnings;
  return warnings;
}
void CollectMujocoWarning(const char* message) { MujocoWarnings().emplace_back(message); }
void PrintMujocoWarnings() {
  for (const std::string& warning : MujocoWarnings()) {
    std::cerr << "ipmc-swim: MuJoCo warning: " << warning << "\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ipmc-swim: an IPMC flagellum swimming in Stokes flow (MuJoCo 2.2)"};
  app.set_version_flag("--version", std::string("ipmc-swim ") + ipmc::ProgramVersion());
  app.require_subcommand(1);
  // Every command, in the order --help lists them.
  const ipmc::CommandRegistration commands[] = {
      ipmc::Registration(ipmc::AddGenerateCommand, ipmc::RunGenerateCommandLine),
      ipmc::Registration(ipmc::AddResistanceCommand, ipmc::RunResistanceCommandLine),
      ipmc::Registration(ipmc::AddGaitCommand, ipmc::RunGaitCommandLine),
      ipmc::Registration(ipmc::AddBenchCommand, ipmc::RunBenchCommandLine),
      ipmc::Registration(ipmc::AddRunCommand, ipmc::RunRunCommandLine),
      ipmc::Registration(ipmc::AddBodeCommand, ipmc::RunBodeCommandLine),
      ipmc::Registration(ipmc::AddStepCommand, ipmc::RunStepCommandLine),
      ipmc::Registration(ipmc::AddRenderCommand, ipmc::RunRenderCommandLine),
      ipmc::Registration(ipmc::AddViewCommand, ipmc::RunViewCommandLine),
      ipmc::Registration(ipmc::AddPlotCommand, ipmc::RunPlotCommandLine),
      ipmc::Registration(ipmc::AddIdentifyCommand, ipmc::RunIdentifyCommandLine),
      ipmc::Registration(ipmc::AddDesignCommand, ipmc::RunDesignCommandLine),
      ipmc::Registration(ipmc::AddExportCommand, ipmc::RunExportCommandLine),
      ipmc::Registration(ipmc::AddPipelineCommand, ipmc::RunPipelineCommandLine),
      ipmc::Registration(ipmc::AddSweepCommands, ipmc::RunSweepCommandLine),  // sweep and merge
      ipmc::Registration(ipmc::AddOptimizeCommand, ipmc::RunOptimizeCommandLine),
      ipmc::Registration(ipmc::AddTable5Command, ipmc::RunTable5CommandLine),
      ipmc::Registration(ipmc::AddConvergeCommand, ipmc::RunConvergeCommandLine),
      ipmc::Registration(ipmc::AddKeysCommand, ipmc::RunKeysCommandLine),
      ipmc::Registration(ipmc::AddOptionsCommand, ipmc::RunOptionsCommandLine),
  };
  std::vector<ipmc::CommandRunner> runners;
  for (const ipmc::CommandRegistration& add : commands) runners.push_back(add(app));
  std::string names;
  bool known = false;
  for (const CLI::App* command : app.get_subcommands({})) {
    names += (names.empty() ? "" : ", ") + command->get_name();
    known = known || (argc > 1 && command->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !known) {
    std::cerr << "ipmc-swim: error: unknown command '" << argv[1] << "' (commands: " << commands
              << ")\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ipmc-swim: error: " << e.what() << " (see --help)\n";
    return 2;
  }
  mju_user_warning = CollectMujocoWarning;
  // A write beyond the file size limit (ulimit -f) fails with EFBIG, as on
  // a full disk, instead of killing the process with its temporaries left.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    int status = 0;
    for (const ipmc::CommandRunner& run : runners) {
      if (int s = run(); s >= 0) status = s;
    }
    PrintMujocoWarnings();
    return status;
  } catch (const ipmc::Interrupted& stop) {
    std::cerr << "ipmc-swim: interrupted by " << stop.SignalName() << ": " << stop.what() << "\n";
    return stop.ExitCode();
  } catch (const std::exception& e) {
    std::cerr << "ipmc-swim: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

#include "sim/cli/options_command.h"

#include <cstdio>
#include <vector>

#include "sim/cli/command.h"
#include "sim/batch/sweep_command.h"
#include "sim/core/generate_command.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/loop_analysis.h"
#include "sim/identify/pipeline_run.h"
#include "sim/runs/bench_command.h"
#include "sim/runs/gait_command.h"
#include "sim/runs/run_command.h"
#include "sim/runs/table5_run.h"

namespace ipmc {
namespace {

constexpr char kCommand[] = "options";

}  // namespace

void AddOptionsCommand(CLI::App& app, OptionsArgs& args) {
  CLI::App* cmd = AddCommand(app, kCommand,
                             "Print every command's options: name, flag, type, unit, range, "
                             "default, meaning");
  cmd->add_option("--format", args.format, "text | markdown (docs/OPTIONS.md)")
      ->check(CLI::IsMember({"text", "markdown"}));
}

int RunOptionsCommand(const CLI::App& app, const OptionsArgs& args) {
  if (!app.got_subcommand(kCommand)) return -1;
  const std::vector<OptionTableInfo> tables = {
      InfoOf(RunOptions()),      InfoOf(SweepOptionTable()), InfoOf(MergeOptionTable()),
      InfoOf(GenerateOptions()), InfoOf(GaitOptions()),     InfoOf(BenchOptions()),
      InfoOf(BodeOptions()),     InfoOf(StepOptions()),     InfoOf(IdentifyOptions()),
      InfoOf(DesignOptions()),   InfoOf(PipelineOptions()), InfoOf(Table5Options())};
  const std::string reference = OptionReference(tables, args.format);
  std::fwrite(reference.data(), 1, reference.size(), stdout);
  return 0;
}

}  // namespace ipmc

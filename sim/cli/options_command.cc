#include "sim/cli/options_command.h"

#include <cstdio>
#include <vector>

#include "sim/batch/sweep_command.h"
#include "sim/core/generate_command.h"
#include "sim/core/keys_command.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/loop_analysis.h"
#include "sim/identify/pipeline_run.h"
#include "sim/runs/bench_command.h"
#include "sim/runs/gait_command.h"
#include "sim/runs/run_command.h"
#include "sim/runs/table5_run.h"

namespace ipmc {

void AddOptionsCommand(CLI::App& app, OptionsArgs& args) {
  AddTableCommand(app, OptionsOptions(), args);
}

int RunOptionsCommand(const OptionsArgs& args) {
  if (!args.Chosen()) return -1;
  const std::vector<OptionTableInfo> tables = {
      InfoOf(RunOptions()),      InfoOf(SweepOptionTable()), InfoOf(MergeOptionTable()),
      InfoOf(GenerateOptions()), InfoOf(GaitOptions()),      InfoOf(BenchOptions()),
      InfoOf(BodeOptions()),     InfoOf(StepOptions()),      InfoOf(IdentifyOptions()),
      InfoOf(DesignOptions()),   InfoOf(PipelineOptions()),  InfoOf(Table5Options()),
      InfoOf(KeysOptions()),     InfoOf(OptionsOptions())};
  const std::string reference = OptionReference(tables, args.spec.format);
  std::fwrite(reference.data(), 1, reference.size(), stdout);
  return 0;
}

}  // namespace ipmc

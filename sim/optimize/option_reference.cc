#include "sim/optimize/option_reference.h"

#include "sim/batch/sweep_command.h"
#include "sim/core/generate_command.h"
#include "sim/core/keys_command.h"
#include "sim/core/resistance_command.h"
#include "sim/identify/controller_export.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/loop_analysis.h"
#include "sim/identify/pipeline_run.h"
#include "sim/optimize/optimize_run.h"
#include "sim/runs/bench_command.h"
#include "sim/runs/converge_study.h"
#include "sim/runs/gait_command.h"
#include "sim/runs/run_command.h"
#include "sim/runs/table5_run.h"

namespace ipmc {

std::vector<OptionTableInfo> EveryOptionTable() {
  return {InfoOf(RunOptions()),      InfoOf(SweepOptionTable()), InfoOf(MergeOptionTable()),
          InfoOf(OptimizeOptionTable()),
          InfoOf(GenerateOptions()), InfoOf(ResistanceOptions()), InfoOf(GaitOptions()),
          InfoOf(BenchOptions()),
          InfoOf(BodeOptions()),     InfoOf(StepOptions()),      InfoOf(IdentifyOptions()),
          InfoOf(DesignOptions()),   InfoOf(ExportOptions()),    InfoOf(PipelineOptions()),
          InfoOf(Table5Options()),   InfoOf(ConvergeOptions()),  InfoOf(KeysOptions()),
          InfoOf(OptionsOptions())};
}

std::string OptionsReference(const ReferenceCommand& command) {
  CheckReferenceFormat("options", command);
  return OptionReference(EveryOptionTable(), command.format);
}

}  // namespace ipmc

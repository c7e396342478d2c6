#include "sim/cli/pipeline_command.h"

#include <cstdio>
#include <string>

namespace ipmc {

void AddPipelineCommand(CLI::App& app, PipelineArgs& args) {
  AddTableCommand(app, PipelineOptions(), args);
}

int RunPipelineCommandLine(const PipelineArgs& args) {
  if (!args.Chosen()) return -1;
  const std::string report =
      TranslatingFieldErrors(PipelineOptions(), [&] { return RunPipelineCommand(args.spec); });
  std::printf("%s", report.c_str());
  return 0;
}

}  // namespace ipmc

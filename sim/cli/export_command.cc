#include "sim/cli/export_command.h"

#include <cstdio>
#include <filesystem>

#include "sim/base/numbers.h"

namespace ipmc {

void AddExportCommand(CLI::App& app, ExportArgs& args) {
  AddTableCommand(app, ExportOptions(), args);
}

int RunExportCommandLine(const ExportArgs& args) {
  if (!args.Chosen()) return -1;
  const ExportedController exported =
      TranslatingFieldErrors(ExportOptions(), [&] { return RunExportCommand(args.spec); });
  const nlohmann::ordered_json& c = exported.coefficients;
  std::printf("%s: %d link(s), %s at %g Hz%s\n", c["scenario"].get<std::string>().c_str(),
              c["links"].get<int>(), c["controller"].get<std::string>().c_str(),
              c["sample_rate_Hz"].get<double>(),
              c["clamp"].get<bool>()
                  ? (", clamp +-" + FormatShortest(c["v_max_V"].get<double>()) + " V").c_str()
                  : "");
  for (const char* file : kExportFiles) {
    std::printf("wrote %s\n", (std::filesystem::path(args.spec.out) / file).string().c_str());
  }
  return 0;
}

}  // namespace ipmc

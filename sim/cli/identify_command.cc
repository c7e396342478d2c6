#include "sim/cli/identify_command.h"

#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include "controllers/fractional_integrator.h"
#include "sim/linear/frequency_response.h"
#include "controllers/reference_model.h"
#include "ipmc_swim/fields.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/cli/command.h"
#include "sim/core/data_paths.h"
#include "sim/core/fan_out.h"
#include "sim/core/simulation.h"
#include "sim/identify/bench_identification.h"
#include "sim/identify/controller_design.h"
#include "sim/identify/identify_run.h"
#include "sim/identify/levy.h"
#include "sim/identify/loop_analysis.h"
#include "sim/identify/report_text.h"
#include "sim/identify/welch.h"
#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/files.h"
#include "sim/runs/bench_run.h"

namespace ipmc {
namespace {

void PrintIndicesTable(const LinkIdentification& id) {
  std::printf("Table 3 indices on P = s^-0.5 G (complex response, band points):\n");
  std::printf("%-5s %12s %12s %12s %12s %9s\n", "model", "J", "MSE", "MAD", "MD", "R^2");
  const std::pair<const char*, const LinkModelFit*> rows[] = {{"P1", &id.g1}, {"P2", &id.g2}};
  for (const auto& [name, fit] : rows) {
    const FitIndices& i = fit->indices;
    std::printf("%-5s %12.5g %12.5g %12.5g %12.5g %9.5f\n", name, i.levy_cost, i.mse, i.mad,
                i.max_deviation, i.r_squared);
  }
}

int RunIdentify(const IdentifyCommand& args) {
  const RecordIdentification result =
      TranslatingFieldErrors(IdentifyOptions(), [&] { return RunIdentifyCommandOnFile(args); });
  const LevyOptions& levy = result.levy;
  const FrequencyResponseEstimate& estimate = result.estimate;
  const LinkIdentification& id = result.id;

  std::printf("%s: input %s, output %s, %zu samples at %g Hz (%.6g s)\n", args.data_path.c_str(),
              args.input_column.c_str(), args.output_column.c_str(), result.samples,
              args.sample_rate_Hz, result.samples / args.sample_rate_Hz);
  std::printf("%s\n", WelchDescription(estimate).c_str());
  std::printf("Levy over [%g, %g] rad/s: %d points from %.4g to %.4g rad/s, mean coherence %.4f; "
              "s^-0.5 removed\n",
              levy.w_low_rad_s, levy.w_high_rad_s, id.g1.indices.points,
              id.g1.indices.w_first_rad_s, id.g1.indices.w_last_rad_s,
              MeanCoherenceInBand(estimate, id.g1.indices));
  std::printf("P1 = s^-0.5 G1, %s\n", DescribeG1(id.g1).c_str());
  std::printf("P2 = s^-0.5 G2, %s\n", DescribeG2(id.g2, id).c_str());
  PrintIndicesTable(id);
  const FitCheck& check = result.check;
  std::printf("fit check: %d of %d band bins drove the fits (%d below coherence %g, %d below "
              "excitation -%g dB), mean coherence %.4f\n",
              check.used_bins, check.band_bins, check.low_coherence, args.min_coherence,
              check.low_excitation, args.min_excitation_dB, check.mean_coherence);
  for (const std::string& warning : check.warnings) {
    std::fprintf(stderr, "warning: %s: %s\n", args.data_path.c_str(), warning.c_str());
  }
  for (std::size_t i = 0; i < result.other_links.size(); ++i) {
    const RecordIdentification& link = result.other_links[i];
    const std::string& path = args.link_records[i];
    std::printf("link %zu (%s): P1 = s^-0.5 G1, %s; R^2 = %.5f, %d of %d band bins\n", i + 2,
                path.c_str(), DescribeG1(link.id.g1).c_str(), link.id.g1.indices.r_squared,
                link.check.used_bins, link.check.band_bins);
    for (const std::string& warning : link.check.warnings) {
      std::fprintf(stderr, "warning: %s: %s\n", path.c_str(), warning.c_str());
    }
  }

  if (!args.out.empty()) {
    const std::filesystem::path dir(args.out);
    std::printf("wrote %s, %s and %s\n", (dir / "response.csv").string().c_str(),
                (dir / "identification.json").string().c_str(),
                (dir / "plant.toml").string().c_str());
  }
  return 0;
}

}  // namespace

void AddIdentifyCommand(CLI::App& app, IdentifyArgs& args) {
  AddTableCommand(app, IdentifyOptions(), args);
}

int RunIdentifyCommandLine(const IdentifyArgs& args) {
  if (!args.Chosen()) return -1;
  return RunIdentify(args.spec);
}

}  // namespace ipmc

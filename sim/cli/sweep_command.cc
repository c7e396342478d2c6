#include "sim/cli/sweep_command.h"

#include "sim/cli/command.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/batch/sweep.h"
#include "sim/io/columns.h"
#include "sim/io/numbers.h"

namespace ipmc {
namespace {

constexpr char kSweepCommand[] = "sweep";
constexpr char kMergeCommand[] = "merge";

constexpr int kBarWidth = 30;
// Result columns shown on stdout (all are in the files).
constexpr const char* kShownResults[] = {columns::kMeanSpeedAlong, columns::kLastCycleComAlong};

// "m:ss", or "h:mm:ss" from an hour on.
std::string Clock(double seconds) {
  const long total = std::max(0L, static_cast<long>(seconds + 0.5));
  char buffer[32];
  if (total >= 3600) {
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld:%02ld", total / 3600, total / 60 % 60,
                  total % 60);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%ld:%02ld", total / 60, total % 60);
  }
  return buffer;
}

// Progress on stderr: a bar redrawn in place on a terminal, else one line
// per point (for logs and pipes).
class ProgressReport {
 public:
  explicit ProgressReport(bool terminal) : terminal_(terminal) {}

  // Draws the empty bar, so that a long first run does not look like a hang.
  void Start(int total) {
    if (terminal_ && total > 0) {
      const std::string line = "[" + std::string(kBarWidth, '-') + "] 0/" +
                               std::to_string(total) + " runs";
      last_width_ = line.size() + 1;
      std::fprintf(stderr, "\r%s", line.c_str());
      std::fflush(stderr);
    }
  }

  void operator()(const SweepProgress& p) {
    if (!terminal_) {
      if (p.ok) {
        std::fprintf(stderr, "run %d/%d done (point %d)\n", p.done, p.total, p.point);
      } else {
        std::fprintf(stderr, "run %d/%d failed (point %d): %s\n", p.done, p.total, p.point,
                     p.error.c_str());
      }
      return;
    }
    const int filled = p.total > 0 ? kBarWidth * p.done / p.total : kBarWidth;
    const double remaining_s = p.elapsed_s / p.done * (p.total - p.done);
    std::string line = "\r[" + std::string(filled, '#') + std::string(kBarWidth - filled, '-') +
                       "] " + std::to_string(p.done) + "/" + std::to_string(p.total) +
                       " runs, " + Clock(p.elapsed_s) + " elapsed, ETA " + Clock(remaining_s);
    if (!p.ok) ++failed_;
    if (failed_ > 0) line += ", " + std::to_string(failed_) + " failed";
    const size_t width = line.size();
    if (width < last_width_) line += std::string(last_width_ - width, ' ');
    last_width_ = width;
    std::fputs(line.c_str(), stderr);
    std::fflush(stderr);
  }

  // Ends the bar's line.
  void Finish() const {
    if (terminal_ && last_width_ > 0) std::fputc('\n', stderr);
  }

 private:
  bool terminal_;
  size_t last_width_ = 0;
  int failed_ = 0;
};

// A number cell at 6 significant digits; other cells as they are.
// (The table writes numbers without a '+'; a cell with one is text.)
std::string Readable(const std::string& cell) {
  const std::optional<double> value = cell.empty() || cell[0] == '+' ? std::nullopt
                                                                     : ParseDouble(cell);
  return value ? FormatDouble(*value, 6) : cell;
}

// The swept values, status and speed of each row, aligned.
void PrintSummary(const SweepTable& table) {
  const std::vector<std::string>& names = table.columns;
  const size_t status =
      std::find(names.begin(), names.end(), columns::kStatus) - names.begin();
  std::vector<size_t> shown;
  for (size_t c = 0; c <= status && c < names.size(); ++c) shown.push_back(c);
  for (const char* name : kShownResults) {
    const auto it = std::find(names.begin(), names.end(), name);
    if (it != names.end()) shown.push_back(it - names.begin());
  }
  std::vector<size_t> width;
  for (size_t c : shown) {
    size_t w = names[c].size();
    for (const auto& row : table.rows) w = std::max(w, Readable(row[c]).size());
    width.push_back(w);
  }
  auto print_row = [&](auto cell_of) {
    std::string line;
    for (size_t k = 0; k < shown.size(); ++k) {
      std::string cell = cell_of(shown[k]);
      cell.resize(width[k], ' ');
      line += (k > 0 ? "  " : "") + cell;
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    std::printf("%s\n", line.c_str());
  };
  print_row([&](size_t c) { return names[c]; });
  for (const auto& row : table.rows) print_row([&](size_t c) { return Readable(row[c]); });
}

int RunSweepFile(const SweepArgs& args) {
  const SweepShard shard = ParseSweepShard(args.shard);
  if (args.jobs < 1) {
    throw std::invalid_argument("sweep: --jobs must be >= 1 (got " + std::to_string(args.jobs) +
                                ")");
  }
  const SweepPlan plan = LoadSweep(args.sweep_path);
  ProgressReport progress(isatty(STDERR_FILENO) == 1);
  SweepOptions options;
  options.jobs = args.jobs;
  options.shard = shard;
  options.on_point_done = [&](const SweepProgress& p) { progress(p); };
  progress.Start(static_cast<int>(std::count_if(
      plan.points.begin(), plan.points.end(),
      [&](const SweepPoint& point) { return point.index % shard.count == shard.index - 1; })));
  const SweepTable table = RunSweep(plan, options);
  progress.Finish();
  WriteSweepTable(args.out_prefix, table);

  PrintSummary(table);
  const size_t status = plan.keys.size() + 1;
  int failed = 0;
  for (const auto& row : table.rows) {
    if (row[status] != columns::kStatusOk) {
      ++failed;
      std::fprintf(stderr, "point %s failed: %s\n", row[0].c_str(), row[status + 1].c_str());
    }
  }
  std::string scope = std::to_string(table.rows.size()) + " points";
  if (shard.count > 1) {
    scope += " (shard " + args.shard + " of " + std::to_string(plan.points.size()) + ")";
  }
  std::printf("%s: %zu ok, %d failed; wrote %s.csv and %s.json\n", scope.c_str(),
              table.rows.size() - failed, failed, args.out_prefix.c_str(),
              args.out_prefix.c_str());
  return 0;
}

int RunMergeTables(const SweepArgs& args) {
  std::vector<SweepTable> tables;
  for (const std::string& path : args.merge_tables) tables.push_back(LoadSweepTableCsv(path));
  const SweepTable merged = MergeSweepTables(tables, args.merge_tables);
  WriteSweepTable(args.merge_out_prefix, merged);
  std::printf("%zu points from %zu tables; wrote %s.csv and %s.json\n", merged.rows.size(),
              tables.size(), args.merge_out_prefix.c_str(), args.merge_out_prefix.c_str());
  return 0;
}

}  // namespace

void AddSweepCommands(CLI::App& app, SweepArgs& args) {
  args.jobs = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  CLI::App* sweep = AddCommand(
      app, kSweepCommand, "Run a scenario over a grid or list of overrides (a sweep file, TOML)");
  sweep->add_option("sweep", args.sweep_path, "Sweep file")->required();
  sweep->add_option("--jobs", args.jobs, "Points run in parallel (default: hardware threads)");
  sweep->add_option("--shard", args.shard,
                    "Run part i of n: the points with index % n == i - 1");
  sweep->add_option("--out", args.out_prefix, "Writes PREFIX.csv and PREFIX.json")->required();

  CLI::App* merge =
      AddCommand(app, kMergeCommand, "Join the tables (CSV) of a sweep's shards into one");
  merge->add_option("tables", args.merge_tables, "Shard tables (PREFIX.csv of each sweep --shard)")
      ->required()
      ->default_str("");
  merge->add_option("--out", args.merge_out_prefix, "Writes PREFIX.csv and PREFIX.json")
      ->required();
}

int RunSweepCommand(const CLI::App& app, const SweepArgs& args) {
  if (app.got_subcommand(kSweepCommand)) return RunSweepFile(args);
  if (app.got_subcommand(kMergeCommand)) return RunMergeTables(args);
  return -1;
}

}  // namespace ipmc

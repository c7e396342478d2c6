#include "sim/cli/sweep_command.h"


#include <algorithm>
#include <charconv>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "sim/batch/sweep.h"
#include "sim/io/progress_bar.h"

namespace ipmc {
namespace {

constexpr char kSweepCommand[] = "sweep";
constexpr char kMergeCommand[] = "merge";

// Result columns shown on stdout (all are in the files).
constexpr const char* kShownResults[] = {"mean_speed_along_mm_s", "last_cycle_com_along_mm"};

// Progress on stderr: a bar redrawn in place on a terminal, else one line
// per point (for logs and pipes).
class ProgressReport {
 public:
  explicit ProgressReport(bool terminal) : bar_("sweep", "runs", terminal) {}

  void Start(int total) { bar_.Start(total); }

  void operator()(const SweepProgress& p) {
    if (!bar_.terminal()) {
      if (p.ok) {
        std::fprintf(stderr, "run %d/%d done (point %d)\n", p.done, p.total, p.point);
      } else {
        std::fprintf(stderr, "run %d/%d failed (point %d): %s\n", p.done, p.total, p.point,
                     p.error.c_str());
      }
      return;
    }
    if (!p.ok) ++failed_;
    bar_.Update(p.done, failed_ > 0 ? std::to_string(failed_) + " failed" : "");
  }

  void Finish() { bar_.Finish(); }

 private:
  ProgressBar bar_;
  int failed_ = 0;
};

// A number cell at 6 significant digits; other cells as they are.
std::string Readable(const std::string& cell) {
  double value = 0.0;
  const char* end = cell.data() + cell.size();
  const std::from_chars_result result = std::from_chars(cell.data(), end, value);
  if (cell.empty() || result.ec != std::errc() || result.ptr != end) return cell;
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

// The swept values, status and speed of each row, aligned.
void PrintSummary(const SweepTable& table) {
  const std::vector<std::string>& columns = table.columns;
  const size_t status = std::find(columns.begin(), columns.end(), "status") - columns.begin();
  std::vector<size_t> shown;
  for (size_t c = 0; c <= status && c < columns.size(); ++c) shown.push_back(c);
  for (const char* name : kShownResults) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    if (it != columns.end()) shown.push_back(it - columns.begin());
  }
  std::vector<size_t> width;
  for (size_t c : shown) {
    size_t w = columns[c].size();
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
  print_row([&](size_t c) { return columns[c]; });
  for (const auto& row : table.rows) print_row([&](size_t c) { return Readable(row[c]); });
}

int RunSweepFile(const SweepArgs& args) {
  const SweepShard shard = ParseSweepShard(args.shard);
  if (args.jobs < 1) {
    throw std::invalid_argument("sweep: --jobs must be >= 1 (got " + std::to_string(args.jobs) +
                                ")");
  }
  const SweepPlan plan = LoadSweep(args.sweep_path);
  ProgressReport progress(StderrIsTerminal());
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
    if (row[status] != "ok") {
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
  CLI::App* sweep = app.add_subcommand(
      kSweepCommand, "Run a scenario over a grid or list of overrides (a sweep file, TOML)");
  sweep->add_option("sweep", args.sweep_path, "Sweep file")->required();
  sweep->add_option("--jobs", args.jobs, "Points run in parallel (default: hardware threads)")
      ->capture_default_str();
  sweep->add_option("--shard", args.shard,
                    "Run part i of n: the points with index % n == i - 1")
      ->capture_default_str();
  sweep->add_option("--out", args.out_prefix, "Writes PREFIX.csv and PREFIX.json")->required();

  CLI::App* merge =
      app.add_subcommand(kMergeCommand, "Join the tables (CSV) of a sweep's shards into one");
  merge->add_option("tables", args.merge_tables, "Shard tables (PREFIX.csv of each sweep --shard)")
      ->required();
  merge->add_option("--out", args.merge_out_prefix, "Writes PREFIX.csv and PREFIX.json")
      ->required();
}

int RunSweepCommand(const CLI::App& app, const SweepArgs& args) {
  if (app.got_subcommand(kSweepCommand)) return RunSweepFile(args);
  if (app.got_subcommand(kMergeCommand)) return RunMergeTables(args);
  return -1;
}

}  // namespace ipmc

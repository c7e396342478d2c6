// `run` as both front ends run it (sim/runs/closed_loop_run.h): the option
// table, the plan made before the run (the scenario with its overrides,
// the inputs summary.json records, the output folder and file formats, all
// checked before anything is simulated) and the files written after it.
//
//   ipmc-swim run SCENARIO [--set KEY=VALUE ...] [--cycles N] [--out DIR]
//       [--format mat,h5] [--video FILE.mp4 ...] [--allow-long]
//   ipmc_swim.run(scenario, out=DIR, formats=[...], allow_long=..., **overrides)
//
// The command line's --set and --cycles are Python's keyword overrides;
// the film (--video and its options, renders/swim_film.h) is the command
// line's alone.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/core/scenario.h"
#include "sim/io/files.h"
#include "sim/io/option_table.h"
#include "sim/runs/closed_loop_run.h"
#include "sim/runs/output.h"

namespace ipmc {

struct RunCommand {
  std::string scenario;            // a scenario file (TOML) or a run's summary.json
  std::vector<std::string> set;    // KEY=VALUE scenario settings, in order (command line)
  int cycles = 0;                  // = set cycles=N, if given (command line)
  std::string out;                 // "": the scenario's output.dir (none for a re-run)
  std::vector<std::string> formats;  // besides CSV and JSON: mat, h5
  std::string video;               // the film's MP4 (command line)
  bool allow_long = false;
};

const OptionTable<RunCommand>& RunOptions();

// A run as planned before it starts: what to simulate, what summary.json
// records of its inputs, and where its files go ("" for none). While it
// lives, the output folder is locked (one run per folder).
struct RunPlan {
  ScenarioConfig scenario;
  nlohmann::json inputs;
  std::string dir;
  RunFileFormats formats;
  std::string video;
  std::shared_ptr<DirectoryLock> lock;
};

// The plan of a command line: the scenario file with the settings `set`
// and `cycles` (if given) applied, or a run's summary.json run again
// (which takes neither, and writes only to `out`). Checks every output
// (never over the scenario, formats mat or h5 only with a folder, the
// video's folder writable) and throws FieldError naming the field.
RunPlan PlanRunCommand(const RunCommand& command, const OptionGiven& given);

// The plan of a scenario already read (Python's dict or file with keyword
// overrides), its `inputs` as summary.json records them and the files it
// came from (never overwritten); command.scenario, set and cycles are not
// used.
RunPlan PlanRunCommand(const RunCommand& command, ScenarioConfig scenario, nlohmann::json inputs,
                       const std::vector<std::string>& input_files);

// Writes the run's files into plan.dir (nothing if it is ""): timeseries.csv,
// states.csv, summary.json and the planned formats.
void WriteRunOutputs(const RunPlan& plan, const ClosedLoopResult& result);

}  // namespace ipmc

// The paper's Table 5 (section 5.3): the tracking indices of every link
// under both controllers, reproduced and set beside the paper's values
// (the `table5` command; sim/cli/table5_command.h prints it).
//
// Both controllers run in the paper's linear loop (no clamp) on
// scenarios/paper.toml's setting (model, time step, waveform, sample rate,
// PID gains): C_I through eq. 15 as printed (controllers/paper_eq15.h;
// section 5.3: "the results of the non-integer order controller
// correspond to its approximation") and the PID of eq. 12. Per link, with
// e = r - y the error of the link's relative tip deflection [mm] over the
// horizon H of `cycles` wave periods (rectangle rule at the controller's
// sample rate, as `run` computes them, TrackingIndices):
//   IAE = int_0^H |e| dt [mm s],  ITAE = int_0^H t |e| dt [mm s^2],
// printed beside the paper's value with the relative error
// (here - paper) / paper.
//
// Readings the paper leaves open, as options (Table5Options()):
//  - plants: uniform (every link eq. 7's plant, section 5.3's "same
//    dynamics"; default) or table2 (Table 2's row per link);
//  - cycles: the horizon in wave periods (default: the scenario's, 3);
//  - start_ramp_cycles: the references' fade-in (default: the scenario's
//    waveform.start_ramp_cycles, 0.25); 0 starts the references at their
//    t = 0 values, a step;
//  - loop: multibody (the MuJoCo run of `run`; default) or
//    transfer-function (each link's plant P_q(s) of the model, alone in
//    its loop: no body, drag or coupling between the links; the output is
//    the plant's free deflection, advanced exactly over each sample by
//    zero-order hold, HeldPlant).
// With jobs 2 (default) the two controllers run on two threads; each run
// owns its model, data and controller state, so the table does not depend
// on jobs. With out, OUT/table5.csv and OUT/table5.json are written
// together once both runs have succeeded; a bad option value is a
// FieldError naming the field, before anything runs.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "controllers/closed_loop.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/core/scenario.h"
#include "sim/io/option_table.h"

namespace ipmc {

enum class Table5Loop { kMultibody, kTransferFunction };

// "multibody" / "transfer-function".
const char* Table5LoopName(Table5Loop loop);

struct Table5Reading {
  PlantAssignment plants = PlantAssignment::kUniform;
  int cycles = 3;                   // horizon [wave periods], [1, kMaxTable5Cycles]
  double start_ramp_cycles = 0.25;  // fade-in [wave periods], [0, cycles]; 0: step start
  Table5Loop loop = Table5Loop::kMultibody;

  // Throws FieldError "table5: FIELD must be ..., got ...".
  void Validate() const;
};

constexpr int kMaxTable5Cycles = 100;

// One Table 5: per link (1..n), each controller's indices.
struct Table5Values {
  std::vector<TrackingIndices> fractional;  // C_I through eq. 15
  std::vector<TrackingIndices> pid;         // eq. 12
};

// The paper's Table 5 as printed.
Table5Values PaperTable5();

// scenarios/paper.toml of the source tree.
std::string PaperScenarioPath();

// The scenario of one controller's run: `setting` in the linear loop (no
// clamp) under `reading`, with the PID of the setting (kind kPid) or C_I
// through eq. 15 at the setting's sample rate (kind kFractional), and no
// output files.
ScenarioConfig Table5Scenario(const ScenarioConfig& setting, ControllerKind controller,
                              const Table5Reading& reading);

// Runs both controllers, on `jobs` (1 or 2) threads. Throws
// std::invalid_argument for a bad reading or jobs, std::runtime_error for
// a failing run.
Table5Values RunTable5(const ScenarioConfig& setting, const Table5Reading& reading, int jobs);

// Rows of the table in print order: index (IAE, ITAE), then link.
struct Table5Row {
  const char* index;
  int link;
  double fractional_here, fractional_paper, pid_here, pid_paper;
};
std::vector<Table5Row> Table5Rows(const Table5Values& here, const Table5Values& paper);
// (here - paper) / paper.
double RelativeError(double here, double paper);

// The table as CSV (index, link, controller, here, paper,
// relative_error) and as JSON (the reading and the same rows).
std::string Table5Csv(const Table5Values& here, const Table5Values& paper);
nlohmann::json Table5Json(const Table5Values& here, const Table5Values& paper,
                          const Table5Reading& reading);

// `table5` as the command line runs it: the reading's options, jobs and
// the output folder.
struct Table5Command {
  std::string plants = "uniform";
  int cycles = 3;                   // used if given; else the scenario's
  double start_ramp_cycles = 0.25;  // used if given; else the scenario's
  std::string loop = "multibody";
  int jobs = 2;
  std::string out;  // "": no files
};
const OptionTable<Table5Command>& Table5Options();

// What the command computed, for printing.
struct Table5Outcome {
  ScenarioConfig setting;  // scenarios/paper.toml
  Table5Reading reading;
  Table5Values here, paper;
};

// Loads the setting, reads the options (cycles and start_ramp_cycles from
// the setting unless given, by field), runs both controllers and writes
// OUT/table5.csv and OUT/table5.json once both have succeeded.
Table5Outcome RunTable5Command(const Table5Command& command,
                               const std::function<bool(const std::string& field)>& given);

}  // namespace ipmc

// `bench` as both front ends run it (sim/runs/bench_run.h): the option
// table (the model, the signal's fields, the output CSV), the checks of
// the output before the run (never over the model), the run and the CSV.
#pragma once

#include <string>

#include "sim/io/option_table.h"
#include "sim/runs/bench_run.h"

namespace ipmc {

struct BenchCommand {
  std::string model;  // default: models/flagellum3_clamped.xml
  std::string signal = "sine";  // sine | chirp
  BenchSignal bench;
  std::string out;  // the CSV; required on the command line, optional in Python
  BenchCommand();
};

const OptionTable<BenchCommand>& BenchOptions();

// Checks the signal and `out` (a writable place, not the model: FieldError
// naming out), runs the bench and writes `out` (if set) atomically.
BenchRecord RunBenchCommand(const BenchCommand& command, const BenchProgress& progress = {});

}  // namespace ipmc

// What run and gait print about a swim: the per-cycle displacements, the
// mean speed and the Reynolds numbers (and the swim's warnings), and where
// a run's files went.
#pragma once

#include <string>

#include "sim/core/swim_meter.h"
#include "sim/runs/output.h"

namespace ipmc {

void PrintSwimMetrics(const SwimMetrics& swim);

// "wrote DIR/timeseries.csv, states.csv and summary.json", with run.mat
// and run.h5 if written (sim/runs/output.h).
void PrintWritten(const std::string& dir, const RunFileFormats& formats = {});

}  // namespace ipmc

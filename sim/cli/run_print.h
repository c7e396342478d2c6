// What run and gait print about a swim: the per-cycle displacements, the
// mean speed and the Reynolds numbers (and the swim's warnings), and where
// a run's files went.
#pragma once

#include <string>
#include <vector>

#include "sim/core/energy.h"
#include "sim/core/swim_meter.h"
#include "sim/runs/output.h"

namespace ipmc {

void PrintSwimMetrics(const SwimMetrics& swim);
// The same with the run's warnings (sim/runs/run_warnings.h) on stderr
// instead of the swim's.
void PrintSwimMetrics(const SwimMetrics& swim, const std::vector<std::string>& warnings);

// Which cycles the link table, the mean speed and the mean powers are
// taken over, and why (MetricCyclesText, sim/runs/output.h).
void PrintMetricCycles(const ClosedLoopResult& result);
// The start-up cycles, which the means leave out, apart: their swim and
// the actuators' mean power (nothing when the means hold every cycle).
void PrintStartup(const ClosedLoopResult& result);

// The energy table of a closed-loop run (sim/core/energy.h): every cycle's
// mean powers, elastic energy, efficiency and cost of transport, then the
// means over the cycles they were taken over.
void PrintEnergy(const EnergyMetrics& energy);

// "wrote DIR/timeseries.csv, states.csv and summary.json", with run.mat
// and run.h5 if written (sim/runs/output.h).
void PrintWritten(const std::string& dir, const RunFileFormats& formats = {});

}  // namespace ipmc

// Sweeps that grow: a sweep file whose grid or list gains points, run
// again into the prefix of its finished table, runs only the new points.
//
// The earlier run's journal then records another sweep (its fingerprint
// covers every point), which alone would be refused. Its table
// (PREFIX.csv with PREFIX.json) names each point's resolved inputs: the
// swept values, the resolved scenario and the model's SHA-256. A point of
// the new plan whose inputs are an earlier point's takes that point's row
// (with its new index): the cells a run would give, as runs are
// deterministic. The journal is started over with those rows, and the
// other points run. Nothing is reused, and the journal is refused as
// before, if the earlier table is missing, incomplete or not the
// journal's, if another program version made it, if its columns differ
// (other swept keys, links), or if no point matches (a changed base, a
// changed model). Gait sweeps' points are not reused.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sim/batch/sweep_file.h"
#include "sim/batch/sweep_scheduler.h"

namespace ipmc {

// The rows of the earlier table at PREFIX that the shard's points of
// `plan` reuse, by the plan's point index (row[0] set to it); empty when
// none can be (see above). Throws nothing for an earlier table it cannot
// use: the journal's own checks then speak.
std::map<int, std::vector<std::string>> ReusableSweepRows(const SweepPlan& plan,
                                                          const SweepShard& shard,
                                                          const std::string& prefix);

}  // namespace ipmc

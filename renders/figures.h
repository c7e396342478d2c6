// The paper's figures, and the swim's, drawn with gnuplot
// (renders/gnuplot_figure.h: PDF, SVG or PNG by the output's extension)
// from the program's own CSV outputs. Columns are found by name
// (sim/io/columns.h); a JSON file the same command writes beside the CSV
// (summary.json, bode.json, step.json, identification.json), when there,
// says what is drawn for the title and legend. Titles say what is shown
// (controller, link, clamp, scenario), never a path; axis labels come from
// one table of column names (AxisLabel).
//
// Kinds and their input:
//  - bode (Fig. 9, 10), bode.csv of `bode --out`: magnitude and phase of
//    plant, controller, open loop and the reference model's open loop
//    against w; the open loop's gain crossover, phase and gain margins
//    marked as MATLAB's `margin` does and named in the title: those the
//    bode command found by root search on the exact response and wrote to
//    bode.json (the phase margin as a bar from -180 deg up by the margin at
//    the gain crossover, the gain margin as a bar from -GM to 0 dB at the
//    phase crossover closest to 0 dB); none without bode.json.
//  - step (Fig. 11), step.csv of `step --out`: each link's unit step and
//    the reference model's; below, each link's voltage with the clamp.
//  - tracking (Fig. 12a), timeseries.csv: per link, reference and measured
//    relative tip deflection, the tracking error (measured - reference)
//    with its RMS over the steady cycles (every cycle after the first, if
//    there are two; in the panel and the notes), and the voltage with the
//    clamp limits and the intervals at the clamp shaded; for a gait run,
//    per joint the reference and measured angle.
//  - waveform (Fig. 12b), timeseries.csv: the body in the head's frame at a
//    few instants: realised, the ideal (closed loop: the wave projected
//    onto the links, whose references it gives) and the scenario's
//    continuous wave y(x, t) (summary.json's resolved scenario).
//  - surface (Fig. 13), timeseries.csv: the lateral deflection in the
//    head's frame against time and the distance s along the body (so that
//    the map ends at the tail at every instant, which along x a bent body
//    does not reach), ideal beside realised with a shared colour bar, and
//    realised - ideal on its own scale (realised alone without an ideal).
//  - trajectory, timeseries.csv: the centre of mass's and the head's path
//    in the plane with a marker at the start of every cycle, and the net
//    displacement along and across the swimming axis against time.
//  - identification (Fig. 7), response.csv of `identify --out`: the
//    measured frequency response (Welch's H1) with its coherence and the
//    fitted G1 and G2 over the fit's band.
//  - sweep, a sweep table: --y against --x, one curve per --group.
//  - compare, two or more run directories (timeseries.csv and summary.json
//    of `run`): their centre of mass's displacement along the swimming axis
//    against time, the displacement per cycle, and per link the tracking
//    error (measured minus reference) and the voltage, one colour per run;
//    the legend names what differs between the runs' resolved scenarios
//    (summary.json inputs.resolved_scenario), e.g. "controller.kind = pid".
//
// The ideal body of waveform and surface is sim/runs/body_record.h's.
#pragma once

#include <string>
#include <vector>

#include "renders/figure_labels.h"  // AxisLabel
#include "renders/gnuplot_figure.h"

namespace ipmc {

enum class FigureKind {
  kBode,
  kStep,
  kTracking,
  kWaveform,
  kSurface,
  kTrajectory,
  kIdentification,
  kSweep,
  kCompare,
  kRegime
};

// At most this many runs in a compare figure.
constexpr int kMaxComparedRuns = 8;

// The kinds' names, as the command line spells them.
const std::vector<std::string>& FigureKindNames();
// Throws FieldError naming the kinds there are.
FigureKind FigureKindOf(const std::string& name);

struct FigureOptions {
  std::string title;  // empty: what is shown
  FigureSize size;    // 0: the kind's own; else in [200, 10000] px
  // bode
  std::vector<std::string> curves = {"plant", "controller", "open_loop", "reference_open_loop"};
  // waveform
  int instants = 4;             // in [1, 12], spread over the last period
  std::vector<double> times_s;  // or these instants (at most 12)
  // waveform, trajectory: the wave period [s]; 0: period_s of summary.json
  // beside the input (waveform: else the whole record; trajectory: else no
  // cycle markers)
  double period_s = 0.0;
  // surface: most time rows in the map, >= 2
  int max_lines = 100;
  // sweep
  std::string x_column, y_column, group_column;
  bool log_x = false, log_y = false;
  // compare: the legend's name of each run, in the order of the runs
  // (empty: what differs between their resolved scenarios)
  std::vector<std::string> labels;

  // Throws FieldError "plot: --option must be ..., got ...".
  void Validate(FigureKind kind) const;
};

// The kind-specific options (FigureOptions' members, named as the command
// line's flags without "--": "instants", "times-s", ...) and the kinds
// each applies to. Throws FieldError "plot: --OPTION applies to plot KINDS
// only, not KIND" for a given option the kind does not use, so that none
// is silently ignored; an unknown name is a FieldError too.
const std::vector<std::string>& FigureKindOptionNames();
void CheckFigureOptionsApply(FigureKind kind, const std::vector<std::string>& given);

struct FigureReport {
  std::string title;                     // on one line
  std::vector<std::string> title_lines;  // as drawn
  // What the figure found besides drawing (e.g. the margins marked).
  std::vector<std::string> notes;
};

// Draws figure `kind` of the CSV at `input` into out_path. Throws
// FieldError (sim/base/error.h) for a bad option or an unknown output
// format, InputError naming the file and the column for input without the
// needed columns or rows, std::runtime_error if gnuplot fails; nothing is
// written then.
FigureReport DrawFigureOf(FigureKind kind, const std::string& input, const FigureOptions& options,
                          const std::string& out_path);
// The same for a list of inputs: one for every kind but compare, which
// takes 2 to kMaxComparedRuns run directories. Throws FieldError (field
// "input") for another count.
FigureReport DrawFigureOf(FigureKind kind, const std::vector<std::string>& inputs,
                          const FigureOptions& options, const std::string& out_path);

// The converge command's figure (sim/runs/converge_study.h): each study's
// |swim error| [%] against its resolution, log-log, from its converge.csv.
FigureReport DrawConvergeFigure(const std::string& table_path, const std::string& out_path);


}  // namespace ipmc

// The "plot" subcommand of ipmc-swim: the paper's figures 9-13 drawn with
// gnuplot from the program's own CSV outputs.
//
//   ipmc-swim plot KIND INPUT --out FILE.png [--title TEXT]
//                  [--width-px W] [--height-px H] [kind's options]
//
// KIND and what is drawn (columns are found by name in INPUT's header):
//  - bode (Fig. 9 and 10), INPUT = bode.csv of "ipmc-swim bode": magnitude
//    [dB] and phase [deg] panels against w [rad/s] (log axis) of the
//    curves in --curves (default plant,controller,open_loop,
//    reference_open_loop; column <curve>_db and <curve>_deg each).
//  - step (Fig. 11), INPUT = step.csv of "ipmc-swim step": the reference
//    model's unit step and y_link<q> [mm] of every link in the file against
//    time [s].
//  - tracking (Fig. 12a), INPUT = timeseries.csv of "ipmc-swim run": one
//    panel per link, reference<q>_mm and measured<q>_mm (relative tip
//    deflection [mm]) against time [s].
//  - waveform (Fig. 12b), INPUT = timeseries.csv of a closed-loop run: the
//    body shape at a few instants, ideal (dashed) and realised (solid), in
//    the head's frame (x along the body from the head at rest, y lateral,
//    both mm). Realised: head (0, 0) and the tips tip<k>_x/y_mm relative
//    to head_x/y_mm, rotated by -yaw_rad. Ideal: the chain through the same
//    points that the references would give: segment k keeps the realised
//    body's mean length from point k-1 to tip k, and turns from segment
//    k-1 (the head's axis for k = 1) by asin(reference_k / L_k). L_k is
//    the length that maps the measured deflection onto the realised turn
//    angle, fitted by least squares (measured_k ~ L_k sin(turn_k)); the
//    tips stand in for the hinges, so this is the discretised wave as the
//    realised body would draw it, not the continuous wave of eq. 2. Links
//    without a reference column stay straight. Instants: --times-s T1,T2..
//    (nearest samples), or --instants N (default 4) spread over the last
//    wave period, --period-s or period_s of summary.json beside INPUT (the
//    whole record if neither is there).
//  - surface (Fig. 13), INPUT = timeseries.csv: the realised body shape
//    (as in waveform) of every sample, at most --max-lines (default 100)
//    evenly thinned, as a mesh in x [mm] - time [s] - y [mm] coloured by
//    time: one line per sample along the body, and one per point (head,
//    tips) across samples, which traces the tips' paths. A second panel
//    shows the ideal shape when the file has reference columns.
//  - sweep, INPUT = a sweep table (columns point, swept keys, status,
//    error, metrics): --y against --x, one curve per value of --group if
//    given; rows whose status is not "ok" are skipped (all rows are used if
//    there is no status column). A numeric x column gives lines sorted by
//    x (--log-x, --log-y for log axes); any other gives one category per
//    distinct value. Axis labels are the column names, which carry their
//    units (e.g. mean_speed_along_mm_s).
//
// An option that does not apply to KIND is refused. The data and the
// gnuplot script go to a temporary directory (removed afterwards); gnuplot
// (from PATH) renders to a temporary file beside FILE.png, which is
// renamed into place only if gnuplot exited with 0 and the file is a PNG.
// INPUT is read by sim/io/csv.h. Errors throw std::invalid_argument (bad
// options), InputError (sim/io/error.h: an unreadable INPUT, missing or
// non-numeric columns; the message names INPUT, the line and the column)
// or std::runtime_error (gnuplot missing or failing, I/O); no FILE.png is
// left behind then.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace ipmc {

struct PlotArgs {
  std::string kind;  // bode | step | tracking | waveform | surface | sweep
  std::string input_path;
  std::string out_path;
  std::string title;  // empty: a description of the figure and INPUT
  int width_px = 0;   // 0: the kind's default
  int height_px = 0;  // 0: the kind's default

  // bode
  std::vector<std::string> curves = {"plant", "controller", "open_loop",
                                     "reference_open_loop"};
  // waveform
  int instants = 4;
  std::vector<double> times_s;
  double period_s = 0.0;  // 0: from summary.json, else the whole record
  // surface
  int max_lines = 100;
  // sweep
  std::string x_column, y_column, group_column;
  bool log_x = false;
  bool log_y = false;
};

// Adds subcommand "plot" to app, storing options in args.
void AddPlotCommand(CLI::App& app, PlotArgs& args);

// Runs "plot" if app parsed it and returns 0; returns -1 if it was not
// chosen. Throws as described above.
int RunPlotCommand(const CLI::App& app, const PlotArgs& args);

}  // namespace ipmc

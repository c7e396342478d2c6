#include "sim/cli/plot_command.h"

#include "sim/cli/command.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/io/columns.h"
#include "sim/io/csv.h"
#include "sim/io/error.h"
#include "sim/io/files.h"
#include "sim/io/numbers.h"
#include "sim/runs/output.h"

extern char** environ;

namespace ipmc {
namespace {

namespace fs = std::filesystem;

constexpr char kPlotCommand[] = "plot";

constexpr char kBode[] = "bode";
constexpr char kStep[] = "step";
constexpr char kTracking[] = "tracking";
constexpr char kWaveform[] = "waveform";
constexpr char kSurface[] = "surface";
constexpr char kSweep[] = "sweep";

constexpr char kSummaryFile[] = "summary.json";
constexpr char kSummaryPeriodKey[] = "period_s";

constexpr char kGnuplot[] = "gnuplot";
constexpr char kPngSignature[] = "\x89PNG\r\n\x1a\n";
constexpr size_t kPngSignatureSize = 8;

constexpr int kMinImagePx = 200;
constexpr int kMaxImagePx = 10000;
constexpr int kMaxInstants = 12;
constexpr int kMinSurfaceLines = 2;

// Throws unless the table has at least `rows` rows.
void RequireRows(const CsvTable& table, size_t rows) {
  if (table.Rows() < rows) {
    throw std::invalid_argument(table.source() + ": needs at least " + std::to_string(rows) +
                                " data rows, has " + std::to_string(table.Rows()));
  }
}

// ---------------------------------------------------------------------------
// Scratch files and gnuplot.

// A fresh directory under the system's temporary directory, removed with
// everything in it when the object goes.
class ScratchDir {
 public:
  ScratchDir() {
    std::string name = (fs::temp_directory_path() / "ipmc-swim-plot.XXXXXX").string();
    if (mkdtemp(name.data()) == nullptr) {
      throw std::runtime_error("plot: cannot create a temporary directory (" +
                               std::string(std::strerror(errno)) + ")");
    }
    path_ = name;
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  fs::path File(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

// A gnuplot string literal: single quotes, in which only '' is special.
std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\n' || c == '\r') {
      quoted += ' ';
    } else {
      quoted += c;
      if (c == '\'') quoted += '\'';
    }
  }
  return quoted + "'";
}

// Numbers in scripts and data: 10 significant digits.
std::string Num(double value) { return FormatDouble(value, 10); }

// Data values for gnuplot: non-finite values become its missing-value
// marker (the preamble declares "NaN" missing).
std::string DataValue(double value) { return std::isfinite(value) ? Num(value) : "NaN"; }

// Column-wise data as a whitespace-separated table.
std::string DataTable(const std::vector<std::vector<double>>& series) {
  std::string text;
  const size_t rows = series.empty() ? 0 : series.front().size();
  for (size_t r = 0; r < rows; ++r) {
    for (size_t c = 0; c < series.size(); ++c) {
      text += (c ? " " : "") + DataValue(series[c][r]);
    }
    text += "\n";
  }
  return text;
}

// The last non-empty line of gnuplot's output, its error message, with the
// temporary script's path (gone by the time anyone reads it) shortened.
std::string LastLine(const fs::path& log, const fs::path& script) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  const size_t start = last.find_first_not_of(" \t");
  if (start == std::string::npos) return "no message";
  last = last.substr(start);
  const std::string quoted_script = "\"" + script.string() + "\"";
  if (const size_t at = last.find(quoted_script); at != std::string::npos) {
    last.replace(at, quoted_script.size(), "script");
  }
  return last;
}

// Runs "gnuplot SCRIPT" with its output in LOG; throws unless it exits 0.
void RunGnuplot(const fs::path& script, const fs::path& log, const std::string& input) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::string program = kGnuplot;
  std::string script_path = script.string();
  char* argv[] = {program.data(), script_path.data(), nullptr};
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, kGnuplot, &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    throw std::runtime_error(std::string("plot: cannot run ") + kGnuplot + " (" +
                             std::strerror(spawn_error) + "; Debian package gnuplot-nox)");
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      throw std::runtime_error(std::string("plot: waiting for gnuplot failed (") +
                               std::strerror(errno) + ")");
    }
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = WIFEXITED(status)
                                ? "exit status " + std::to_string(WEXITSTATUS(status))
                                : "killed by signal " + std::to_string(WTERMSIG(status));
    throw std::runtime_error("plot: gnuplot failed drawing " + input + " (" + how +
                             "): " + LastLine(log, script));
  }
}

bool IsPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[kPngSignatureSize] = {};
  in.read(head, kPngSignatureSize);
  return in.gcount() == static_cast<std::streamsize>(kPngSignatureSize) &&
         std::memcmp(head, kPngSignature, kPngSignatureSize) == 0;
}

// ---------------------------------------------------------------------------
// Figures. Each builder writes its data into the scratch directory and
// returns the gnuplot commands that draw it (after the preamble).

struct Figure {
  std::string commands;
  int width_px = 1000;
  int height_px = 700;
};

std::string DefaultTitle(const PlotArgs& args) {
  std::string what;
  if (args.kind == kBode) what = "Frequency response";
  if (args.kind == kStep) what = "Unit step response of each link's closed loop";
  if (args.kind == kTracking) what = "Relative tip deflection of each link, reference and measured";
  if (args.kind == kWaveform) what = "Body shape in the head's frame, ideal and realised";
  if (args.kind == kSurface) what = "Body shape over time, in the head's frame";
  if (args.kind == kSweep) {
    what = args.y_column + " against " + args.x_column;
    if (!args.group_column.empty()) what += ", by " + args.group_column;
  }
  return what + " (" + args.input_path + ")";
}

std::string BodeLabel(const std::string& curve) {
  if (curve == "plant") return "plant P";
  if (curve == "controller") return "controller C";
  if (curve == "open_loop") return "open loop C P";
  if (curve == "reference_open_loop") return "reference open loop (5/s)^1.16";
  return curve;
}

// Fig. 9 and 10: magnitude and phase of the chosen curves.
Figure BodeFigure(const CsvTable& table, const PlotArgs& args, const ScratchDir& scratch,
                  const std::string& title) {
  RequireRows(table, 2);
  std::vector<std::vector<double>> series = {table.Numbers(columns::kFrequency)};
  for (const std::string& curve : args.curves) {
    series.push_back(table.Numbers(columns::MagnitudeDb(curve)));
    series.push_back(table.Numbers(columns::PhaseDeg(curve)));
  }
  const fs::path data = scratch.File("bode.dat");
  WriteFileAtomically(data.string(), DataTable(series));

  auto plot_line = [&](int offset) {
    std::string line = "plot ";
    for (size_t k = 0; k < args.curves.size(); ++k) {
      const bool reference = args.curves[k] == "reference_open_loop";
      line += (k ? ", " : "") + Quote(data.string()) + " using 1:" +
              std::to_string(2 + 2 * k + offset) + " with lines lw 2" +
              (reference ? " dt 2 lc rgb 'black'" : "") + " title " +
              Quote(BodeLabel(args.curves[k]));
    }
    return line + "\n";
  };
  Figure figure;
  figure.height_px = 800;
  figure.commands = "set multiplot layout 2,1 title " + Quote(title) + "\n" +
                    "set logscale x\nset format x '%g'\nset lmargin 10\nset rmargin 4\n"
                    "set xzeroaxis lt 1 lc rgb 'gray40'\n"
                    "set key outside top center horizontal\n"
                    "set ylabel 'magnitude [dB]'\n" + plot_line(0) +
                    "unset xzeroaxis\nunset key\n"
                    "set xlabel 'angular frequency w [rad/s]'\n"
                    "set ylabel 'phase [deg]'\n" + plot_line(1) + "unset multiplot\n";
  return figure;
}

// Fig. 11: the reference model's step and each link's.
Figure StepFigure(const CsvTable& table, const PlotArgs&, const ScratchDir& scratch,
                  const std::string& title) {
  RequireRows(table, 2);
  std::vector<std::vector<double>> series = {table.Numbers(columns::kTime),
                                              table.Numbers(columns::kReferenceModel)};
  std::vector<int> links;
  for (int q = 1; table.Has(columns::StepOutput(q)); ++q) {
    series.push_back(table.Numbers(columns::StepOutput(q)));
    links.push_back(q);
  }
  if (links.empty()) table.Column(columns::StepOutput(1));
  const fs::path data = scratch.File("step.dat");
  WriteFileAtomically(data.string(), DataTable(series));

  // The reference model last, dashed on top of the links.
  std::string plot = "plot ";
  for (size_t k = 0; k < links.size(); ++k) {
    plot += Quote(data.string()) + " using 1:" + std::to_string(3 + k) +
            " with lines lw 2 title " + Quote("link " + std::to_string(links[k])) + ", ";
  }
  plot += Quote(data.string()) +
          " using 1:2 with lines lw 3 dt 2 lc rgb 'black' title 'reference model'";
  Figure figure;
  figure.height_px = 600;
  figure.commands = "set title " + Quote(title) + "\n" +
                    "set xlabel 'time [s]'\nset ylabel 'tip deflection [mm] (1 mm step)'\n"
                    "set key right bottom\n" + plot + "\n";
  return figure;
}

// Links q = 1, 2, ... with a reference<q>_mm column.
std::vector<int> ReferencedLinks(const CsvTable& table) {
  std::vector<int> links;
  for (int q = 1; table.Has(columns::Reference(q)); ++q) links.push_back(q);
  return links;
}

// Fig. 12a: reference and measured deflection, one panel per link.
Figure TrackingFigure(const CsvTable& table, const PlotArgs&, const ScratchDir& scratch,
                      const std::string& title) {
  RequireRows(table, 2);
  const std::vector<int> links = ReferencedLinks(table);
  if (links.empty()) table.Column(columns::Reference(1));
  std::vector<std::vector<double>> series = {table.Numbers(columns::kTime)};
  for (int q : links) {
    series.push_back(table.Numbers(columns::Reference(q)));
    series.push_back(table.Numbers(columns::Measured(q)));
  }
  const fs::path data = scratch.File("tracking.dat");
  WriteFileAtomically(data.string(), DataTable(series));

  std::string commands = "set multiplot layout " + std::to_string(links.size()) +
                         ",1 title " + Quote(title) + "\n" +
                         "set lmargin 12\nset rmargin 4\nset key outside top center horizontal\n";
  for (size_t k = 0; k < links.size(); ++k) {
    if (k == 1) commands += "unset key\n";
    if (k + 1 == links.size()) commands += "set xlabel 'time [s]'\n";
    commands += "set ylabel " + Quote("link " + std::to_string(links[k]) + " deflection [mm]") +
                "\n";
    commands += "plot " + Quote(data.string()) + " using 1:" + std::to_string(3 + 2 * k) +
                " with lines lw 2 lc rgb '#1f77b4' title 'measured', '' using 1:" +
                std::to_string(2 + 2 * k) +
                " with lines lw 2 dt 2 lc rgb 'black' title 'reference'\n";
  }
  Figure figure;
  figure.height_px = 100 + 260 * static_cast<int>(links.size());
  figure.commands = commands + "unset multiplot\n";
  return figure;
}

struct Point2 {
  double x = 0.0, y = 0.0;
};

// The body per sample as points (head, tip 1, ..., tip n) in the head's
// frame [mm]: realised from the tips, ideal from the references (see the
// header, "waveform").
struct BodyRecord {
  std::vector<double> t_s;
  std::vector<std::vector<Point2>> realised;
  std::vector<std::vector<Point2>> ideal;  // empty without reference columns
};

double WrapAngle(double angle) { return std::remainder(angle, kTwoPi); }

BodyRecord ReadBodyRecord(const CsvTable& table, bool need_ideal) {
  RequireRows(table, 1);
  BodyRecord body;
  body.t_s = table.Numbers(columns::kTime);
  const std::vector<double> head_x = table.Numbers(columns::kHeadX);
  const std::vector<double> head_y = table.Numbers(columns::kHeadY);
  const std::vector<double> yaw = table.Numbers(columns::kYaw);
  std::vector<std::vector<double>> tip_x, tip_y;
  for (int k = 1; k == 1 || table.Has(columns::TipX(k)); ++k) {
    tip_x.push_back(table.Numbers(columns::TipX(k)));
    tip_y.push_back(table.Numbers(columns::TipY(k)));
  }
  const size_t samples = body.t_s.size();
  const size_t tips = tip_x.size();
  body.realised.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    const double c = std::cos(yaw[i]), s = std::sin(yaw[i]);
    body.realised[i].push_back({0.0, 0.0});
    for (size_t k = 0; k < tips; ++k) {
      const double dx = tip_x[k][i] - head_x[i], dy = tip_y[k][i] - head_y[i];
      body.realised[i].push_back({c * dx + s * dy, -s * dx + c * dy});
    }
  }

  const std::vector<int> links = ReferencedLinks(table);
  if (links.empty()) {
    if (need_ideal) table.Column(columns::Reference(1));
    return body;
  }
  // Per segment k (point k-1 to tip k): mean length, and the length L_k
  // that maps the measured deflection onto the realised turn angle.
  std::vector<double> segment_mm(tips, 0.0), link_mm(tips, 0.0);
  std::vector<std::vector<double>> reference(tips);
  for (size_t k = 0; k < tips; ++k) {
    const int link = static_cast<int>(k) + 1;
    double numerator = 0.0, denominator = 0.0;
    const bool referenced = table.Has(columns::Reference(link));
    std::vector<double> measured;
    if (referenced) {
      reference[k] = table.Numbers(columns::Reference(link));
      measured = table.Numbers(columns::Measured(link));
    }
    for (size_t i = 0; i < samples; ++i) {
      const std::vector<Point2>& p = body.realised[i];
      segment_mm[k] += std::hypot(p[k + 1].x - p[k].x, p[k + 1].y - p[k].y) / samples;
      if (!referenced) continue;
      const double direction = std::atan2(p[k + 1].y - p[k].y, p[k + 1].x - p[k].x);
      const double previous = k == 0 ? 0.0 : std::atan2(p[k].y - p[k - 1].y, p[k].x - p[k - 1].x);
      const double sine = std::sin(WrapAngle(direction - previous));
      numerator += measured[i] * sine;
      denominator += sine * sine;
    }
    const double fitted = denominator > 0.0 ? numerator / denominator : 0.0;
    link_mm[k] = std::isfinite(fitted) && fitted > 0.0 ? fitted : segment_mm[k];
  }
  body.ideal.resize(samples);
  for (size_t i = 0; i < samples; ++i) {
    Point2 point;
    double direction = 0.0;
    body.ideal[i].push_back(point);
    for (size_t k = 0; k < tips; ++k) {
      if (!reference[k].empty()) {
        const double ratio = std::clamp(reference[k][i] / link_mm[k], -1.0, 1.0);
        direction += std::asin(ratio);
      }
      point.x += segment_mm[k] * std::cos(direction);
      point.y += segment_mm[k] * std::sin(direction);
      body.ideal[i].push_back(point);
    }
  }
  return body;
}

size_t NearestSample(const std::vector<double>& t_s, double t) {
  size_t best = 0;
  for (size_t i = 1; i < t_s.size(); ++i) {
    if (std::abs(t_s[i] - t) < std::abs(t_s[best] - t)) best = i;
  }
  return best;
}

// period_s of summary.json beside `input`; 0 if there is none.
double SummaryPeriod(const std::string& input) {
  const fs::path summary = fs::path(input).parent_path() / kSummaryFile;
  std::ifstream in(summary);
  if (!in) return 0.0;
  const nlohmann::json json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || !json.contains(kSummaryPeriodKey) ||
      !json[kSummaryPeriodKey].is_number()) {
    return 0.0;
  }
  const double period = json[kSummaryPeriodKey].get<double>();
  return std::isfinite(period) && period > 0.0 ? period : 0.0;
}

std::vector<size_t> WaveformInstants(const BodyRecord& body, const PlotArgs& args) {
  std::vector<size_t> samples;
  if (!args.times_s.empty()) {
    for (double t : args.times_s) samples.push_back(NearestSample(body.t_s, t));
    return samples;
  }
  const double t_first = body.t_s.front(), t_last = body.t_s.back();
  double period = args.period_s > 0.0 ? args.period_s : SummaryPeriod(args.input_path);
  if (period <= 0.0 || period > t_last - t_first) period = t_last - t_first;
  for (int k = 1; k <= args.instants; ++k) {
    samples.push_back(NearestSample(body.t_s, t_last - period + period * k / args.instants));
  }
  return samples;
}

std::string PointsBlock(const std::vector<Point2>& points) {
  std::string text;
  for (const Point2& p : points) text += DataValue(p.x) + " " + DataValue(p.y) + "\n";
  return text;
}

// Fig. 12b: ideal and realised shape at a few instants.
Figure WaveformFigure(const CsvTable& table, const PlotArgs& args, const ScratchDir& scratch,
                      const std::string& title) {
  const BodyRecord body = ReadBodyRecord(table, /*need_ideal=*/true);
  const std::vector<size_t> instants = WaveformInstants(body, args);
  std::string data_text;
  for (size_t sample : instants) {
    data_text += PointsBlock(body.realised[sample]) + "\n\n" + PointsBlock(body.ideal[sample]) +
                 "\n\n";
  }
  const fs::path data = scratch.File("waveform.dat");
  WriteFileAtomically(data.string(), data_text);

  std::string plot = "plot ";
  for (size_t k = 0; k < instants.size(); ++k) {
    const std::string color = std::to_string(k + 1);
    char label[64];
    std::snprintf(label, sizeof(label), "t = %.4g s", body.t_s[instants[k]]);
    plot += (k ? ", " : "") + Quote(data.string()) + " index " + std::to_string(2 * k) +
            " using 1:2 with linespoints lw 2 pt 7 ps 1.2 lc " + color + " title " +
            Quote(std::string(label) + " realised") + ", '' index " + std::to_string(2 * k + 1) +
            " using 1:2 with linespoints lw 2 dt 2 pt 6 ps 1.2 lc " + color + " title " +
            Quote(std::string(label) + " ideal");
  }
  Figure figure;
  figure.height_px = 500;
  figure.commands = "set title " + Quote(title) + "\n" +
                    "set xlabel 'x along the body from the head [mm]'\n"
                    "set ylabel 'y lateral [mm]'\n"
                    "set key outside right top\n"
                    "set xzeroaxis lt 1 lc rgb 'gray40'\n" + plot + "\n";
  return figure;
}

// Evenly spread sample indices, at most `count`.
std::vector<size_t> Thinned(size_t samples, int count) {
  std::vector<size_t> chosen;
  if (samples <= static_cast<size_t>(count)) {
    for (size_t i = 0; i < samples; ++i) chosen.push_back(i);
    return chosen;
  }
  for (int k = 0; k < count; ++k) {
    chosen.push_back(static_cast<size_t>(std::lround(
        static_cast<double>(k) * static_cast<double>(samples - 1) / (count - 1))));
  }
  return chosen;
}

// Rows "x t y" per sample, one isoline per sample.
std::string SurfaceData(const std::vector<std::vector<Point2>>& shapes,
                        const std::vector<double>& t_s, const std::vector<size_t>& samples) {
  std::string text;
  for (size_t i : samples) {
    for (const Point2& p : shapes[i]) {
      text += DataValue(p.x) + " " + DataValue(t_s[i]) + " " + DataValue(p.y) + "\n";
    }
    text += "\n";
  }
  return text;
}

// Fig. 13: the body's lateral shape against time in 3-D.
Figure SurfaceFigure(const CsvTable& table, const PlotArgs& args, const ScratchDir& scratch,
                     const std::string& title) {
  const BodyRecord body = ReadBodyRecord(table, /*need_ideal=*/false);
  const std::vector<size_t> samples = Thinned(body.t_s.size(), args.max_lines);
  const bool with_ideal = !body.ideal.empty();
  // Both panels on the same axes.
  double lateral_max = 0.0, along_max = 0.0;
  for (size_t i : samples) {
    for (const auto* shapes : {&body.realised, &body.ideal}) {
      if (shapes->empty()) continue;
      for (const Point2& p : (*shapes)[i]) {
        lateral_max = std::max(lateral_max, std::abs(p.y));
        along_max = std::max(along_max, p.x);
      }
    }
  }
  if (!(lateral_max > 0.0)) lateral_max = 1.0;
  if (!(along_max > 0.0)) along_max = 1.0;

  const fs::path realised = scratch.File("surface_realised.dat");
  WriteFileAtomically(realised.string(), SurfaceData(body.realised, body.t_s, samples));
  std::string commands = "set view 60,30\nset xyplane at " + Num(-1.1 * lateral_max) + "\n" +
                         "set xrange [0:" + Num(along_max) + "]\n" +
                         "set yrange [" + Num(body.t_s[samples.front()]) + ":" +
                         Num(body.t_s[samples.back()]) + "]\n" +
                         "set zrange [" + Num(-1.1 * lateral_max) + ":" + Num(1.1 * lateral_max) +
                         "]\n"
                         "set xlabel 'x along the body [mm]'\nset ylabel 'time [s]'\n"
                         "set zlabel 'y lateral [mm]' rotate parallel\n"
                         "set palette rgbformulae 33,13,10\nunset colorbox\nunset key\n";
  auto splot = [](const fs::path& data, const std::string& panel) {
    return "set title " + Quote(panel) + "\nsplot " + Quote(data.string()) +
           " using 1:2:3:2 with lines lw 1.5 lc palette\n";
  };
  Figure figure;
  figure.height_px = 560;
  if (with_ideal) {
    const fs::path ideal = scratch.File("surface_ideal.dat");
    WriteFileAtomically(ideal.string(), SurfaceData(body.ideal, body.t_s, samples));
    figure.width_px = 1400;
    figure.commands = "set multiplot layout 1,2 title " + Quote(title) + "\n" + commands +
                      splot(ideal, "ideal (from the references)") +
                      splot(realised, "realised (tips)") + "unset multiplot\n";
  } else {
    figure.commands = commands + splot(realised, title);
  }
  return figure;
}

// A sweep column, or one element of an array column: "link_lengths_mm[0]".
class SweepAxis {
 public:
  SweepAxis(const CsvTable& table, const std::string& spec) : name_(spec) {
    std::string column = spec;
    const size_t open = spec.find('[');
    if (open != std::string::npos && spec.back() == ']') {
      column = spec.substr(0, open);
      const std::string index = spec.substr(open + 1, spec.size() - open - 2);
      const std::optional<long> value = ParseInteger(index);
      if (!value || *value < 0) {
        throw std::invalid_argument(table.source() + ": column " + spec +
                                    ": the element index must be a whole number >= 0");
      }
      element_ = *value;
    }
    column_ = table.Column(column);
  }

  // The field (or its array element) of `row` as text.
  std::string Text(const CsvTable& table, size_t row) const {
    const std::string& text = table.Text(row, column_);
    if (element_ < 0) return text;
    const nlohmann::json array = nlohmann::json::parse(text, nullptr, false);
    if (!array.is_array() || element_ >= static_cast<long>(array.size())) {
      throw std::invalid_argument(table.source() + ": column " + name_ + ": '" + text +
                                  "' has no element " + std::to_string(element_));
    }
    const nlohmann::json& value = array[element_];
    return value.is_string() ? value.get<std::string>() : value.dump();
  }

 private:
  std::string name_;
  size_t column_ = 0;
  long element_ = -1;
};

// Metric against a swept parameter, one curve per group.
Figure SweepFigure(const CsvTable& table, const PlotArgs& args, const ScratchDir& scratch,
                   const std::string& title) {
  const SweepAxis x_axis(table, args.x_column);
  const size_t y_column = table.Column(args.y_column);
  const bool grouped = !args.group_column.empty();
  const std::optional<SweepAxis> group_axis =
      grouped ? std::optional<SweepAxis>(SweepAxis(table, args.group_column)) : std::nullopt;
  const bool has_status = table.Has(columns::kStatus);
  const size_t status_column = has_status ? table.Column(columns::kStatus) : 0;

  std::vector<size_t> rows;
  for (size_t r = 0; r < table.Rows(); ++r) {
    if (!has_status || table.Text(r, status_column) == columns::kStatusOk) rows.push_back(r);
  }
  if (rows.empty()) {
    throw std::invalid_argument(table.source() + ": no row with status " + columns::kStatusOk +
                                " to plot");
  }
  bool numeric_x = true;
  for (size_t r : rows) numeric_x = numeric_x && ParseDouble(x_axis.Text(table, r)).has_value();
  std::vector<std::string> categories;  // distinct x values, non-numeric x
  std::vector<std::string> groups;      // distinct group values, in order
  std::map<std::string, std::vector<std::pair<double, double>>> points;
  for (size_t r : rows) {
    const std::string group = grouped ? group_axis->Text(table, r) : "";
    if (std::find(groups.begin(), groups.end(), group) == groups.end()) groups.push_back(group);
    double x = 0.0;
    const std::string value = x_axis.Text(table, r);
    if (numeric_x) {
      x = *ParseDouble(value);
    } else {
      auto at = std::find(categories.begin(), categories.end(), value);
      if (at == categories.end()) at = categories.insert(categories.end(), value);
      x = static_cast<double>(at - categories.begin());
    }
    points[group].push_back({x, table.Number(r, y_column)});
  }
  std::string data_text;
  for (const std::string& group : groups) {
    std::vector<std::pair<double, double>>& curve = points[group];
    std::stable_sort(curve.begin(), curve.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [x, y] : curve) data_text += DataValue(x) + " " + DataValue(y) + "\n";
    data_text += "\n\n";
  }
  const fs::path data = scratch.File("sweep.dat");
  WriteFileAtomically(data.string(), data_text);

  std::string commands = "set title " + Quote(title) + "\n" + "set xlabel " +
                         Quote(args.x_column) + "\nset ylabel " + Quote(args.y_column) + "\n" +
                         "set key outside right top\n";
  if (args.log_x) commands += "set logscale x\n";
  if (args.log_y) commands += "set logscale y\n";
  if (!numeric_x) {
    commands += "set xrange [-0.5:" + Num(categories.size() - 0.5) + "]\nset xtics (";
    for (size_t k = 0; k < categories.size(); ++k) {
      commands += (k ? ", " : "") + Quote(categories[k]) + " " + std::to_string(k);
    }
    commands += ")\n";
  } else {
    commands += "set offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05\n";
  }
  std::string plot = "plot ";
  for (size_t k = 0; k < groups.size(); ++k) {
    const std::string label = grouped ? args.group_column + " = " + groups[k] : args.y_column;
    plot += (k ? ", " : "") + Quote(data.string()) + " index " + std::to_string(k) +
            " using 1:2 with " + (numeric_x ? "linespoints lw 2" : "points") +
            " pt 7 ps 1.3 title " + Quote(label);
  }
  Figure figure;
  figure.height_px = 600;
  figure.commands = commands + plot + "\n";
  return figure;
}

// ---------------------------------------------------------------------------
// Options.

// Refuses options that KIND does not use, so that none is silently
// ignored.
void ValidateOptions(const CLI::App& command, const PlotArgs& args) {
  const std::pair<const char*, const char*> option_kind[] = {
      {"--curves", kBode},      {"--instants", kWaveform}, {"--times-s", kWaveform},
      {"--period-s", kWaveform}, {"--max-lines", kSurface}, {"--x", kSweep},
      {"--y", kSweep},          {"--group", kSweep},       {"--log-x", kSweep},
      {"--log-y", kSweep}};
  for (const auto& [option, kind] : option_kind) {
    if (args.kind != kind && command.count(option) > 0) {
      throw std::invalid_argument(std::string(kPlotCommand) + ": " + option +
                                  " applies to plot " + kind + " only, not " + args.kind);
    }
  }
  const std::pair<const char*, int> sizes[] = {{"--width-px", args.width_px},
                                                {"--height-px", args.height_px}};
  for (const auto& [option, size] : sizes) {
    if (command.count(option) > 0 && (size < kMinImagePx || size > kMaxImagePx)) {
      ThrowOption(kPlotCommand, option,
                  "in [" + std::to_string(kMinImagePx) + ", " + std::to_string(kMaxImagePx) + "]",
                  std::to_string(size));
    }
  }
  if (args.out_path.empty()) ThrowOption(kPlotCommand, "--out", "a file name", "nothing");
  if (args.kind == kBode && args.curves.empty()) ThrowOption(kPlotCommand, "--curves", "non-empty", "nothing");
  if (args.instants < 1 || args.instants > kMaxInstants) {
    ThrowOption(kPlotCommand, "--instants", "in [1, " + std::to_string(kMaxInstants) + "]",
                std::to_string(args.instants));
  }
  for (double t : args.times_s) {
    if (!std::isfinite(t)) ThrowOption(kPlotCommand, "--times-s", "finite", FormatDouble(t));
  }
  if (args.times_s.size() > static_cast<size_t>(kMaxInstants)) {
    ThrowOption(kPlotCommand, "--times-s", "at most " + std::to_string(kMaxInstants) + " times",
                std::to_string(args.times_s.size()));
  }
  if (!std::isfinite(args.period_s) || args.period_s < 0) {
    ThrowOption(kPlotCommand, "--period-s", "finite and > 0", FormatDouble(args.period_s));
  }
  if (args.max_lines < kMinSurfaceLines) {
    ThrowOption(kPlotCommand, "--max-lines", ">= " + std::to_string(kMinSurfaceLines),
                std::to_string(args.max_lines));
  }
  if (args.kind == kSweep && (args.x_column.empty() || args.y_column.empty())) {
    throw std::invalid_argument(std::string(kPlotCommand) + ": plot sweep needs --x and --y");
  }
}

void RenderPng(const Figure& figure, const PlotArgs& args, const ScratchDir& scratch) {
  const int width = args.width_px > 0 ? args.width_px : figure.width_px;
  const int height = args.height_px > 0 ? args.height_px : figure.height_px;
  const std::string size = std::to_string(width) + "," + std::to_string(height);

  EnsureParentDirectory(args.out_path);
  PendingFile png(args.out_path);
  const std::string& temp = png.temp_path();

  // pngcairo where this gnuplot has it (antialiased), else libgd's png.
  const std::string script =
      "set encoding utf8\n"
      "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
      "  set terminal pngcairo size " + size + " noenhanced font 'sans,11' linewidth 1\n"
      "} else {\n"
      "  set terminal png size " + size + " noenhanced\n"
      "}\n"
      "set output " + Quote(temp) + "\n"
      "set datafile missing 'NaN'\n"
      "set grid back lt 1 lc rgb 'gray85' lw 1\n" +
      figure.commands + "unset output\n";
  const fs::path script_path = scratch.File("plot.gp");
  WriteFileAtomically(script_path.string(), script);
  RunGnuplot(script_path, scratch.File("gnuplot.log"), args.input_path);
  if (!IsPng(temp)) {
    throw std::runtime_error("plot: gnuplot wrote no PNG drawing " + args.input_path + ": " +
                             LastLine(scratch.File("gnuplot.log"), script_path));
  }
  png.Commit();
}

int RunPlot(const CLI::App& command, const PlotArgs& args) {
  ValidateOptions(command, args);
  const CsvTable table = CsvTable::Read(args.input_path);
  const std::string title = args.title.empty() ? DefaultTitle(args) : args.title;
  ScratchDir scratch;
  Figure figure;
  if (args.kind == kBode) figure = BodeFigure(table, args, scratch, title);
  if (args.kind == kStep) figure = StepFigure(table, args, scratch, title);
  if (args.kind == kTracking) figure = TrackingFigure(table, args, scratch, title);
  if (args.kind == kWaveform) figure = WaveformFigure(table, args, scratch, title);
  if (args.kind == kSurface) figure = SurfaceFigure(table, args, scratch, title);
  if (args.kind == kSweep) figure = SweepFigure(table, args, scratch, title);
  RenderPng(figure, args, scratch);
  std::printf("plot %s of %s written to %s\n", args.kind.c_str(), args.input_path.c_str(),
              args.out_path.c_str());
  return 0;
}

}  // namespace

void AddPlotCommand(CLI::App& app, PlotArgs& args) {
  CLI::App* cmd = AddCommand(app, kPlotCommand, "Draw one of the paper's figures (gnuplot PNG)");
  cmd->add_option("kind", args.kind,
                  "bode (Fig. 9/10) | step (Fig. 11) | tracking (Fig. 12a) | waveform (Fig. 12b) "
                  "| surface (Fig. 13) | sweep")
      ->required()
      ->check(CLI::IsMember({kBode, kStep, kTracking, kWaveform, kSurface, kSweep}));
  cmd->add_option("input", args.input_path,
                  "bode.csv, step.csv, timeseries.csv (tracking, waveform, surface) or a sweep "
                  "table")
      ->required();
  cmd->add_option("-o,--out", args.out_path, "PNG file to write")->required();
  cmd->add_option("--title", args.title, "Figure title (default: what is drawn and INPUT)");
  cmd->add_option("--width-px", args.width_px, "Image width [px] (default: the kind's)")
      ->default_str("");
  cmd->add_option("--height-px", args.height_px, "Image height [px] (default: the kind's)")
      ->default_str("");
  cmd->add_option("--curves", args.curves,
                  "bode: curves to draw, of plant, controller, open_loop, reference_open_loop")
      ->delimiter(',');
  cmd->add_option("--instants", args.instants,
                  "waveform: number of instants over the last wave period");
  cmd->add_option("--times-s", args.times_s, "waveform: instants [s] (nearest samples)")
      ->delimiter(',')
      ->default_str("");
  cmd->add_option("--period-s", args.period_s,
                  "waveform: wave period [s] (default: period_s of summary.json beside INPUT)")
      ->default_str("");
  cmd->add_option("--max-lines", args.max_lines, "surface: most body lines drawn");
  cmd->add_option("--x", args.x_column,
                  "sweep: column on the x axis (NAME[i]: element i of an array column)");
  cmd->add_option("--y", args.y_column, "sweep: column on the y axis");
  cmd->add_option("--group", args.group_column, "sweep: one curve per value of this column");
  cmd->add_flag("--log-x", args.log_x, "sweep: logarithmic x axis");
  cmd->add_flag("--log-y", args.log_y, "sweep: logarithmic y axis");
}

int RunPlotCommand(const CLI::App& app, const PlotArgs& args) {
  if (!app.got_subcommand(kPlotCommand)) return -1;
  return RunPlot(*app.get_subcommand(kPlotCommand), args);
}

}  // namespace ipmc

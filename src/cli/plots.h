// Plots of a run, rendered by gnuplot (Debian gnuplot-nox) as PNG and SVG. The data and the
// gnuplot script are written next to the pictures (frf.dat, frf.gp), so users can restyle them.
//
// Safety: gnuplot is run without a shell (cli/child_process.h) and every text in a script (case
// title, body, contact and study names, labels) is a single-quoted gnuplot string, which gnuplot
// never substitutes (no `command`, no @macro); file names in scripts are our own. `stickslip plot`
// never runs a script it finds in a folder: it writes every script again from the data files.
//
// Completeness: gnuplot draws into a TemporaryFolder of the plot's folder (io/atomic_file.h); a
// picture is moved to its result name only when gnuplot exited with status 0 and the file is
// complete (a PNG ends with its IEND chunk, an SVG with </svg>): a full disk or an interruption
// never leaves a truncated picture. A picture that could not be drawn is reported (PlotLog) and
// an older picture of that name is removed, so that no picture shows other data than its .dat.
// A missing gnuplot is a warning, not a failure (the .dat and .gp files are written).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cli/results_files.h"

namespace stickslip {

// x[i] = NaN is a break: the data file gets a blank line there and gnuplot ends the line.
struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  std::string style = "lines lw 2";  // gnuplot "with" clause, e.g. "points pt 6 ps 1.2"
};

// How the plots are drawn: output.log_amplitude of the case (kept in summary.json, so that
// `stickslip plot` draws what `run` drew), or `stickslip plot --log`.
struct PlotOptions {
  // The amplitude axis of frf, frf_full_vs_reduced and frf_study logarithmic (drawn linear when
  // no amplitude is > 0: a logarithmic axis has nothing to show then).
  bool log_amplitude = false;
};

// What the plots of one command did not draw. Each failure is printed as a warning when it
// happens (stickslip: warning: ...) and remembered.
class PlotLog {
 public:
  void failed(const std::filesystem::path& picture, const std::string& reason);
  void gnuplot_absent(const std::string& warning);  // printed once
  const std::vector<std::string>& missing() const { return missing_; }
  // A picture another process could not draw (its warning printed there).
  void add_missing(const std::string& picture) { missing_.push_back(picture); }

 private:
  std::vector<std::string> missing_;
  bool absent_reported_ = false;
};

// Exit status of a command whose results are all written but some pictures are missing.
constexpr int kExitPlotsMissing = 4;

// The end of a command that drew plots: when pictures are missing, one line lists them and says
// `stickslip plot <redraw_dir>` redraws them; returns kExitPlotsMissing then, else 0.
int plots_exit_code(const PlotLog& log, const std::filesystem::path& redraw_dir);

// One plot with several curves; writes <stem>.dat, <stem>.gp, <stem>.png, <stem>.svg into dir.
// Returns false (and logs the pictures not drawn) if gnuplot is missing or fails. log_x: a
// logarithmic x axis (drawn linear unless every x is > 0).
bool plot_curves(const std::filesystem::path& dir, const std::string& stem,
                 const std::string& title, const std::string& xlabel, const std::string& ylabel,
                 const std::vector<PlotSeries>& series, PlotLog* log, bool log_y = false,
                 bool log_x = false);

// Amplitude of the first dynamic harmonic of each output.frf DOF over the converged points,
// labelled "<prefix><body> node <id> <axis>".
std::vector<PlotSeries> frf_series(const SolveResults& results, const std::string& prefix);

// The plots of one solve folder, from its files: frf (the FRF DOFs of summary.json; with
// analysis.stability the unstable points' parts of each curve dashed, in the curve's colour, and
// the bifurcations of summary.json marked by black symbols, one legend entry per type; frf_phase
// likewise dashed, split at midpoints) and
// frf_phase (their phase, unwrapped along the sweep),
// contact_state (mean stick / slip / separation fractions over the pairs along the sweep),
// dissipation (energy dissipated per cycle per contact, and in all, along the sweep) and
// hysteresis, hysteresis_t2 (force against relative displacement along t1, t2 of the contact
// frame, of the histories.csv pairs at the most dissipative point; t2 for 3D pairs only).
void plot_solve_results(const std::filesystem::path& dir, const SolveResults& results,
                        const std::vector<PlotSeries>& frf, PlotLog* log,
                        const PlotOptions& options = {});

// The thesis's validation plot frf_full_vs_reduced: the reduced nonlinear FRF curves and the
// full-model recovery at the recovered points (drawn when there are at least two).
void plot_full_vs_reduced(const std::filesystem::path& dir, const std::string& title,
                          const std::vector<PlotSeries>& frf,
                          const std::vector<PlotSeries>& full_frf, PlotLog* log,
                          const PlotOptions& options = {});

// frf_full_vs_reduced again from its data file dir/frf_full_vs_reduced.dat (the recovered
// full-model amplitudes are in no CSV); nothing if there is none. A damaged data file throws
// InvalidInput naming its line.
void redraw_full_vs_reduced(const std::filesystem::path& dir, const std::string& title,
                            PlotLog* log, const PlotOptions& options = {});

// The overlay frf_study of a study's FRF curves (per studied value, in the study's order, the
// frf_series of its folder, labelled by folder), titled "<title>: <parameter>": one colour per
// value, one dash type per FRF DOF. Nothing when there are no curves.
void plot_study(const std::filesystem::path& dir, const std::string& title,
                const std::string& parameter,
                const std::vector<std::vector<PlotSeries>>& per_value, PlotLog* log,
                const PlotOptions& options = {});

}  // namespace stickslip

// Plots of a run, rendered by gnuplot (Debian gnuplot-nox) as PNG and SVG. The data and the
// gnuplot script are written next to the pictures (frf.dat, frf.gp), so users can restyle them.
// A missing gnuplot gives a warning (return false), never a failure.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cli/results_files.h"

namespace stickslip {

struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  std::string style = "lines lw 2";  // gnuplot "with" clause, e.g. "points pt 6 ps 1.2"
};

// One plot with several curves; writes <stem>.dat, <stem>.gp, <stem>.png, <stem>.svg into dir.
// Returns false (and sets *warning) if gnuplot is missing or fails.
bool plot_curves(const std::filesystem::path& dir, const std::string& stem,
                 const std::string& title, const std::string& xlabel, const std::string& ylabel,
                 const std::vector<PlotSeries>& series, std::string* warning);

// Runs gnuplot on an existing <stem>.gp in dir (re-rendering a plot); false + warning if not.
bool render_plot_script(const std::filesystem::path& dir, const std::string& stem,
                        std::string* warning);

using WarnFn = std::function<void(const std::string&)>;

// Amplitude of the first dynamic harmonic of each output.frf DOF over the converged points,
// labelled "<prefix><body> node <id> <axis>".
std::vector<PlotSeries> frf_series(const SolveResults& results, const std::string& prefix);

// The plots of one solve folder, from its files: frf (the FRF DOFs of summary.json),
// contact_state (mean stick / slip / separation fractions over the pairs along the sweep) and
// hysteresis (first local axis of the histories.csv pairs at the most dissipative point).
void plot_solve_results(const std::filesystem::path& dir, const SolveResults& results,
                        const std::vector<PlotSeries>& frf, const WarnFn& warn);

// The thesis's validation plot frf_full_vs_reduced: the reduced nonlinear FRF curves and the
// full-model recovery at the recovered points (drawn when there are at least two).
void plot_full_vs_reduced(const std::filesystem::path& dir, const std::string& title,
                          const std::vector<PlotSeries>& frf,
                          const std::vector<PlotSeries>& full_frf, const WarnFn& warn);

// The overlay frf_study of a study's FRF curves (the frf_series of every study folder, labelled
// by folder), titled "<title>: <parameter>".
void plot_study(const std::filesystem::path& dir, const std::string& title,
                const std::string& parameter, const std::vector<PlotSeries>& overlay,
                const WarnFn& warn);

}  // namespace stickslip

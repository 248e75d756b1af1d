// Plots of a run, rendered by gnuplot (Debian gnuplot-nox) as PNG and SVG. The data and the
// gnuplot script are written next to the pictures (frf.dat, frf.gp), so users can restyle them.
// A missing gnuplot gives a warning (return false), never a failure.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

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

}  // namespace stickslip

#include "cli/plots.h"

#include <cstdlib>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "io/atomic_file.h"

namespace stickslip {
namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

bool plot_curves(const std::filesystem::path& dir, const std::string& stem,
                 const std::string& title, const std::string& xlabel, const std::string& ylabel,
                 const std::vector<PlotSeries>& series, std::string* warning) {
  // Data: one gnuplot index block per series.
  write_file_atomically((dir / (stem + ".dat")).string(), [&](std::ostream& out) {
    for (const PlotSeries& s : series) {
      fmt::print(out, "# {}\n", s.label);
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        fmt::print(out, "{:.10g} {:.10g}\n", s.x[i], s.y[i]);
      }
      out << "\n\n";
    }
  });
  std::string plot = "plot ";
  for (size_t i = 0; i < series.size(); ++i) {
    plot += fmt::format("{}{} index {} using 1:2 with {} title {}", i ? ", " : "",
                        quoted(stem + ".dat"), i, series[i].style, quoted(series[i].label));
  }
  write_file_atomically((dir / (stem + ".gp")).string(), [&](std::ostream& out) {
    fmt::print(out, "set title {}\nset xlabel {}\nset ylabel {}\nset grid\nset key outside\n",
               quoted(title), quoted(xlabel), quoted(ylabel));
    fmt::print(out, "set terminal pngcairo size 1000,600 noenhanced\nset output {}\n{}\n",
               quoted(stem + ".png"), plot);
    fmt::print(out, "set terminal svg size 1000,600 noenhanced\nset output {}\n{}\n",
               quoted(stem + ".svg"), plot);
  });
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
    *warning = "gnuplot not found: " + stem +
               ".png/.svg not drawn (install gnuplot-nox; the "
               "data and script are in " +
               (dir / (stem + ".gp")).string() + ")";
    return false;
  }
  const std::string cmd =
      "cd " + quoted(dir.string()) + " && gnuplot " + quoted(stem + ".gp") + " > /dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    *warning = "gnuplot failed on " + (dir / (stem + ".gp")).string();
    return false;
  }
  return true;
}

}  // namespace stickslip

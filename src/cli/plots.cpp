#include "cli/plots.h"

#include <cmath>
#include <cstdlib>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "core/types.h"
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
  return render_plot_script(dir, stem, warning);
}

bool render_plot_script(const std::filesystem::path& dir, const std::string& stem,
                        std::string* warning) {
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

std::vector<PlotSeries> frf_series(const SolveResults& results, const std::string& prefix) {
  static const char* kAxes[3] = {"x", "y", "z"};
  std::vector<PlotSeries> out;
  const FrequencyResponse& fr = results.response;
  const int h = fr.harmonics.size() > 1 ? 1 : 0;
  for (const ResponseDofDefinition& r : results.frf) {
    const auto it = results.master.find(MasterDofKey{r.body, r.node, r.direction});
    if (it == results.master.end()) continue;
    PlotSeries s;
    s.label = fmt::format("{}{} node {} {}", prefix, r.body, r.node, kAxes[r.direction]);
    for (size_t i = 0; i < fr.points.size(); ++i) {
      if (!fr.points[i].converged) continue;
      s.x.push_back(rad_s_to_hz(fr.points[i].omega));
      s.y.push_back(std::abs(it->second(static_cast<Eigen::Index>(i), h)));
    }
    out.push_back(std::move(s));
  }
  return out;
}

void plot_solve_results(const std::filesystem::path& dir, const SolveResults& results,
                        const std::vector<PlotSeries>& frf, const WarnFn& warn) {
  std::string warning;
  const std::string title = results.title.empty() ? "stickslip" : results.title;
  if (!frf.empty() && !plot_curves(dir, "frf", title, "frequency (Hz)",
                                   "amplitude of harmonic 1 (m)", frf, &warning)) {
    warn(warning);
    return;
  }
  // Contact state along the sweep: mean fractions over all pairs.
  PlotSeries stick{"stick", {}, {}}, slip{"slip", {}, {}}, separation{"separation", {}, {}};
  for (const FrequencyPoint& p : results.response.points) {
    if (!p.converged || p.pairs.empty()) continue;
    double a = 0, b = 0, c = 0;
    for (const PairResponse& r : p.pairs) {
      a += r.cycle.stick_fraction;
      b += r.cycle.slip_fraction;
      c += r.cycle.separation_fraction;
    }
    const double n = static_cast<double>(p.pairs.size());
    const double f = rad_s_to_hz(p.omega);
    stick.x.push_back(f), stick.y.push_back(a / n);
    slip.x.push_back(f), slip.y.push_back(b / n);
    separation.x.push_back(f), separation.y.push_back(c / n);
  }
  if (!stick.x.empty() && !plot_curves(dir, "contact_state", title, "frequency (Hz)",
                                       "fraction of the cycle (mean over pairs)",
                                       {stick, slip, separation}, &warning)) {
    warn(warning);
  }
  // Hysteresis loops (first local axis) of the pairs with a sampled cycle, at the point that
  // dissipates most.
  int best = -1;
  double most = -1;
  for (size_t i = 0; i < results.response.points.size(); ++i) {
    const FrequencyPoint& p = results.response.points[i];
    const double e = dissipated_energy(p);
    if (p.converged && e > most) most = e, best = static_cast<int>(i);
  }
  if (best < 0) return;
  const FrequencyPoint& p = results.response.points[best];
  std::vector<PlotSeries> loops;
  for (size_t q = 0; q < p.pairs.size(); ++q) {
    const AftSamples& h = p.pairs[q].history;
    if (h.u.size() == 0) continue;
    PlotSeries s{fmt::format("pair {}", q), {}, {}};
    for (int j = 0; j <= h.u.cols(); ++j) {  // closed loop: repeat the first sample
      s.x.push_back(h.u(0, j % h.u.cols()));
      s.y.push_back(h.f(0, j % h.u.cols()));
    }
    loops.push_back(std::move(s));
  }
  if (!loops.empty() &&
      !plot_curves(dir, "hysteresis", fmt::format("{}: {:.6g} Hz", title, rad_s_to_hz(p.omega)),
                   "relative displacement, first local axis (m)",
                   "contact force, first local axis (N)", loops, &warning)) {
    warn(warning);
  }
}

void plot_full_vs_reduced(const std::filesystem::path& dir, const std::string& title,
                          const std::vector<PlotSeries>& frf,
                          const std::vector<PlotSeries>& full_frf, const WarnFn& warn) {
  if (full_frf.empty() || full_frf.front().x.size() < 2) return;
  std::vector<PlotSeries> both = frf;  // the same curves, relabelled
  for (PlotSeries& c : both) c.label = "reduced: " + c.label;
  both.insert(both.end(), full_frf.begin(), full_frf.end());
  std::string warning;
  if (!plot_curves(dir, "frf_full_vs_reduced", title, "frequency (Hz)",
                   "amplitude of harmonic 1 (m)", both, &warning)) {
    warn(warning);
  }
}

void plot_study(const std::filesystem::path& dir, const std::string& title,
                const std::string& parameter, const std::vector<PlotSeries>& overlay,
                const WarnFn& warn) {
  std::string warning;
  if (!plot_curves(dir, "frf_study", title + ": " + parameter, "frequency (Hz)",
                   "amplitude of harmonic 1 (m)", overlay, &warning)) {
    warn(warning);
  }
}

}  // namespace stickslip

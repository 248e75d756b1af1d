#include "cli/plots.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <complex>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/child_process.h"
#include "cli/interruption.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

// Text for one line of a gnuplot script or data file: control characters (newlines, tabs, escape
// sequences; a newline would end the command, a trailing backslash would continue it) become
// spaces.
std::string one_line(const std::string& s) {
  std::string out = s;
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return out;
}

// A gnuplot string constant that gnuplot takes literally. gnuplot substitutes backquoted commands
// (`...`, run by a shell) inside double-quoted strings but not inside single-quoted ones, where
// the only special character is the quote itself, written twice; macros (@name) are expanded in
// neither (checked with gnuplot 5.4; tests/cli/plot_safety_test.cpp). So: single quotes, quotes
// doubled, on one line.
std::string gp_string(const std::string& s) {
  std::string out = "'";
  for (char c : one_line(s)) {
    if (c == '\'') out += '\'';
    out += c;
  }
  return out + "'";
}

struct PlotSpec {
  std::string stem, title, xlabel, ylabel;
  std::vector<PlotSeries> series;
  // The script draws x · x_scale and y · y_scale (the .dat keeps SI values).
  double x_scale = 1.0, y_scale = 1.0;
  bool log_y = false;  // `set logscale y`
  bool log_x = false;  // `set logscale x`
};

// A length axis ("... (m)") in the unit that suits its largest value: m from 0.1 m, mm from
// 0.1 mm, µm from 0.1 µm, else nm; the label's "(m)" becomes that unit and the returned factor
// multiplies the data. Other axes are left alone (factor 1).
double length_axis(std::string& label, double largest) {
  const std::string metre = "(m)";
  if (label.size() < metre.size() || label.compare(label.size() - metre.size(), metre.size(), metre) != 0)
    return 1.0;
  struct Unit {
    const char* name;
    double factor;
  };
  static constexpr Unit kUnits[] = {{"m", 1.0}, {"mm", 1e3}, {"\xc2\xb5m", 1e6}, {"nm", 1e9}};
  Unit unit = kUnits[3];
  for (const Unit& u : kUnits) {
    if (largest * u.factor >= 0.1) {
      unit = u;
      break;
    }
  }
  const std::string name = unit.name;
  label.replace(label.size() - metre.size(), metre.size(), "(" + name + ")");
  return unit.factor;
}

// The gnuplot script of a plot reading `data` and drawing `png` and `svg` (our own file names).
std::string plot_script(const PlotSpec& p, const std::string& data, const std::string& png,
                        const std::string& svg) {
  std::string plot = "plot ";
  for (size_t i = 0; i < p.series.size(); ++i) {
    const std::string x = p.x_scale == 1.0 ? "1" : fmt::format("($1*{:g})", p.x_scale);
    const std::string y = p.y_scale == 1.0 ? "2" : fmt::format("($2*{:g})", p.y_scale);
    plot += fmt::format("{}{} index {} using {}:{} with {} title {}", i ? ", " : "",
                        gp_string(data), i, x, y, p.series[i].style, gp_string(p.series[i].label));
  }
  return fmt::format(
      "set title {}\nset xlabel {}\nset ylabel {}\nset grid\n{}set key outside\n"
      "set terminal pngcairo size 1000,600 noenhanced\nset output {}\n{}\n"
      "set terminal svg size 1000,600 noenhanced\nset output {}\n{}\nunset output\n",
      gp_string(p.title), gp_string(p.xlabel), gp_string(p.ylabel),
      std::string(p.log_y ? "set logscale y\n" : "") + (p.log_x ? "set logscale x\n" : ""),
      gp_string(png), plot, gp_string(svg), plot);
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A PNG that ends with its IEND chunk, an SVG that ends with </svg>: what gnuplot writes when it
// finishes (a full disk makes it stop early, often with exit status 0).
bool picture_complete(const fs::path& p) {
  const std::string b = file_bytes(p);
  if (p.extension() == ".png") {
    static const std::string kSignature("\x89PNG\r\n\x1a\n", 8);
    static const std::string kEnd("\0\0\0\0IEND\xae\x42\x60\x82", 12);
    return b.size() >= 20 && b.compare(0, 8, kSignature) == 0 &&
           b.compare(b.size() - 12, 12, kEnd) == 0;
  }
  size_t end = b.find_last_not_of(" \t\r\n");
  return end != std::string::npos && end + 1 >= 6 && b.compare(end + 1 - 6, 6, "</svg>") == 0;
}

// How long a killed gnuplot waits for this process's own interruption (the signal reaches both).
constexpr double kInterruptionGrace = 1.0;  // s

// Draws p's pictures from its data and script (already in dir): gnuplot runs in a TemporaryFolder
// of dir on a copy of the script whose data path is "../<stem>.dat"; the pictures are published
// only complete. Returns false after logging the pictures not drawn.
bool draw(const fs::path& dir, const PlotSpec& p, PlotLog* log) {
  const fs::path png = dir / (p.stem + ".png"), svg = dir / (p.stem + ".svg");
  const fs::path gnuplot = find_program("gnuplot");
  if (gnuplot.empty()) {
    log->gnuplot_absent("gnuplot not found: no .png/.svg pictures (install gnuplot-nox; the data "
                        "and scripts are in the .dat and .gp files)");
    return false;
  }
  TemporaryFolder tmp(dir);
  const std::string script = p.stem + ".gp";
  {
    const int fd = tmp.create_file(script, (dir / script).string());
    const std::string text =
        plot_script(p, "../" + p.stem + ".dat", p.stem + ".png", p.stem + ".svg");
    const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
    const int error = errno;
    ::close(fd);
    if (!ok) {
      throw InvalidInput({(tmp.path() / script).string(), 0, ""},
                         std::string("cannot write the gnuplot script: ") + std::strerror(error));
    }
  }
  const ChildOutcome outcome = run_program(gnuplot, {script}, tmp.path(), tmp.lock_descriptor());
  // gnuplot killed by Ctrl-C with us: no warning, the interruption ends the program.
  if (outcome.started && !outcome.exited) yield_to_interruption(kInterruptionGrace);
  std::string why;
  if (!outcome.started) {
    why = "gnuplot could not be started: " + outcome.message;
  } else if (!outcome.exited) {
    why = fmt::format("gnuplot was killed by signal {}", outcome.signal);
  } else if (outcome.exit_code != 0) {
    why = fmt::format("gnuplot failed (exit status {}){}", outcome.exit_code,
                      outcome.message.empty() ? "" : ": " + outcome.message);
  }
  bool all = true;
  for (const fs::path& picture : {png, svg}) {
    const fs::path drawn = tmp.path() / picture.filename();
    std::string reason = why;
    if (reason.empty() && !picture_complete(drawn)) {
      reason = "gnuplot left it incomplete (full disk?)" +
               (outcome.message.empty() ? std::string() : ": " + outcome.message);
    }
    if (reason.empty()) {
      publish_file(drawn, picture);
    } else {
      std::error_code ignored;
      fs::remove(picture, ignored);  // an older picture would not show this .dat
      log->failed(picture, reason);
      all = false;
    }
  }
  return all;
}

bool plot_spec(const fs::path& dir, const PlotSpec& p, PlotLog* log) {
  // Data: one gnuplot index block per series.
  write_file_atomically((dir / (p.stem + ".dat")).string(), [&](std::ostream& out) {
    for (const PlotSeries& s : p.series) {
      fmt::print(out, "# {}\n", one_line(s.label));
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (std::isnan(s.x[i])) {  // a break: gnuplot ends the line at a blank line
          out << "\n";
          continue;
        }
        fmt::print(out, "{:.10g} {:.10g}\n", s.x[i], s.y[i]);
      }
      out << "\n\n";
    }
  });
  write_file_atomically((dir / (p.stem + ".gp")).string(), [&](std::ostream& out) {
    out << plot_script(p, p.stem + ".dat", p.stem + ".png", p.stem + ".svg");
  });
  return draw(dir, p, log);
}

constexpr const char* kFullModelPrefix = "full model: ";
constexpr const char* kFullModelStyle = "points pt 6 ps 1.3";

}  // namespace

void PlotLog::failed(const fs::path& picture, const std::string& reason) {
  std::fprintf(stderr, "stickslip: warning: %s not drawn: %s\n", picture.string().c_str(),
               reason.c_str());
  missing_.push_back(picture.string());
}

void PlotLog::gnuplot_absent(const std::string& warning) {
  if (absent_reported_) return;
  absent_reported_ = true;
  std::fprintf(stderr, "stickslip: warning: %s\n", warning.c_str());
}

int plots_exit_code(const PlotLog& log, const fs::path& redraw_dir) {
  if (log.missing().empty()) return 0;
  std::string list;
  for (size_t i = 0; i < log.missing().size(); ++i) list += (i ? ", " : "") + log.missing()[i];
  std::fprintf(stderr,
               "stickslip: %zu picture(s) not drawn: %s; every other result is complete; redraw "
               "them with `stickslip plot %s`\n",
               log.missing().size(), list.c_str(), redraw_dir.string().c_str());
  return kExitPlotsMissing;
}

bool plot_curves(const fs::path& dir, const std::string& stem, const std::string& title,
                 const std::string& xlabel, const std::string& ylabel,
                 const std::vector<PlotSeries>& series, PlotLog* log, bool log_y, bool log_x) {
  PlotSpec spec{stem, title, xlabel, ylabel, series};
  double x_max = 0, y_max = 0;
  for (const PlotSeries& c : series) {
    for (double v : c.x) x_max = std::max(x_max, std::abs(v));
    for (double v : c.y) y_max = std::max(y_max, std::abs(v));
  }
  spec.x_scale = length_axis(spec.xlabel, x_max);
  spec.y_scale = length_axis(spec.ylabel, y_max);
  // gnuplot refuses a logarithmic axis on which no value is > 0 ("all points undefined").
  bool any_positive = false;
  for (const PlotSeries& c : series) {
    for (double v : c.y) any_positive |= v > 0;
  }
  spec.log_y = log_y && any_positive;
  bool all_x_positive = true;
  for (const PlotSeries& c : series) {
    for (double v : c.x) all_x_positive &= v > 0;
  }
  spec.log_x = log_x && all_x_positive;
  return plot_spec(dir, spec, log);
}

void redraw_full_vs_reduced(const fs::path& dir, const std::string& title, PlotLog* log,
                            const PlotOptions& options) {
  const fs::path data = dir / "frf_full_vs_reduced.dat";
  if (!fs::exists(data)) return;
  std::ifstream in(data);
  if (!in) throw InvalidInput({data.string(), 0, ""}, "cannot read this file");
  std::vector<PlotSeries> series;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    if (line.rfind("# ", 0) == 0) {
      PlotSeries s{line.substr(2), {}, {}};
      if (s.label.rfind(kFullModelPrefix, 0) == 0) s.style = kFullModelStyle;
      series.push_back(std::move(s));
      continue;
    }
    std::istringstream row(line);
    row.imbue(std::locale::classic());
    double x, y;
    std::string rest;
    if (series.empty() || !(row >> x >> y) || (row >> rest)) {
      throw InvalidInput({data.string(), number, ""},
                         "expected '# <label>' or two numbers (frequency, amplitude): run `stickslip "
                         "recover` again to rewrite it");
    }
    series.back().x.push_back(x);
    series.back().y.push_back(y);
  }
  plot_curves(dir, "frf_full_vs_reduced", title, "frequency (Hz)", "amplitude of harmonic 1 (m)",
              series, log, options.log_amplitude);
}

namespace {

// One series per output.frf DOF over the converged points: value(X1) of the first dynamic
// harmonic's complex coefficient, labelled "<prefix><body> node <id> <axis>".
std::vector<PlotSeries> frf_channels(const SolveResults& results, const std::string& prefix,
                                     const std::function<double(std::complex<double>)>& value) {
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
      s.y.push_back(value(it->second(static_cast<Eigen::Index>(i), h)));
    }
    out.push_back(std::move(s));
  }
  return out;
}

// Phase in degrees (x(t) = Re X e^{iΩt}: relative to a force of phase 0), unwrapped along the
// sweep so that a resonance shows as one continuous drop of 180° rather than a jump at ±180°.
std::vector<PlotSeries> frf_phase_series(const SolveResults& results) {
  std::vector<PlotSeries> out =
      frf_channels(results, "", [](std::complex<double> x) { return std::arg(x) * 180.0 / kPi; });
  for (PlotSeries& s : out) {
    for (size_t i = 1; i < s.y.size(); ++i) s.y[i] += 360.0 * std::round((s.y[i - 1] - s.y[i]) / 360.0);
  }
  return out;
}

// The forced response predicted from the nonlinear mode (snmt.csv; analysis.nonlinear_mode) for
// each FRF DOF, dashed, and the backbone it rests on (the mode's frequency against the same
// amplitude), dotted: x = frequency (Hz), y = |harmonic 1| (m).
std::vector<PlotSeries> predicted_frf_series(const SolveResults& results) {
  static const char* kAxes[3] = {"x", "y", "z"};
  std::vector<PlotSeries> out;
  const SolveResults::Prediction& pr = results.prediction;
  for (const ResponseDofDefinition& r : results.frf) {
    const auto it = pr.master.find(MasterDofKey{r.body, r.node, r.direction});
    if (it == pr.master.end()) continue;
    const std::string dof = fmt::format("{} node {} {}", r.body, r.node, kAxes[r.direction]);
    PlotSeries curve{"nonlinear mode prediction: " + dof, {}, {}, "lines lw 2 dt 2"};
    PlotSeries backbone{"backbone: " + dof, {}, {}, "lines lw 1 dt 3"};
    std::vector<std::pair<double, double>> along;  // (amplitude, mode frequency), sorted below
    for (size_t i = 0; i < pr.frequency_hz.size(); ++i) {
      const double a = std::abs(it->second[i]);
      curve.x.push_back(pr.frequency_hz[i]);
      curve.y.push_back(a);
      along.emplace_back(a, pr.mode_frequency_hz[i]);
    }
    std::sort(along.begin(), along.end());
    for (const auto& [a, hz] : along) {
      if (!backbone.y.empty() && a == backbone.y.back()) continue;  // both roots of one amplitude
      backbone.x.push_back(hz);
      backbone.y.push_back(a);
    }
    out.push_back(std::move(curve));
    out.push_back(std::move(backbone));
  }
  return out;
}

// The bifurcation markers of the FRF plot: one series per bifurcation type (black symbols), at the
// bifurcation's frequency and, for each FRF curve, its amplitude there.
std::vector<PlotSeries> bifurcation_markers(const SolveResults& results, size_t curves) {
  struct Kind {
    const char* type;
    const char* label;
    const char* style;
  };
  static constexpr Kind kKinds[] = {
      {"fold", "fold", "points pt 7 ps 1.6 lc rgb 'black'"},
      {"branch_point", "branch point", "points pt 13 ps 1.8 lc rgb 'black'"},
      {"period_doubling", "period doubling", "points pt 9 ps 1.8 lc rgb 'black'"},
      {"neimark_sacker", "Neimark-Sacker", "points pt 5 ps 1.6 lc rgb 'black'"}};
  std::vector<PlotSeries> out;
  for (const Kind& k : kKinds) {
    PlotSeries s{k.label, {}, {}, k.style};
    for (const SolvedBifurcation& b : results.bifurcations) {
      if (b.type != k.type) continue;
      for (size_t d = 0; d < curves && d < b.amplitude_m.size(); ++d) {
        if (std::isnan(b.amplitude_m[d])) continue;
        s.x.push_back(b.frequency_hz);
        s.y.push_back(b.amplitude_m[d]);
      }
    }
    if (!s.x.empty()) out.push_back(std::move(s));
  }
  return out;
}

// The FRF curves split by stability (analysis.stability): per curve a solid series over the
// stable points and a dashed one over the unstable points, in one colour. Where stability
// changes between two consecutive points the curve is split at the bifurcation located between
// them (summary.json) or else at the segment's midpoint, which ends one series and starts the
// other; a NaN in x is a break (plot_spec). Curves without stability are returned as they are.
// at_bifurcations false: always at the midpoint (the phase plot: summary.json has no phase).
std::vector<PlotSeries> frf_by_stability(const SolveResults& results,
                                         const std::vector<PlotSeries>& frf,
                                         bool at_bifurcations = true) {
  std::vector<int> index;  // the converged points, as frf_channels takes them
  bool any = false;
  for (size_t i = 0; i < results.response.points.size(); ++i) {
    const FrequencyPoint& p = results.response.points[i];
    if (!p.converged) continue;
    index.push_back(static_cast<int>(i));
    any = any || p.stability_computed;
  }
  if (!any) return frf;
  const auto stable = [&](size_t j) {
    const FrequencyPoint& p = results.response.points[index[j]];
    return !p.stability_computed || p.floquet.stable;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<PlotSeries> out;
  for (size_t d = 0; d < frf.size(); ++d) {
    const PlotSeries& c = frf[d];
    if (c.x.size() != index.size()) {  // not per converged point: drawn as it is
      out.push_back(c);
      continue;
    }
    PlotSeries solid{c.label, {}, {}, fmt::format("lines lw 2 lc {}", d + 1)};
    PlotSeries dashed{c.label + ", unstable (dashed: Floquet multiplier > 1)", {}, {},
                      fmt::format("lines lw 2 dt 2 lc {}", d + 1)};
    for (size_t j = 0; j < c.x.size(); ++j) {
      PlotSeries& here = stable(j) ? solid : dashed;
      here.x.push_back(c.x[j]);
      here.y.push_back(c.y[j]);
      if (j + 1 == c.x.size() || stable(j) == stable(j + 1)) continue;
      double fx = 0.5 * (c.x[j] + c.x[j + 1]), fy = 0.5 * (c.y[j] + c.y[j + 1]);
      for (const SolvedBifurcation& b : results.bifurcations) {
        if (at_bifurcations && b.point == index[j] && index[j + 1] == index[j] + 1 && d < b.amplitude_m.size() &&
            !std::isnan(b.amplitude_m[d])) {
          fx = b.frequency_hz, fy = b.amplitude_m[d];
          break;
        }
      }
      PlotSeries& next = stable(j + 1) ? solid : dashed;
      here.x.push_back(fx), here.y.push_back(fy);
      here.x.push_back(nan), here.y.push_back(nan);
      next.x.push_back(fx), next.y.push_back(fy);
    }
    for (PlotSeries* p : {&solid, &dashed}) {
      // No trailing break (a blank line before the block's end would read as an empty block).
      while (!p->x.empty() && std::isnan(p->x.back())) p->x.pop_back(), p->y.pop_back();
      if (!p->x.empty()) out.push_back(std::move(*p));
    }
  }
  return out;
}

}  // namespace

std::vector<PlotSeries> frf_series(const SolveResults& results, const std::string& prefix) {
  return frf_channels(results, prefix, [](std::complex<double> x) { return std::abs(x); });
}

void plot_solve_results(const std::filesystem::path& dir, const SolveResults& results,
                        const std::vector<PlotSeries>& frf, PlotLog* log,
                        const PlotOptions& options) {
  const std::string title = results.title.empty() ? "stickslip" : results.title;
  if (!frf.empty()) {
    std::vector<PlotSeries> curves = frf_by_stability(results, frf);
    for (PlotSeries& m : bifurcation_markers(results, frf.size())) curves.push_back(std::move(m));
    for (PlotSeries& m : predicted_frf_series(results)) curves.push_back(std::move(m));
    plot_curves(dir, "frf", title, "frequency (Hz)", "amplitude of harmonic 1 (m)", curves, log,
                options.log_amplitude);
    plot_curves(dir, "frf_phase", title, "frequency (Hz)", "phase of harmonic 1 (deg)",
                frf_by_stability(results, frf_phase_series(results), false), log);
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
  if (!stick.x.empty()) {
    plot_curves(dir, "contact_state", title, "frequency (Hz)",
                "fraction of the cycle (mean over pairs)", {stick, slip, separation}, log);
  }
  // Energy dissipated per cycle along the sweep: one curve per contact (the sum over its pairs),
  // and their total when there are several contacts.
  std::vector<PlotSeries> energy;
  std::map<std::string, size_t> energy_of_contact;
  for (const SolvedPairId& id : results.pairs) {
    if (energy_of_contact.emplace(id.contact, energy.size()).second) {
      energy.push_back(PlotSeries{id.contact, {}, {}});
    }
  }
  if (energy.size() > 1) energy.push_back(PlotSeries{"all contacts", {}, {}, "lines lw 3 dt 2"});
  for (const FrequencyPoint& p : results.response.points) {
    if (!p.converged || p.pairs.size() != results.pairs.size() || energy.empty()) continue;
    for (PlotSeries& s : energy) s.x.push_back(rad_s_to_hz(p.omega)), s.y.push_back(0.0);
    for (size_t q = 0; q < p.pairs.size(); ++q) {
      energy[energy_of_contact.at(results.pairs[q].contact)].y.back() +=
          p.pairs[q].cycle.dissipated_energy;
    }
    if (energy.size() > 1) energy.back().y.back() = dissipated_energy(p);
  }
  if (!energy.empty() && !energy.front().x.empty()) {
    plot_curves(dir, "dissipation", title, "frequency (Hz)", "energy dissipated per cycle (J)",
                energy, log);
  }
  // Hysteresis loops of the pairs with a sampled cycle (output.histories), at the point that
  // dissipates most: force against relative displacement along the first tangential axis t1 of
  // each pair's contact frame (1D laws: their one axis), and along t2 for 3D pairs.
  int best = -1;
  double most = -1;
  for (size_t i = 0; i < results.response.points.size(); ++i) {
    const FrequencyPoint& p = results.response.points[i];
    const double e = dissipated_energy(p);
    if (p.converged && e > most) most = e, best = static_cast<int>(i);
  }
  if (best < 0) return;
  const FrequencyPoint& p = results.response.points[best];
  size_t most_dissipative = 0;
  for (size_t q = 1; q < p.pairs.size(); ++q) {
    if (p.pairs[q].cycle.dissipated_energy > p.pairs[most_dissipative].cycle.dissipated_energy) {
      most_dissipative = q;
    }
  }
  const auto loops_on_axis = [&](int axis) {
    std::vector<PlotSeries> loops;
    for (size_t q = 0; q < p.pairs.size(); ++q) {
      const AftSamples& h = p.pairs[q].history;
      if (h.u.cols() == 0 || h.u.rows() <= axis) continue;
      // A 3D pair has rows t1, t2, n; a 1D law one row: t2 exists only with three rows.
      if (axis == 1 && h.u.rows() < 3) continue;
      std::string name = q < results.pairs.size()
                             ? fmt::format("{} pair {}", results.pairs[q].contact,
                                           results.pairs[q].pair)
                             : fmt::format("pair {}", q);
      if (q == most_dissipative && p.pairs[q].cycle.dissipated_energy > 0) {
        name += " (most dissipative)";
      }
      PlotSeries s{name, {}, {}};
      for (int j = 0; j <= h.u.cols(); ++j) {  // closed loop: repeat the first sample
        s.x.push_back(h.u(axis, j % h.u.cols()));
        s.y.push_back(h.f(axis, j % h.u.cols()));
      }
      loops.push_back(std::move(s));
    }
    return loops;
  };
  const std::string loop_title = fmt::format("{}: {:.6g} Hz", title, rad_s_to_hz(p.omega));
  const std::vector<PlotSeries> t1 = loops_on_axis(0);
  if (!t1.empty()) {
    plot_curves(dir, "hysteresis", loop_title,
                "relative displacement along t1 of the contact frame (m)",
                "contact force along t1 (N)", t1, log);
  }
  const std::vector<PlotSeries> t2 = loops_on_axis(1);
  if (!t2.empty()) {
    plot_curves(dir, "hysteresis_t2", loop_title,
                "relative displacement along t2 of the contact frame (m)",
                "contact force along t2 (N)", t2, log);
  }
}

void plot_full_vs_reduced(const std::filesystem::path& dir, const std::string& title,
                          const std::vector<PlotSeries>& frf,
                          const std::vector<PlotSeries>& full_frf, PlotLog* log,
                          const PlotOptions& options) {
  if (full_frf.empty() || full_frf.front().x.size() < 2) return;
  std::vector<PlotSeries> both = frf;  // the same curves, relabelled
  for (PlotSeries& c : both) c.label = "reduced: " + c.label;
  both.insert(both.end(), full_frf.begin(), full_frf.end());
  plot_curves(dir, "frf_full_vs_reduced", title, "frequency (Hz)", "amplitude of harmonic 1 (m)",
              both, log, options.log_amplitude);
}

void plot_study(const std::filesystem::path& dir, const std::string& title,
                const std::string& parameter,
                const std::vector<std::vector<PlotSeries>>& per_value, PlotLog* log,
                const PlotOptions& options) {
  // One colour per studied value, one dash type per FRF DOF: x and y of one value alike.
  std::vector<PlotSeries> overlay;
  for (size_t v = 0; v < per_value.size(); ++v) {
    for (size_t d = 0; d < per_value[v].size(); ++d) {
      PlotSeries s = per_value[v][d];
      s.style = fmt::format("lines lw 2 lc {} dt {}", v + 1, d % 5 + 1);
      overlay.push_back(std::move(s));
    }
  }
  if (overlay.empty()) return;
  plot_curves(dir, "frf_study", title + ": " + parameter, "frequency (Hz)",
              "amplitude of harmonic 1 (m)", overlay, log, options.log_amplitude);
}

}  // namespace stickslip

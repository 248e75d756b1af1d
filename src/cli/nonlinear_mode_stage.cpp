#include "cli/nonlinear_mode_stage.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cli/results_files.h"
#include "cli/stale_results.h"
#include "cli/summary_file.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "model/nonlinear_mode_case.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;
const char* kAxes[3] = {"x", "y", "z"};

void write_tables(const StageRun& run, const PreparedModel& model,
                  const SolvedNonlinearMode& solved) {
  const NonlinearModeResult& r = solved.result;
  const StudyColumns study = study_columns(run.definition, run.value);
  write_file_atomically((run.dir / "nonlinear_modes.csv").string(), [&](std::ostream& out) {
    out << "point,modal_amplitude,frequency_hz,damping_ratio,xi_per_s,converged,iterations,"
           "residual_m,residual_relative,dissipated_energy_j"
        << study.header << "\n";
    for (size_t i = 0; i < r.points.size(); ++i) {
      const NonlinearModePoint& p = r.points[i];
      fmt::print(out, "{},{},{},{},{},{},{},{},{},{}{}\n", i, p.amplitude, rad_s_to_hz(p.omega),
                 p.damping_ratio, p.xi, p.converged ? 1 : 0, p.iterations, p.residual_norm,
                 p.residual_norm / p.residual_scale, p.dissipated_energy, study.cells);
    }
  });
  write_file_atomically((run.dir / "nonlinear_mode_shapes.csv").string(), [&](std::ostream& out) {
    out << "point,body,node,axis,harmonic,real_m,imag_m" << study.header << "\n";
    for (size_t i = 0; i < r.points.size(); ++i) {
      const NonlinearModePoint& p = r.points[i];
      if (!p.converged) continue;
      for (const PreparedBody& body : model.bodies) {
        for (const auto& [key, g] : body.master_dof) {
          for (size_t h = 0; h < r.harmonics.size(); ++h) {
            const std::complex<double> x = p.master(g, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},{},{}{}\n", i, body.name, key.first, kAxes[key.second],
                       r.harmonics[h], x.real(), x.imag(), study.cells);
          }
        }
      }
    }
  });
}

void write_nonlinear_mode_summary(const StageRun& run, const PreparedModel& model,
                                  const SolvedNonlinearMode& solved,
                                  const std::vector<std::string>& removed, double seconds_total) {
  const CaseDefinition& def = run.definition;
  const NonlinearModeResult& r = solved.result;
  int converged = 0;
  double most_damping = -1, most_damping_amplitude = 0;
  for (const NonlinearModePoint& p : r.points) {
    if (!p.converged) continue;
    ++converged;
    if (p.damping_ratio > most_damping) {
      most_damping = p.damping_ratio;
      most_damping_amplitude = p.amplitude;
    }
  }
  Json summary = start_summary(run);
  summary["analysis"] = "nonlinear_mode";
  Json mode = {{"mode", r.mode},
               {"linear_frequency_hz", rad_s_to_hz(r.linear_omega)},
               {"linear_damping_ratio", r.linear_xi / (2 * r.linear_omega)},
               {"amplitude_start", def.analysis.amplitude.start},
               {"amplitude_stop", def.analysis.amplitude.stop}};
  if (converged > 0) {
    mode["largest_damping_ratio"] = most_damping;
    mode["largest_damping_amplitude"] = most_damping_amplitude;
  } else {
    mode["largest_damping_ratio"] = nullptr;
    mode["largest_damping_amplitude"] = nullptr;
  }
  summary["nonlinear_mode"] = mode;
  summary["reduced_dofs"] = model.num_dofs;
  summary["contact_pairs"] = model.pairs.size();
  summary["unknowns"] = solved.system->size() + 2;
  summary["points"] = r.points.size();
  summary["converged_points"] = converged;
  summary["completed"] = r.completed;
  summary["message"] = r.message;
  summary["aft"] = {{"method", case_name(def.analysis.aft)},
                    {"time_samples", def.analysis.time_samples}};
  finish_summary(summary, run, model, solved.seconds_solve, seconds_total, removed);
  write_summary(run.dir, summary);
}

void plot_nonlinear_mode(const StageRun& run, const SolvedNonlinearMode& solved, PlotLog* plots) {
  PlotSeries backbone;
  backbone.label = fmt::format("mode {}", solved.result.mode);
  PlotSeries damping = backbone;
  for (const NonlinearModePoint& p : solved.result.points) {
    if (!p.converged) continue;
    backbone.x.push_back(p.amplitude);
    backbone.y.push_back(rad_s_to_hz(p.omega));
    damping.x.push_back(p.amplitude);
    damping.y.push_back(p.damping_ratio);
  }
  if (backbone.x.empty()) return;
  const std::string title = run.definition.title.empty() ? "nonlinear mode" : run.definition.title;
  plot_curves(run.dir, "nonlinear_mode_backbone", title + ": backbone",
              "modal amplitude (sqrt(kg) m)", "frequency (Hz)", {backbone}, plots, false, true);
  plot_curves(run.dir, "nonlinear_mode_damping", title + ": modal damping ratio",
              "modal amplitude (sqrt(kg) m)", "damping ratio", {damping}, plots, false, true);
}

}  // namespace

SolveOutcome run_nonlinear_mode_stage(const StageRun& run, const PreparedModel& model,
                                      const ProgressFn& progress, ProgressReporter* reporter,
                                      PlotLog* plots, std::chrono::steady_clock::time_point t_run) {
  using Clock = std::chrono::steady_clock;
  SweepProgress sweep;
  if (reporter != nullptr) {
    sweep.start = [reporter](const std::string& label, int points) {
      reporter->start(label, points);
    };
    sweep.on_point = reporter->callback();
    sweep.finish = [reporter] { reporter->finish(); };
  }
  const SolvedNonlinearMode solved =
      solve_nonlinear_mode(model, run.definition, progress, reporter ? &sweep : nullptr);
  create_output_folder(run.dir);
  write_tables(run, model, solved);
  const auto t_plots = Clock::now();
  if (plots != nullptr && run.definition.output.plots) plot_nonlinear_mode(run, solved, plots);
  const double plots_s = std::chrono::duration<double>(Clock::now() - t_plots).count();
  const std::vector<std::string> removed = remove_stale_results(run.dir, ResultFamily::kEverything);
  if (!removed.empty()) progress(describe_removed(removed));
  write_nonlinear_mode_summary(run, model, solved, removed,
                               std::chrono::duration<double>(Clock::now() - t_run).count());
  SummaryTimings timings;
  timings.plots_s = plots_s;
  timings.total_s = std::chrono::duration<double>(Clock::now() - t_run).count();
  complete_summary(run.dir, timings);
  int failed = 0;
  for (const NonlinearModePoint& p : solved.result.points) failed += p.converged ? 0 : 1;
  progress(
      fmt::format("nonlinear mode {}: {} amplitudes ({} not converged) in {:.2f} s; results "
                  "in {}",
                  solved.result.mode, solved.result.points.size(), failed, solved.seconds_solve,
                  run.dir.string()));
  return SolveOutcome{.failed_points = failed};
}

}  // namespace stickslip

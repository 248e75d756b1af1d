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
  write_nonlinear_modes_table(run, r);
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

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

// The converged points of a nonlinear mode, its largest damping ratio (−1 if none) and where.
struct ModeTally {
  int converged = 0;
  double most_damping = -1, most_damping_amplitude = 0;
};
ModeTally tally(const NonlinearModeResult& r) {
  ModeTally t;
  for (const NonlinearModePoint& p : r.points) {
    if (!p.converged) continue;
    ++t.converged;
    if (p.damping_ratio > t.most_damping) {
      t.most_damping = p.damping_ratio;
      t.most_damping_amplitude = p.amplitude;
    }
  }
  return t;
}

void write_nonlinear_mode_summary(const StageRun& run, const PreparedModel& model,
                                  const SolvedNonlinearMode& solved,
                                  const std::vector<std::string>& removed, double seconds_total) {
  const CaseDefinition& def = run.definition;
  const NonlinearModeResult& r = solved.result;
  const auto [converged, most_damping, most_damping_amplitude] = tally(r);
  Json summary = start_summary(run);
  summary["analysis"] = "nonlinear_mode";
  Json mode = {{"mode", r.mode},
               {"linear_frequency_hz", rad_s_to_hz(r.linear_omega)},
               {"linear_damping_ratio", r.linear_xi / (2 * r.linear_omega)},
               {"first_slip_amplitude", finite_or_null(r.first_slip_amplitude)},
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
  PlotSeries slipping{"pairs slipping over part of the cycle", {}, {}};
  PlotSeries slip{"mean fraction of the cycle in slip", {}, {}};
  PlotSeries separating{"pairs separating over part of the cycle", {}, {}};
  for (const NonlinearModePoint& p : solved.result.points) {
    if (!p.converged) continue;
    backbone.x.push_back(p.amplitude);
    backbone.y.push_back(rad_s_to_hz(p.omega));
    damping.x.push_back(p.amplitude);
    damping.y.push_back(p.damping_ratio);
    for (PlotSeries* s : {&slipping, &slip, &separating}) s->x.push_back(p.amplitude);
    slipping.y.push_back(p.pairs_slipping);
    slip.y.push_back(p.mean_slip_fraction);
    separating.y.push_back(p.pairs_separating);
  }
  if (backbone.x.empty()) return;
  const std::string title = run.definition.title.empty() ? "nonlinear mode" : run.definition.title;
  plot_curves(run.dir, "nonlinear_mode_backbone", title + ": backbone",
              "modal amplitude (sqrt(kg) m)", "frequency (Hz)", {backbone}, plots, false, true);
  plot_curves(run.dir, "nonlinear_mode_damping", title + ": modal damping ratio",
              "modal amplitude (sqrt(kg) m)", "damping ratio", {damping}, plots, false, true);
  plot_curves(run.dir, "nonlinear_mode_contact_state", title + ": contact state",
              "modal amplitude (sqrt(kg) m)", "fraction", {slipping, slip, separating}, plots,
              false, true);
}

}  // namespace

void write_nonlinear_modes_table(const StageRun& run, const NonlinearModeResult& r) {
  const StudyColumns study = study_columns(run.definition, run.value);
  write_file_atomically((run.dir / "nonlinear_modes.csv").string(), [&](std::ostream& out) {
    out << "point,modal_amplitude,frequency_hz,damping_ratio,xi_per_s,converged,iterations,"
           "residual_m,residual_relative,dissipated_energy_j,pairs_slipping,pairs_separating,"
           "mean_slip_fraction"
        << study.header << "\n";
    for (size_t i = 0; i < r.points.size(); ++i) {
      const NonlinearModePoint& p = r.points[i];
      fmt::print(out, "{},{},{},{},{},{},{},{},{},{},{},{},{}{}\n", i, p.amplitude,
                 rad_s_to_hz(p.omega), p.damping_ratio, p.xi, p.converged ? 1 : 0, p.iterations,
                 p.residual_norm, p.residual_norm / p.residual_scale, p.dissipated_energy,
                 p.pairs_slipping, p.pairs_separating, p.mean_slip_fraction, study.cells);
    }
  });
}

void write_prediction_tables(const StageRun& run, const PreparedModel& model,
                             const SolvedCase& solved) {
  const NonlinearModeResult& mode = solved.mode;
  write_nonlinear_modes_table(run, mode);
  const StudyColumns study = study_columns(run.definition, run.value);
  write_file_atomically((run.dir / "snmt.csv").string(), [&](std::ostream& out) {
    out << "row,point,branch,modal_amplitude,frequency_hz,mode_frequency_hz,damping_ratio,"
           "phase_deg"
        << study.header << "\n";
    for (size_t i = 0; i < solved.prediction.size(); ++i) {
      const ForcedResponsePrediction& r = solved.prediction[i];
      const NonlinearModePoint& p = mode.points[r.point];
      fmt::print(out, "{},{},{},{},{},{},{},{}{}\n", i, r.point, r.above ? "above" : "below",
                 p.amplitude, rad_s_to_hz(r.omega), rad_s_to_hz(p.omega), p.damping_ratio,
                 r.phase * 180.0 / kPi, study.cells);
    }
  });
  write_file_atomically((run.dir / "snmt_response.csv").string(), [&](std::ostream& out) {
    out << "row,body,node,axis,harmonic,real_m,imag_m" << study.header << "\n";
    for (size_t i = 0; i < solved.prediction.size(); ++i) {
      const ForcedResponsePrediction& r = solved.prediction[i];
      for (const PreparedBody& body : model.bodies) {
        for (const auto& [key, g] : body.master_dof) {
          for (size_t h = 0; h < mode.harmonics.size(); ++h) {
            const std::complex<double> x = r.master(g, static_cast<int>(h));
            fmt::print(out, "{},{},{},{},{},{},{}{}\n", i, body.name, key.first, kAxes[key.second],
                       mode.harmonics[h], x.real(), x.imag(), study.cells);
          }
        }
      }
    }
  });
}

nlohmann::ordered_json prediction_summary(const CaseDefinition& def, const PreparedModel& model,
                                          const SolvedCase& solved) {
  const NonlinearModeResult& r = solved.mode;
  const auto [converged, most_damping, most_damping_amplitude] = tally(r);
  Json mode = {
      {"mode", r.mode},
      {"linear_frequency_hz", rad_s_to_hz(r.linear_omega)},
      {"linear_damping_ratio", r.linear_xi / (2 * r.linear_omega)},
      {"first_slip_amplitude", finite_or_null(r.first_slip_amplitude)},
      {"amplitude_start", def.analysis.amplitude.start},
      {"amplitude_stop", def.analysis.amplitude.stop},
      {"points", r.points.size()},
      {"converged_points", converged},
      {"largest_damping_ratio", converged > 0 ? Json(most_damping) : Json(nullptr)},
      {"largest_damping_amplitude", converged > 0 ? Json(most_damping_amplitude) : Json(nullptr)},
      {"prediction_points", solved.prediction.size()},
      {"solve_s", solved.seconds_mode}};
  // The predicted peak: the largest amplitude with a forced response (the roots below and above
  // ω(a) closest there; their mean frequency), and each output.frf DOF's amplitude there.
  int top = -1;
  for (const ForcedResponsePrediction& p : solved.prediction) top = std::max(top, p.point);
  Json peak = nullptr;
  if (top >= 0) {
    double sum = 0;
    int roots = 0;
    const ForcedResponsePrediction* at = nullptr;
    for (const ForcedResponsePrediction& p : solved.prediction) {
      if (p.point != top) continue;
      sum += p.omega;
      ++roots;
      at = &p;
    }
    const auto h1 = std::find(r.harmonics.begin(), r.harmonics.end(), 1) - r.harmonics.begin();
    Json dofs = Json::array();
    for (const ResponseDofDefinition& d : def.output.frf) {
      Json entry = {{"body", d.body}, {"node", d.node}, {"direction", kAxes[d.direction]}};
      const int b = model.body_index(d.body);
      const int g = b < 0 ? -1 : model.bodies[b].global_dof(d.node, d.direction);
      entry["amplitude_m"] = g >= 0 ? Json(std::abs(at->master(g, h1))) : Json(nullptr);
      dofs.push_back(entry);
    }
    peak = {{"point", top},
            {"modal_amplitude", r.points[top].amplitude},
            {"frequency_hz", rad_s_to_hz(sum / roots)},
            {"frf", dofs}};
  }
  mode["predicted_peak"] = peak;
  return mode;
}

void plot_nonlinear_mode_study(const fs::path& dir, const std::string& title,
                               const std::string& parameter, NonlinearModeOverlay overlay,
                               PlotLog* plots) {
  const auto by_value = [](const auto& a, const auto& b) { return a.first < b.first; };
  std::stable_sort(overlay.backbone.begin(), overlay.backbone.end(), by_value);
  std::stable_sort(overlay.damping.begin(), overlay.damping.end(), by_value);
  std::vector<PlotSeries> backbone, damping;
  for (auto& entry : overlay.backbone) {
    if (!entry.second.x.empty()) backbone.push_back(std::move(entry.second));
  }
  for (auto& entry : overlay.damping) {
    if (!entry.second.x.empty()) damping.push_back(std::move(entry.second));
  }
  if (backbone.empty()) return;
  const std::string head =
      (title.empty() ? std::string("nonlinear mode") : title) + ": " + parameter;
  plot_curves(dir, "nonlinear_mode_study_backbone", head + ", backbone",
              "modal amplitude (sqrt(kg) m)", "frequency (Hz)", backbone, plots, false, true);
  plot_curves(dir, "nonlinear_mode_study_damping", head + ", modal damping ratio",
              "modal amplitude (sqrt(kg) m)", "damping ratio", damping, plots, false, true);
}

SolveOutcome run_nonlinear_mode_stage(const StageRun& run, const PreparedModel& model,
                                      const ProgressFn& progress, ProgressReporter* reporter,
                                      PlotLog* plots, std::chrono::steady_clock::time_point t_run,
                                      NonlinearModeOverlay* overlay) {
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
  if (overlay != nullptr) {
    PlotSeries backbone{run.folder, {}, {}}, damping{run.folder, {}, {}};
    for (const NonlinearModePoint& p : solved.result.points) {
      if (!p.converged) continue;
      backbone.x.push_back(p.amplitude);
      backbone.y.push_back(rad_s_to_hz(p.omega));
      damping.x.push_back(p.amplitude);
      damping.y.push_back(p.damping_ratio);
    }
    overlay->backbone.emplace_back(run.value, std::move(backbone));
    overlay->damping.emplace_back(run.value, std::move(damping));
  }
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

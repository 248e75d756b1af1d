// The nonlinear-mode analysis of `run` and `solve` (`analysis.method: nonlinear_mode`,
// docs/case-file.md): solved through the model layer (model/nonlinear_mode_case.h), its files
// written atomically (docs/output-files.md, "Nonlinear modes"): nonlinear_modes.csv (amplitude,
// frequency, damping ratio, ξ per point), nonlinear_mode_shapes.csv (the master-DOF harmonics at
// every point), summary.json (its `nonlinear_mode` entry) and, with plots, the backbone
// (frequency against modal amplitude) and the damping ratio against modal amplitude. The
// frequency-response files of an earlier run in the folder are removed (cli/stale_results.h).
// There is no full-model recovery of a nonlinear mode.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "model/case_model.h"

namespace stickslip {

// nonlinear_modes.csv of a nonlinear mode (docs/output-files.md, "Nonlinear modes").
void write_nonlinear_modes_table(const StageRun& run, const NonlinearModeResult& mode);
// A forced response with analysis.nonlinear_mode (solved.mode, solved.prediction): its
// nonlinear_modes.csv, snmt.csv and snmt_response.csv (docs/output-files.md, "Forced response
// predicted from a nonlinear mode"), and summary.json's `nonlinear_mode` entry.
void write_prediction_tables(const StageRun& run, const PreparedModel& model,
                             const SolvedCase& solved);
nlohmann::ordered_json prediction_summary(const CaseDefinition& definition,
                                          const PreparedModel& model, const SolvedCase& solved);

// The curves of a study's nonlinear modes, one per studied value (labelled by its folder), for
// the overlays nonlinear_mode_study_backbone and nonlinear_mode_study_damping.
struct NonlinearModeOverlay {
  std::vector<std::pair<double, PlotSeries>> backbone, damping;  // (studied value, curve)
};
// Draws the overlays into dir (nothing when there are no curves), the curves in the order of the
// studied value, titled "<title>: <parameter>".
void plot_nonlinear_mode_study(const std::filesystem::path& dir, const std::string& title,
                               const std::string& parameter, NonlinearModeOverlay overlay,
                               PlotLog* plots);

// `plots` null: no plots (`solve`); else the case's output.plots decides. t_run: when this
// folder's analysis started (summary.json total_s). overlay (may be null): receives this
// folder's backbone and damping curves. Returns the points that failed.
SolveOutcome run_nonlinear_mode_stage(const StageRun& run, const PreparedModel& model,
                                      const ProgressFn& progress, ProgressReporter* reporter,
                                      PlotLog* plots, std::chrono::steady_clock::time_point t_run,
                                      NonlinearModeOverlay* overlay = nullptr);

}  // namespace stickslip

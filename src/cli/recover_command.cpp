// `stickslip recover CASE -o DIR [--point N|peak|all]`: the full-model recovery (cli/
// recovery_stage.h) of points of a solve whose files are in DIR. The master-DOF harmonics of the
// reduced model are rebuilt from the contact forces in contact_forces.csv exactly as the solve
// made them (HarmonicBalanceSystem::master_response), so the recovery equals run's to round-off.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "cli/recovery_stage.h"
#include "cli/results_files.h"
#include "cli/stale_results.h"
#include "core/errors.h"
#include "hbm/harmonic_balance.h"
#include "io/case_file.h"

namespace stickslip {

namespace fs = std::filesystem;

namespace {
// Relative agreement required between the master response rebuilt from the contact forces and the
// one the solve wrote. Same formula and 17-digit forces: round-off (1e-15) when the reduced
// matrices are the solve's, ~1e-12 when they went through Harwell–Boeing text in between; an
// edited or mixed-up file differs at the percent level.
constexpr double kMasterConsistency = 1e-6;
}  // namespace

SolveResults read_stage_solve(const StageRun& run, const CaseDefinition& base,
                              const fs::path& out_dir) {
  const std::string hint = stage_hint("solve", base, out_dir);
  SolveResults results = read_solve_results(run.dir, hint);
  if (results.fingerprint.empty()) {
    throw InvalidInput({(run.dir / "summary.json").string(), 0, "fingerprint"},
                       "no fingerprint (written by an older stickslip): run `" + hint + "` again");
  }
  if (results.fingerprint != solve_fingerprint(run.definition)) {
    throw InvalidInput({(run.dir / "summary.json").string(), 0, "fingerprint"},
                       "the solve files in " + run.dir.string() +
                           " were made from a different case (or its mesh or matrix files "
                           "changed since): run `" +
                           hint + "` again");
  }
  return results;
}

void check_solve_matches_model(const SolveResults& results, const PreparedModel& model,
                               const CaseDefinition& def, const StageRun& run,
                               const std::string& hint) {
  const std::string path = (run.dir / "contact_forces.csv").string();
  bool same = results.pairs.size() == model.pairs.size();
  for (size_t q = 0; same && q < model.pairs.size(); ++q) {
    const SolvedPairId& s = results.pairs[q];
    const PreparedPair& m = model.pair_info[q];
    same = s.contact == def.contacts[m.contact].name && s.node_a == m.node_a_id &&
           s.node_b == m.node_b_id && s.local_rows == static_cast<int>(model.pairs[q].frame.rows());
  }
  if (!same) {
    throw InvalidInput({path, 0, ""}, fmt::format("the contact pairs of the file ({}) are not the "
                                                  "case's ({}): run `{}` again",
                                                  results.pairs.size(), model.pairs.size(), hint));
  }
  std::vector<int> harmonics{0};
  for (int h : def.analysis.harmonics) harmonics.push_back(h);
  if (results.response.harmonics != harmonics) {
    throw InvalidInput({path, 0, ""},
                       "the harmonics of the file are not the case's: run `" + hint + "` again");
  }
}

void rebuild_master_response(SolveResults& results, const PreparedModel& model, const StageRun& run,
                             const std::string& hint) {
  // The reduced model's response at every reduced DOF from the contact forces of the files.
  // A cyclic sector: the travelling wave's models (as `solve` made the files).
  const std::unique_ptr<HarmonicBalanceSystem> made =
      model.wave ? std::make_unique<HarmonicBalanceSystem>(model.linear, model.pairs,
                                                           model.excitation, model.hbm, *model.wave)
                 : std::make_unique<HarmonicBalanceSystem>(model.linear, model.pairs,
                                                           model.excitation, model.hbm);
  const HarmonicBalanceSystem& system = *made;
  // Its harmonics are 0 + analysis.harmonics, those of the files (check_solve_matches_model).
  FrequencyResponse& response = results.response;
  const int nh = static_cast<int>(response.harmonics.size());
  for (size_t i = 0; i < response.points.size(); ++i) {
    FrequencyPoint& p = response.points[i];
    Eigen::MatrixXcd f(system.contact_rows(), nh),
        u = Eigen::MatrixXcd::Zero(system.contact_rows(), nh);
    for (size_t q = 0; q < p.pairs.size(); ++q) {
      f.middleRows(system.pair_row(static_cast<int>(q)), p.pairs[q].force_local.rows()) =
          p.pairs[q].force_local;
    }
    if (system.holds_rigid_modes()) {
      // A body held by its contacts: the static response needs the contact displacements,
      // u = R (x_A − x_B) from master_response.csv (missing rows are refused below).
      Eigen::MatrixXcd x = Eigen::MatrixXcd::Zero(model.num_dofs, nh);
      for (const PreparedBody& body : model.bodies) {
        for (const auto& [key, g] : body.master_dof) {
          const auto it = results.master.find(MasterDofKey{body.name, key.first, key.second});
          if (it != results.master.end()) x.row(g) = it->second.row(static_cast<Eigen::Index>(i));
        }
      }
      for (size_t q = 0; q < model.pairs.size(); ++q) {
        const ContactPair& pair = model.pairs[q];
        const int row = system.pair_row(static_cast<int>(q));
        for (int d = 0; d < static_cast<int>(pair.frame.cols()); ++d) {
          for (int c = 0; c < nh; ++c) {
            std::complex<double> rel = 0.0;
            if (!pair.dofs_a.empty()) rel += x(pair.dofs_a[d], c);
            if (!pair.dofs_b.empty()) rel -= x(pair.dofs_b[d], c);
            u.block(row, c, pair.frame.rows(), 1) +=
                pair.frame.col(d).cast<std::complex<double>>() * rel;
          }
        }
      }
    }
    p.master = system.master_response(f, p.omega, system.holds_rigid_modes() ? &u : nullptr);
  }
  // The rebuilt response must be the one the solve wrote (master_response.csv): a file edited
  // or mixed from another solve would otherwise be recovered silently.
  for (const PreparedBody& body : model.bodies) {
    for (const auto& [key, g] : body.master_dof) {
      const auto it = results.master.find(MasterDofKey{body.name, key.first, key.second});
      if (it == results.master.end()) {
        throw InvalidInput(
            {(run.dir / "master_response.csv").string(), 0, ""},
            fmt::format("no rows for body {} node {}: run `{}` again", body.name, key.first, hint));
      }
      for (size_t i = 0; i < response.points.size(); ++i) {
        const Eigen::VectorXcd rebuilt = response.points[i].master.row(g).transpose();
        const Eigen::VectorXcd written = it->second.row(static_cast<Eigen::Index>(i)).transpose();
        const double scale = response.points[i].master.cwiseAbs().maxCoeff();
        if ((rebuilt - written).cwiseAbs().maxCoeff() > kMasterConsistency * scale) {
          throw InvalidInput(
              {(run.dir / "master_response.csv").string(), 0, ""},
              fmt::format("point {}, body {} node {}: the response does not follow from the "
                          "contact forces of contact_forces.csv (files of different solves?): "
                          "run `{}` again",
                          i, body.name, key.first, hint));
        }
      }
    }
  }
}

int run_recover(const RecoverCommand& command) {
  const CaseDefinition base = read_case_file(command.stage.case_file);
  // Only bodies given by a mesh have a full model to recover; a case of matrix bodies alone would
  // otherwise "recover" its points into empty files.
  if (std::none_of(base.bodies.begin(), base.bodies.end(), [](const auto& named) {
        return named.second.source == BodyDefinition::Source::kMesh;
      })) {
    throw InvalidInput(base.where("bodies"),
                       "recover needs a body given by a mesh: every body of this case is given by "
                       "reduced matrices, which have no full model (the contact forces of "
                       "contact_forces.csv are the loads to apply in the program the matrices "
                       "came from)");
  }
  const bool quiet = command.stage.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  const fs::path out_dir = stage_output_dir(base, command.stage.output_dir);
  const std::string hint = stage_hint("solve", base, out_dir);
  ModelCache cache;  // meshes, reductions and full matrices shared by the study's analyses
  PlotLog plots;
  for (const StageRun& stage_run : stage_runs(base, out_dir)) {
    StageRun run = stage_run;
    if (command.point == "peak") run.definition.recovery.points = RecoveryPoints::kPeak;
    if (command.point == "all") run.definition.recovery.points = RecoveryPoints::kAll;
    const CaseDefinition& def = run.definition;
    if (!run.folder.empty()) progress("study: " + run.folder);
    SolveResults results = read_stage_solve(run, base, out_dir);
    // Point numbers are checked before the (possibly long) model preparation.
    std::vector<int> listed;
    if (!command.point.empty() && command.point != "peak" && command.point != "all") {
      listed = numbered_points(command.point, results.response, (run.dir / "points.csv").string());
    }
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.stage.case_file, /*full_matrices=*/true, progress,
                            /*load_basis_if_present=*/false, &cache);
    check_solve_matches_model(results, model, def, run, hint);
    rebuild_master_response(results, model, run, hint);
    FrequencyResponse& response = results.response;
    const std::vector<int> points = listed.empty() ? recovery_points(def, model, response) : listed;
    if (points.empty()) {
      progress(std::string("nothing to recover (recovery.points: ") +
               case_name(def.recovery.points) + ")");
      continue;
    }
    std::vector<PlotSeries> full_frf;
    run_recovery(run.dir, def, model, response, points, progress, &full_frf, run.value);
    if (def.output.plots) {
      const auto frf = frf_series(results, run.folder.empty() ? "" : run.folder + ": ");
      plot_full_vs_reduced(run.dir, def.title, frf, full_frf, &plots,
                           PlotOptions{def.output.log_amplitude});
    }
    const std::vector<std::string> removed = remove_stale_results(run.dir, ResultFamily::kRecovery);
    if (!removed.empty()) progress(describe_removed(removed));
    progress(fmt::format("recovered {} point(s); results in {}", points.size(), run.dir.string()));
  }
  return plots_exit_code(plots, out_dir);
}

}  // namespace stickslip

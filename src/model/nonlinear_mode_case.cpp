#include "model/nonlinear_mode_case.h"

#include <chrono>
#include <cmath>
#include <string>

#include <fmt/core.h>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {

std::vector<double> nonlinear_mode_amplitudes(const AmplitudeDefinition& amplitude) {
  std::vector<double> a(amplitude.points);
  const double l0 = std::log(amplitude.start), l1 = std::log(amplitude.stop);
  for (int i = 0; i < amplitude.points; ++i) {
    a[i] = std::exp(l0 + (l1 - l0) * i / (amplitude.points - 1.0));
  }
  a.front() = amplitude.start;  // exactly as given
  a.back() = amplitude.stop;
  return a;
}

namespace {
// The case key of the mode's `mode`, `amplitude`: in analysis itself (method nonlinear_mode) or
// in analysis.nonlinear_mode (a forced response's prediction).
std::string mode_key(const CaseDefinition& def, const std::string& key) {
  return def.analysis.method == SweepMethod::kNonlinearMode ? "analysis." + key
                                                            : "analysis.nonlinear_mode." + key;
}
}  // namespace

void check_mode_prediction(const PreparedModel& model, const CaseDefinition& def) {
  if (!def.analysis.predict_from_mode) return;
  const auto it = model.excitation.harmonics.find(1);
  if (it == model.excitation.harmonics.end() || it->second.cwiseAbs().maxCoeff() == 0) {
    throw InvalidInput(def.where("analysis.nonlinear_mode"),
                       "the case has no excitation of harmonic 1: there is no forced response to "
                       "predict from the nonlinear mode (add an `excitation` entry, or use "
                       "`method: nonlinear_mode` for the mode alone)");
  }
}

void predict_from_nonlinear_mode(const PreparedModel& model, const CaseDefinition& def,
                                 const ProgressFn& progress, const SweepProgress* sweep,
                                 SolvedCase& solved) {
  SolvedNonlinearMode mode = solve_nonlinear_mode(model, def, progress, sweep);
  solved.prediction = predict_forced_response(mode.result, model.excitation.harmonics.at(1));
  solved.mode = std::move(mode.result);
  solved.seconds_mode = mode.seconds_solve;
  if (progress) {
    int converged = 0;
    for (const NonlinearModePoint& p : solved.mode.points) converged += p.converged ? 1 : 0;
    progress(
        fmt::format("forced response predicted from the nonlinear mode: {} points from {} "
                    "converged amplitudes in {:.2f} s",
                    solved.prediction.size(), converged, solved.seconds_mode));
  }
}

SolvedNonlinearMode solve_nonlinear_mode(const PreparedModel& model, const CaseDefinition& def,
                                         const ProgressFn& progress, const SweepProgress* sweep) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const AnalysisDefinition& an = def.analysis;
  const bool prediction = an.method != SweepMethod::kNonlinearMode;
  if (model.pairs.empty()) {
    throw InvalidInput(def.where(prediction ? "analysis.nonlinear_mode" : "analysis.method"),
                       "a model without contacts is linear: its modes are those `stickslip modes` "
                       "lists, there is no nonlinear mode to follow");
  }
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const int k = def.excitation[e].harmonic;
    if (k == 0 || (prediction && k == 1)) continue;
    model_warning(format_location(def.where(fmt::format("excitation[{}]", e))) +
                  (prediction
                       ? ": not used by the prediction from the nonlinear mode "
                         "(analysis.nonlinear_mode), which takes the excitation of harmonic 1"
                       : ": not used by analysis.method nonlinear_mode (a nonlinear mode is a "
                         "free vibration; static forces, harmonic 0, are kept)"));
  }
  Excitation excitation;  // static loads only
  const auto it = model.excitation.harmonics.find(0);
  if (it != model.excitation.harmonics.end()) excitation.harmonics[0] = it->second;
  SolvedNonlinearMode solved;
  solved.system =
      std::make_unique<HarmonicBalanceSystem>(model.linear, model.pairs, excitation, model.hbm);
  if (!solved.system->static_summary().converged() &&
      model.hbm.static_coupling == StaticCoupling::kUncoupled) {
    throw InvalidInput(
        def.where("analysis.static"),
        "the static contact problem did not converge: " + solved.system->static_summary().message);
  }
  const StuckModes modes = stuck_modes(*solved.system);
  if (an.mode > modes.omega2.size()) {
    throw InvalidInput(def.where(mode_key(def, "mode")),
                       fmt::format("mode {} out of range: the stuck assembly has {} modes", an.mode,
                                   modes.omega2.size()));
  }
  solved.stuck_mode_hz = std::sqrt(std::max(modes.omega2[an.mode - 1], 0.0)) / (2 * kPi);
  solved.amplitudes = nonlinear_mode_amplitudes(an.amplitude);
  NonlinearModeOptions options;
  options.mode = an.mode;
  options.amplitudes = solved.amplitudes;
  options.newton.tolerance = an.tolerance;
  options.newton.max_iterations = an.max_iterations;
  if (progress) {
    progress(
        fmt::format("nonlinear mode {} of the stuck assembly ({:.6g} Hz): {} amplitudes from "
                    "{:.6g} to {:.6g}, {} unknowns",
                    an.mode, solved.stuck_mode_hz, solved.amplitudes.size(), an.amplitude.start,
                    an.amplitude.stop, solved.system->size() + 2));
  }
  if (sweep && sweep->start) sweep->start("nonlinear mode", an.amplitude.points);
  if (sweep && sweep->on_point) options.on_point = sweep->on_point;
  if (progress) {
    const double a_slip = first_slip_amplitude(*solved.system, modes.eta.col(an.mode - 1));
    progress(std::isfinite(a_slip)
                 ? fmt::format("the first contact pair slips at a modal amplitude of about {:.4g} "
                               "(estimated from the stuck mode)",
                               a_slip)
                 : std::string("no friction pair moves in this mode"));
  }
  try {
    solved.result = nonlinear_mode(*solved.system, options);
  } catch (const InvalidInput& e) {  // the library names its option: say the case's key
    throw InvalidInput(def.where(mode_key(def, "mode")), e.message());
  }
  if (sweep && sweep->finish) sweep->finish();
  solved.seconds_solve = std::chrono::duration<double>(Clock::now() - t0).count();
  return solved;
}

}  // namespace stickslip

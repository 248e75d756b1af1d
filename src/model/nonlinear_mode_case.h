// The nonlinear mode of a case (`analysis.method: nonlinear_mode`, docs/case-file.md): the harmonic
// balance of the prepared model without its dynamic excitation (static loads and preloads kept),
// and the EPMC continuation of the chosen stuck-assembly mode over the case's amplitudes
// (hbm/nonlinear_mode.h).
#pragma once

#include <memory>
#include <vector>

#include "hbm/nonlinear_mode.h"
#include "model/case_model.h"

namespace stickslip {

struct SolvedNonlinearMode {
  std::unique_ptr<HarmonicBalanceSystem> system;
  NonlinearModeResult result;
  std::vector<double> amplitudes;  // the requested modal amplitudes, √kg·m
  double stuck_mode_hz = 0.0;      // the followed mode's linear frequency
  double seconds_solve = 0.0;
};

// `amplitude.points` amplitudes evenly spaced in ln a from start to stop (both included).
std::vector<double> nonlinear_mode_amplitudes(const AmplitudeDefinition& amplitude);

// With analysis.nonlinear_mode in a forced response (predict_from_mode) the keys are
// analysis.nonlinear_mode.mode and .amplitude, and the case's harmonic-1 excitation is the force
// of the prediction (excitation of other harmonics ≥ 2 is not used by it: a warning).
// InvalidInput at `analysis.mode` when the model has fewer modes or the mode does not move the
// contacts, at `analysis.method` when the model has no contacts, at `analysis.static` when the
// static contact problem fails. A dynamic excitation in the case is not used: a warning
// (model_warning) names it. `progress` (may be null) gets one line per stage, `sweep` (may be null)
// the points.
SolvedNonlinearMode solve_nonlinear_mode(const PreparedModel& model,
                                         const CaseDefinition& definition,
                                         const ProgressFn& progress,
                                         const SweepProgress* sweep = nullptr);

// analysis.nonlinear_mode in a forced response: InvalidInput at that key when the case has no
// harmonic-1 excitation (there is nothing to predict a response to). Nothing otherwise.
void check_mode_prediction(const PreparedModel& model, const CaseDefinition& definition);

// analysis.nonlinear_mode in a forced response: solves the nonlinear mode (solve_nonlinear_mode)
// and predicts the forced response to the case's harmonic-1 excitation from it, into solved.mode,
// solved.prediction and solved.seconds_mode.
void predict_from_nonlinear_mode(const PreparedModel& model, const CaseDefinition& definition,
                                 const ProgressFn& progress, const SweepProgress* sweep,
                                 SolvedCase& solved);

}  // namespace stickslip

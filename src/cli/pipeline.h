// The `run` pipeline's view of the model layer (src/model): the model of a case is built there
// (model/case_model.h: bodies, reduction, reduced model, contact pairs, excitation, harmonic
// balance; model/body_reduction.h: where each body's reduced model comes from); the command line
// adds its progress reporter to the solve.
#pragma once

#include "cli/progress.h"
#include "model/body_reduction.h"
#include "model/case_model.h"

namespace stickslip {

// solve_case (model/case_model.h) with `reporter` (may be null) started with the number of
// points (stepped; 0 for continuation), updated after every frequency point and finished when
// the solve ends.
// `runner` (may be null): model/case_model.h.
SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& definition,
                      const ProgressFn& progress, ProgressReporter* reporter,
                      const SweepRunner* runner = nullptr);

}  // namespace stickslip

#include "cli/pipeline.h"

namespace stickslip {

SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& definition,
                      const ProgressFn& progress, ProgressReporter* reporter,
                      const SweepRunner* runner) {
  if (reporter == nullptr)
    return solve_case(model, definition, progress, static_cast<const SweepProgress*>(nullptr),
                      runner);
  SweepProgress sweep;
  sweep.start = [reporter](const std::string& label, int points) {
    reporter->start(label, points);
  };
  sweep.on_point = reporter->callback();
  sweep.finish = [reporter] { reporter->finish(); };
  return solve_case(model, definition, progress, &sweep, runner);
}

}  // namespace stickslip

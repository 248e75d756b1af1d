#include "hbm/frequency_response.h"

#include <span>
#include <string>

#include "core/errors.h"

namespace stickslip {

FrequencyPoint evaluate_point(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                              double omega, const std::vector<int>& history_pairs) {
  FrequencyPoint point;
  point.omega = omega;
  point.unknowns = x;
  Eigen::VectorXd forces;
  std::vector<CycleStatistics> stats;
  std::vector<AftSamples> samples;
  system.contact_forces(x, forces, &stats, history_pairs.empty() ? nullptr : &samples);
  const bool frozen = !system.unknown_harmonics().has_static();
  const Eigen::MatrixXcd u =
      system.to_complex(x, frozen ? system.static_displacement() : Eigen::VectorXd());
  const Eigen::MatrixXcd f =
      system.to_complex(forces, frozen ? system.static_force() : Eigen::VectorXd());
  point.master = system.master_response(f, omega);
  point.pairs.resize(system.pairs().size());
  for (size_t p = 0; p < system.pairs().size(); ++p) {
    const ContactPair& pair = system.pairs()[p];
    const int m = pair.element->dimension(), r = system.pair_row(static_cast<int>(p));
    PairResponse& out = point.pairs[p];
    out.displacement_local = u.middleRows(r, m);
    out.force_local = f.middleRows(r, m);
    out.force_global = pair.frame.transpose().cast<std::complex<double>>() * out.force_local;
    out.cycle = stats[p];
  }
  for (int p : history_pairs) point.pairs[p].history = samples[p];
  return point;
}

FrequencyResponse frequency_response(const HarmonicBalanceSystem& system,
                                     const FrequencyResponseOptions& options) {
  const int npairs = static_cast<int>(system.pairs().size());
  for (size_t i = 0; i < options.history_pairs.size(); ++i) {
    require(options.history_pairs[i] >= 0 && options.history_pairs[i] < npairs,
            "FrequencyResponseOptions.history_pairs[" + std::to_string(i) + "]",
            std::to_string(options.history_pairs[i]), "in [0, " + std::to_string(npairs) + ")");
  }
  ContinuationResult result;
  const bool stuck = options.initial_guess == InitialGuess::kLinearStuck;
  if (options.method == ContinuationMethod::kSteppedSweep) {
    require(!options.omegas.empty(), "FrequencyResponseOptions.omegas", "[]", "not empty");
    const Eigen::VectorXd x0 = system.linear_guess(options.omegas.front(), stuck);
    result = stepped_sweep(system, x0, std::span<const double>(options.omegas), options.sweep);
  } else {
    validate(options.arclength);
    const Eigen::VectorXd x0 = system.linear_guess(options.arclength.lambda_start, stuck);
    result = arclength_continuation(system, x0, options.arclength);
  }
  FrequencyResponse response;
  response.harmonics = system.output_harmonics();
  response.completed = result.completed;
  response.message = result.message;
  if (!system.static_summary().converged()) {
    response.message =
        "static problem: " + system.static_summary().message + "; " + response.message;
  }
  for (const ContinuationPoint& c : result.points) {
    FrequencyPoint point = evaluate_point(system, c.x, c.lambda, options.history_pairs);
    point.converged = c.newton.converged();
    point.iterations = c.newton.iterations;
    point.residual_norm = c.newton.residual_norm;
    point.message = c.newton.message;
    response.points.push_back(std::move(point));
  }
  return response;
}

}  // namespace stickslip

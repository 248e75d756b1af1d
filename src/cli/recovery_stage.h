// The recovery stage of `stickslip run` (docs/conventions.md, "Full-model recovery"): for the chosen
// frequency points, every body given by a mesh is loaded with the excitation, the static preload
// loads and the harmonic contact forces the nonlinear solve found (global axes, at the contact
// nodes), and solved as a linear harmonic problem on its FULL model (recovery.method: direct =
// sparse complex factorisation, modal = full-body modes + static residual correction,
// expansion = x = T q through the Craig–Bampton basis). Writes:
//   recovery_check.csv   point, frequency_hz, body, harmonic, reduced_max_m (largest reduced
//                        amplitude at the body's master DOFs, m), max_relative, rms_relative:
//                        full-model response at the master DOFs against the reduced
//                        nonlinear response (relative to the reduced one), max_absolute_m
//                        (largest |full − reduced|, m: the measure where the reduced response
//                        of a harmonic is zero and the relative ones are 0 or inf)
//   recovered_nodes.csv  point, body, node, axis, harmonic, real_m, imag_m (recovery.nodes)
//   reactions.csv        point, body, node, axis, harmonic, real_n, imag_n (held DOFs)
//   (with a study every table also has parameter, value)
//   recovery_p<point>_<body>.vtu  displacement and stress amplitudes per harmonic and the
//                        stress envelope over the period (von Mises max / alternating / mean,
//                        max principal) when output.vtu is true
//   recovery_envelope_<body>.vtu  the stress envelope over all recovered points (their maxima)
//   loads_p<point>_<body>.mac     ANSYS APDL macro with the point's loads (output.apdl_macro)
//   recovery_p<point>_<body>.inp  CalculiX deck reproducing the recovery (output.calculix_deck)
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cli/pipeline.h"
#include "cli/plots.h"
#include "io/case_file.h"
#include "model/recovery_loads.h"  // recovery_points, master_loads, recovery_loads, ...

namespace stickslip {

// The points named by a --point option: "peak", "all" (every converged point), a point number
// or a comma-separated list of them (each must exist and have converged; InvalidInput naming
// --point and points_csv otherwise).
std::vector<int> numbered_points(const std::string& spec, const FrequencyResponse& response,
                                 const std::string& points_csv);  // numbers only (no model needed)
std::vector<int> points_from_option(const std::string& spec, const CaseDefinition& definition,
                                    const PreparedModel& model, const FrequencyResponse& response,
                                    const std::string& points_csv);

// The APDL macro loads_p<point>_<body>.mac / the CalculiX deck recovery_p<point>_<body>.inp of
// one body at one point, in dir; returns the path written.
// `mesh` is the body's own mesh, or mapped_master_loads' mesh for a body given by matrices.
std::string write_apdl_loads(const std::filesystem::path& dir, const CaseDefinition& definition,
                             const std::string& body, const Mesh& mesh, int point,
                             double frequency_hz, const std::vector<int>& harmonics,
                             const Eigen::MatrixXcd& loads);
std::string write_calculix_loads(const std::filesystem::path& dir, const CaseDefinition& definition,
                                 const PreparedBody& body, int point, double frequency_hz,
                                 const std::vector<int>& harmonics, const Eigen::MatrixXcd& loads);

// Recovers `points` (indices into response.points; each converged, with master and
// pairs[q].force_global). full_frf (may be null) receives, per output.frf DOF of a mesh body,
// the full-model amplitude of the first dynamic harmonic at each recovered point. With a study,
// study_value (the folder's value) goes into the `value` column of the tables.
void run_recovery(const std::filesystem::path& dir, const CaseDefinition& definition,
                  const PreparedModel& model, const FrequencyResponse& response,
                  const std::vector<int>& points,
                  const std::function<void(const std::string&)>& progress,
                  std::vector<PlotSeries>* full_frf = nullptr, double study_value = 0.0);

}  // namespace stickslip

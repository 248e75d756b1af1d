// CalculiX (ccx 2.20) deck reproducing a full-model harmonic recovery
// (recovery/harmonic_response.h) of one body for one frequency point, so users can recover in their
// own FE code.
//
// What ccx offers: *STEADY STATE DYNAMICS is mode-based. It needs a preceding *FREQUENCY step
// with STORAGE=YES and superposes the stored modes, x = Σ_r φ_r φ_rᵀF / (ω_r² − ω² + i ω c_r),
// with Rayleigh damping c_r = α + β ω_r² from *MODAL DAMPING, RAYLEIGH; there is no static
// residual correction. It therefore matches stickslip's ModalRecovery with the same modes and
// residual_correction = false, and approaches the direct solution only as num_modes grows (the
// truncation error depends on the loads and frequency; it is not a fixed tolerance). Harmonic 0
// is an exact *STATIC step.
//
// Loads and convention: ccx's *CLOAD with LOAD CASE=1 is the real part and LOAD CASE=2 the
// imaginary part of F in f(t) = Re(F e^{iωt}), and it prints the real and then the imaginary
// part of the displacement for the same convention (checked against stickslip's modal solver in
// tests/recovery). That is docs/conventions.md's X_k = a_k − i b_k, so LOAD CASE=1 gets Re X_k =
// a_k and LOAD CASE=2 gets Im X_k = −b_k.
//
// Deck layout:
//   the mesh (io/inp_writer.h) plus the sets SS_NALL (all nodes), SS_EALL (all elements),
//   SS_FIXED (clamped nodes) and SS_OUT (output nodes: options.output_nodes, or all nodes),
//   *MATERIAL SS_MATERIAL (*ELASTIC E, ν; *DENSITY ρ), *SOLID SECTION on SS_EALL,
//   *BOUNDARY SS_FIXED, 1, 3 (all three directions), then one line per clamped DOF,
//   step 1  *FREQUENCY, STORAGE=YES with num_modes (only if a harmonic >= 1 is listed),
//   harmonic 0, if listed: *STATIC step, *CLOAD, OP=NEW,
//   every harmonic k >= 1 (in the order listed): *STEADY STATE DYNAMICS at k f .. k f (ccx
//   computes 2 data points at that single frequency and prints one result: real part block then
//   imaginary part block), *MODAL DAMPING, RAYLEIGH (,,α,β), *CLOAD, OP=NEW, LOAD CASE=1 (real),
//   *CLOAD, OP=NEW, LOAD CASE=2 (imaginary),
//   each load step: *NODE PRINT, NSET=SS_OUT U (the .dat file), *NODE FILE U and *EL FILE S
//   (the .frd file, ParaView/CGX).
// A node gets CLOAD lines for its three directions if any component is non-zero in that
// harmonic. Numbers are written in shortest round-trip decimal form. Node and element numbers are
// the mesh's external ids. Element types are those of the mesh (C3D8 for stickslip's
// kFull hex8 formulation; stickslip's MassIntegration::kStiffnessRule reproduces ccx's mass),
// except C3D8B (B-bar), which ccx lacks: written as C3D8, with a comment line saying so, and
// the pyramids C3D5 and C3D13, which ccx lacks too: written as the C3D8 and C3D20 they are
// (nodes 5-8, and for C3D20 also 13-16, = the apex; C3D13's nodes 10-13 as the C3D20's 17-20).
// Inputs: loads 3 num_nodes x nh, column j = harmonics[j], harmonic 0 real. Bad input throws
// InvalidInput naming the field and rule (also if the mesh already has a set named SS_*).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

struct CalculixDeckOptions {
  double youngs_modulus = 0.0;     // Pa, > 0
  double poisson_ratio = 0.0;      // -1 < nu < 0.5
  double density = 0.0;            // kg/m^3, > 0
  std::vector<int> clamped_nodes;  // node indices fixed in x, y, z
  std::vector<int> clamped_dofs;   // single DOFs fixed (3 node index + direction): supports
  double alpha = 0.0;              // C = alpha M + beta K: alpha in 1/s, >= 0
  double beta = 0.0;               // beta in s, >= 0
  double frequency_hz = 0.0;       // fundamental Ω/2π, > 0 when a harmonic >= 1 is listed
  std::vector<int> harmonics;      // harmonic of each load column (>= 0, unique)
  int num_modes = 100;             // modes of the *FREQUENCY step, >= 1
  std::vector<int> output_nodes;   // node indices printed to the .dat file; empty = all
};
void validate(const CalculixDeckOptions& options);

void write_calculix_deck(std::ostream& out, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                         const CalculixDeckOptions& options);
// Atomic file output (io/atomic_file.h).
void write_calculix_deck(const std::string& path, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                         const CalculixDeckOptions& options);

}  // namespace stickslip

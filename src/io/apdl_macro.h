// ANSYS APDL macro that applies the harmonic loads of one frequency point (excitation and contact
// forces, global axes, N) to the nodes of a full model and solves, so that users can recover
// stresses in ANSYS (the thesis's appendices A.3, B.1, B.2 did this with *DIM/*VFILL arrays; here
// every load is one F command).
//
// Convention. stickslip's harmonic k has the complex amplitude X_k = a_k − i b_k with
// x(t) = a_0 + Σ (a_k cos kΩt + b_k sin kΩt) = Re Σ X_k e^{ikΩt} (docs/conventions.md). ANSYS's
// harmonic load F,node,lab,VALUE,VALUE2 is F = (VALUE + i VALUE2) e^{iΩt}, physical part Re(F
// e^{iΩt}) (ANSYS theory: F1 = Fmax cos ψ, F2 = Fmax sin ψ, results "real" and "imaginary"
// likewise), so
//   VALUE = Re X_k = a_k  (cosine coefficient),   VALUE2 = Im X_k = −b_k  (minus the sine one).
// (The thesis's macro wrote the sine coefficient itself as VALUE2: with docs/conventions.md's
// convention that is the complex conjugate, i.e. a sign flip of every phase.)
//
// Layout of the macro (one line per item, numbers in shortest round-trip decimal form):
//   ! header comments (frequency, convention)
//   harmonic 0, if listed:  FINISH, /SOLU, ANTYPE,STATIC, FDELE,ALL,ALL, F,id,FX|FY|FZ,a_0 ...,
//                           SOLVE
//   harmonics k >= 1:       FINISH, /SOLU, ANTYPE,HARMIC, HROPT,FULL|MSUP[,n], HROUT,ON, KBC,1,
//                           NSUBST,1, ALPHAD,α, BETAD,β, then per harmonic (ascending order as
//                           listed): FDELE,ALL,ALL, HARFRQ,k f (FREQE blank: one frequency),
//                           F,id,FX|FY|FZ,Re,Im ..., SOLVE
//   FINISH
// A node gets its three F commands (FX, FY, FZ) if any of its components in that harmonic is
// non-zero; nodes in index order. Node numbers are the mesh's external ids (mesh.node_ids).
// Inputs: loads is 3 num_nodes x nh (DOF 3 node + direction), column j = harmonics[j]; harmonic
// 0's column must be real. Bad input throws InvalidInput naming the field and rule.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

struct ApdlMacroOptions {
  double frequency_hz = 0.0;   // fundamental Ω/2π, Hz, > 0 when a harmonic >= 1 is listed
  std::vector<int> harmonics;  // harmonic of each column of the loads (>= 0, unique)
  double alpha = 0.0;          // ALPHAD (mass-proportional damping, 1/s), >= 0
  double beta = 0.0;           // BETAD (stiffness-proportional damping, s), >= 0
  int msup_modes = 0;          // 0: HROPT,FULL; n > 0: HROPT,MSUP,n (needs a prior modal solve)
};
void validate(const ApdlMacroOptions& options);

void write_apdl_macro(std::ostream& out, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                      const ApdlMacroOptions& options);
// Atomic file output (io/atomic_file.h).
void write_apdl_macro(const std::string& path, const Mesh& mesh, const Eigen::MatrixXcd& loads,
                      const ApdlMacroOptions& options);

// Shortest decimal text that reads back to exactly v ("50", "-0.25", "1.2345e-07"); at most 24
// characters.
std::string shortest_decimal(double v);
// v in at most `width` characters (>= 12): shortest_decimal(v) when it fits (exact), else
// scientific notation with as many significant digits as fit ("-3.44206885217e-11"): with width
// 20, at least 13 significant digits (relative rounding error <= 5e-14). For fixed-width
// fields (CalculiX reads 20 characters a field).
std::string decimal_in_width(double v, int width);

}  // namespace stickslip

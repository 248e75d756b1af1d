// The Craig–Bampton reduction of one body over PETSc and SLEPc (docs/distributed-reduction.md):
// the reduced body of reduction/craig_bampton.h (same K_r, M_r, DOF map, eigenvalues and basis
// T, to round-off and the sign of each fixed-interface mode), computed by the plugin
// libstickslip_petsc.so (reduction/petsc_plugin_api.h) loaded with dlopen on first use.
//
// Where the plugin is looked for, in this order (the first that loads wins): the environment
// variable STICKSLIP_PETSC_PLUGIN, when set (then only there); libstickslip_petsc.so beside the
// program, then in ../lib/stickslip/ from there; the plugin of the build tree this code was built
// in. When none loads, PetscUnavailable lists each path and dlopen's reason.
//
// Collective: every process of MPI_COMM_WORLD must call it with the same body at once (each
// keeps its share of the interior rows in PETSc; every one gets the whole result); otherwise
// (the default) the process reduces alone. The interior must be held by the boundary and the
// constraints (K_ii positive definite): a floating interior is a failed summary, as a
// factorisation that fails. Costs (docs/performance.md): every process holds the assembled K and
// M whole (as given here) and its share of the factor, of the modes and of T's interior rows,
// then T whole.
#pragma once

#include <span>
#include <stdexcept>
#include <string>

#include "core/types.h"
#include "reduction/craig_bampton.h"

namespace stickslip {

// The plugin could not be loaded (the installation, not the input).
class PetscUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the PETSc reduction did, beside CraigBamptonSummary's phases.
struct PetscReductionInfo {
  int processes = 0;   // processes that shared the work
  std::string solver;  // the constraint modes' KSP+PC(factor), e.g. preonly+cholesky(mumps)
  int constraint_iterations = 0;    // Krylov iterations over all constraint modes (0: direct)
  int eigen_iterations = 0;         // SLEPc's iterations
  double max_eigen_residual = 0.0;  // SLEPc's largest relative residual of the kept modes
  long peak_rss_kb_max = 0;         // peak resident memory of the busiest process, KiB
  long peak_rss_kb_min = 0;         // and of the lightest
};

// Whether the plugin loads (false with the reason in *why).
bool petsc_reduction_available(std::string* why = nullptr);

// Whether the PETSc reductions of this process are collective over MPI_COMM_WORLD (set by the
// program when every process reduces the same bodies together; default false).
void set_petsc_reduction_collective(bool collective);
bool petsc_reduction_collective();

// As craig_bampton() (options.num_modes < n_i; options.modal is not used: SLEPc's settings are
// the plugin's, docs/distributed-reduction.md). Throws InvalidInput on bad input, PetscUnavailable
// when the plugin does not load; a failed solve is reported in the summary.
CraigBamptonResult craig_bampton_petsc(const SparseMatrix& K, const SparseMatrix& M,
                                       std::span<const int> constrained_dofs,
                                       std::span<const int> boundary_dofs,
                                       const CraigBamptonOptions& options,
                                       PetscReductionInfo* info = nullptr);

}  // namespace stickslip

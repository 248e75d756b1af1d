// The interface of the PETSc plugin libstickslip_petsc.so (src/reduction/petsc/): the
// Craig–Bampton reduction of one body over PETSc and SLEPc (docs/distributed-reduction.md),
// behind plain C types so that the program neither links nor includes PETSc, SLEPc or MPI. Loaded
// with dlopen only when a body asks for it (`reduction_solver: petsc`, model/petsc_reduction.h).
//
// With x_i = Φ_c x_b + Φ_n η (reduction/craig_bampton.h), K_ii Φ_c = −K_ib and
// K_ii Φ_n = M_ii Φ_n Ω², Φ_nᵀ M_ii Φ_n = I, the plugin returns the parts of
//   K_r = [K_bb + K_bi Φ_c, 0; 0, Ω²],  M_r = [M_bb + X + Xᵀ + Φ_cᵀ M_ii Φ_c, (M_bi + Φ_cᵀ M_ii)
//   Φ_n; ., I]
// (X = M_bi Φ_c) that need the interior: the caller adds K_bb and M_bb.
//
// Every process of the communicator calls reduce() with the same request (the whole interior
// rows: each process keeps only its own contiguous share of them in PETSc's distributed
// matrices) and gets the whole result.
#pragma once

#include <cstdint>

namespace stickslip {

inline constexpr int kPetscPluginAbi = 1;

// Rows of a sparse matrix in compressed-row form: 0-based, the columns of a row in any order.
struct PetscCsr {
  const std::int64_t* row_start = nullptr;  // rows + 1 entries
  const int* columns = nullptr;
  const double* values = nullptr;
};

struct PetscReductionRequest {
  int num_interior = 0;  // n_i
  int num_boundary = 0;  // n_b
  int num_modes = 0;     // m: the lowest fixed-interface modes, 0 <= m < n_i
  PetscCsr K_ii, M_ii;   // n_i x n_i, symmetric, both triangles
  PetscCsr K_ib, M_ib;   // n_i x n_b
  int collective = 0;    // 1: the processes of MPI_COMM_WORLD together; 0: this process alone
  int block_size = 64;   // constraint modes solved per block of right-hand sides
  int keep_basis = 1;    // 1: fill `basis`
};

struct PetscReductionResult {
  // Given by the caller, column-major, filled on every process.
  double* K_bb_add = nullptr;     // n_b x n_b: K_bi Φ_c
  double* M_bb_add = nullptr;     // n_b x n_b: X + Xᵀ + Φ_cᵀ M_ii Φ_c
  double* M_b_eta = nullptr;      // n_b x m: (M_bi + Φ_cᵀ M_ii) Φ_n
  double* eigenvalues = nullptr;  // m: Ω², ascending
  double* basis = nullptr;        // n_i x (n_b + m): [Φ_c Φ_n] (keep_basis only)
  // Filled by the plugin.
  int processes = 0;                // the processes that shared the work
  int constraint_iterations = 0;    // Krylov iterations of the constraint modes, all blocks
  int eigen_iterations = 0;         // SLEPc's outer iterations
  int eigen_converged = 0;          // eigenpairs converged (>= m on success)
  double seconds_constraint = 0.0;  // set-up, factorisation and solves of the constraint modes
  double seconds_modes = 0.0;       // the fixed-interface eigen-solve
  double seconds_projection = 0.0;  // the reduced matrices and the basis
  double max_eigen_residual = 0.0;  // max ‖K_ii φ − λ M_ii φ‖ / (|λ| ‖M_ii φ‖) (SLEPc's error)
  long peak_rss_kb_max = 0;  // peak resident memory of the busiest process, KiB
  long peak_rss_kb_min = 0;  // and of the lightest
  char solver[128] = {0};    // e.g. "preonly+cholesky(mumps)" or "cg+gamg"
};

struct PetscPluginApi {
  int abi = kPetscPluginAbi;
  // 0 on success; otherwise last_error() says why. Collective over the request's processes.
  int (*reduce)(const PetscReductionRequest* request, PetscReductionResult* result) = nullptr;
  const char* (*last_error)() = nullptr;
};

}  // namespace stickslip

// The plugin's entry point.
extern "C" const stickslip::PetscPluginApi* stickslip_petsc_plugin_api();

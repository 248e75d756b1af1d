// Benchmark of assembly and modal analysis on structured 8-node hexahedral meshes (issue 2).
//
// A box with the proportions of the reference beam (0.25 x 0.05 x 0.03 m, steel), nx x ny x nz
// C3D8I elements (nx : ny : nz ≈ 5 : 1 : 0.6), clamped at x = 0, or one of two slender 1M-DOF
// shapes whose nested-dissection separators are small (a rod's cross-section, a plate's line):
//   rod:   2.75 x 0.04 x 0.04 m, 1100 x 16 x 16 C3D8I (954k DOFs; recovery_bench's large rod),
//   plate: a blade-like plate 0.24 x 0.12 x 0.006 m, 400 x 200 x 4 C3D8I (1.21M DOFs),
// both clamped at x = 0. For each size it times:
// mesh generation, assembly of K and M (fe/assembly.h, both triangles), elimination of the clamped
// DOFs (DofMap), and solve_modes for the lowest 60 modes (factorisation and Lanczos separately).
//
// Usage: modal_bench [small|medium|large|rod|plate|<nx> <ny> <nz>] [num_modes] [max_factor_gb]
//                    [block] [probe]
//   probe (default 1): 0 skips the separate factorisation and single-solve timings before the
//   modal solve (they cost one extra factorisation).
//   small ≈ 10k DOFs, medium ≈ 100k DOFs, large ≈ 1M DOFs (box); rod, plate ≈ 1M DOFs. The modal
//   part is skipped when the Cholesky factor would exceed max_factor_gb (default 8 GB); its size is
//   printed anyway. Peak memory: run under /usr/bin/time -v (docs/performance.md has the commands
//   and the results).
// A plain main rather than Google Benchmark: each size runs once (the large one takes minutes)
// and peak memory is measured per process.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "linalg/modal.h"
#include "linalg/sparse_cholesky.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"

namespace {

using stickslip::ElementType;
using stickslip::Mesh;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A box of the given size (m), C3D8I; `clamped` gets the nodes of the face x = 0.
Mesh box_mesh(int nx, int ny, int nz, const Eigen::Vector3d& size, std::vector<int>* clamped) {
  Mesh mesh = structured_hex_box(nx, ny, nz, size, ElementType::kC3D8I);
  for (int n = 0; n < mesh.num_nodes(); n += nx + 1) clamped->push_back(n);  // i = 0
  return mesh;
}

// CPU seconds of this process (user + system, all threads): with the machine shared, wall time
// depends on the load; CPU time much less.
double cpu_seconds() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv) {
  int nx = 50, ny = 10, nz = 6;  // small: 11.8k DOFs
  Eigen::Vector3d size(0.25, 0.05, 0.03);
  std::string shape = "box";
  int arg = 1;
  if (argc > arg) {
    const std::string size_name = argv[arg];
    if (size_name == "small") {
      ++arg;
    } else if (size_name == "medium") {
      nx = 110, ny = 22, nz = 13;  // 107k DOFs
      ++arg;
    } else if (size_name == "large") {
      nx = 240, ny = 48, nz = 29;  // 1.06M DOFs
      ++arg;
    } else if (size_name == "rod") {
      nx = 1100, ny = 16, nz = 16;  // 954k DOFs
      size = Eigen::Vector3d(2.75, 0.04, 0.04);
      shape = "rod";
      ++arg;
    } else if (size_name == "plate") {
      nx = 400, ny = 200, nz = 4;  // 1.21M DOFs
      size = Eigen::Vector3d(0.24, 0.12, 0.006);
      shape = "plate";
      ++arg;
    } else if (argc > arg + 2) {
      nx = std::atoi(argv[arg]), ny = std::atoi(argv[arg + 1]), nz = std::atoi(argv[arg + 2]);
      arg += 3;
    }
  }
  const int num_modes = argc > arg ? std::atoi(argv[arg]) : 60;
  ++arg;
  // Largest factor (GB) the modal part may allocate; the machine is shared.
  const double max_factor_gb = argc > arg ? std::atof(argv[arg]) : 8.0;
  ++arg;
  // Lanczos vectors per step (ModalOptions::block_size): 0 automatic, 1 single-vector.
  const int block_size = argc > arg ? std::atoi(argv[arg]) : 0;
  ++arg;
  const bool probe = argc > arg ? std::atoi(argv[arg]) != 0 : true;

  auto start = std::chrono::steady_clock::now();
  std::vector<int> clamped;
  const Mesh mesh = box_mesh(nx, ny, nz, size, &clamped);
  const double t_mesh = seconds_since(start);

  stickslip::IsotropicMaterial steel{2.0e11, 0.3, 7800.0};
  stickslip::AssemblyOptions options;  // C3D8I as the mesh says, 2 threads
  stickslip::SparseMatrix K, M;
  start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  stickslip::assemble_stiffness_mass(mesh, steel, options, &K, &M);
  const double t_assembly = seconds_since(start), cpu_assembly = cpu_seconds() - cpu_start;

  start = std::chrono::steady_clock::now();
  const stickslip::DofMap dofs = stickslip::DofMap::from_nodes(mesh.num_nodes(), clamped);
  const stickslip::SparseMatrix Kff = dofs.restrict(K);
  const stickslip::SparseMatrix Mff = dofs.restrict(M);
  const double t_restrict = seconds_since(start);
  K.resize(0, 0);  // free the full matrices before the eigensolver's peak
  M.resize(0, 0);

  std::printf(
      "%s %.3g x %.3g x %.3g m, mesh %dx%dx%d C3D8I: %d nodes, %d elements, %d DOFs (%d free), "
      "nnz(K_ff) = %lld\n",
      shape.c_str(), size.x(), size.y(), size.z(), nx, ny, nz, mesh.num_nodes(),
      mesh.num_elements(), mesh.num_dofs(), dofs.num_free(),
      static_cast<long long>(Kff.nonZeros()));
  std::printf("mesh generation      %8.2f s\n", t_mesh);
  std::printf("assembly (K and M)   %8.2f s (%.2f s CPU)\n", t_assembly, cpu_assembly);
  std::printf("clamp (DofMap)       %8.2f s\n", t_restrict);
  std::fflush(stdout);

  // The factor behind the shift-invert operator: size and cost from the symbolic analysis, then
  // (if it fits in max_factor_gb) the factorisation and one solve, timed on their own.
  start = std::chrono::steady_clock::now();
  const stickslip::CholeskyEstimate estimate = stickslip::SparseCholesky::estimate(Kff);
  const double factor_gb = 8.0 * estimate.factor_nonzeros / 1e9;
  std::printf("factor: %s ordering, nnz(L) = %.3g (%.1f GB), %.3g flops, analysis %.2f s\n",
              estimate.ordering.c_str(), estimate.factor_nonzeros, factor_gb, estimate.flops,
              seconds_since(start));
  if (factor_gb > max_factor_gb) {
    std::printf("modes skipped: the factor needs %.1f GB > max_factor_gb = %.1f GB\n", factor_gb,
                max_factor_gb);
    // The floor of any factor-free (iterative) eigen-solver: one product of K with a block of
    // num_modes vectors, which each of its iterations needs at least once.
    const Eigen::MatrixXd X = Eigen::MatrixXd::Ones(Kff.rows(), num_modes);
    start = std::chrono::steady_clock::now();
    const double cpu = cpu_seconds();
    const Eigen::MatrixXd Y = Kff * X;
    std::printf("one K product with %d vectors: %.2f s wall, %.2f s CPU (%.3g)\n", num_modes,
                seconds_since(start), cpu_seconds() - cpu, Y(0, 0));
    return 0;
  }
  if (probe) {
    start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    const stickslip::SparseCholesky factor(stickslip::SparseMatrix(Kff + Mff));
    const double t_factor = seconds_since(start), cpu_factor = cpu_seconds() - cpu_start;
    Eigen::VectorXd x = Eigen::VectorXd::Ones(Kff.rows()), y(Kff.rows());
    start = std::chrono::steady_clock::now();
    constexpr int kSolves = 5;
    for (int i = 0; i < kSolves; ++i) factor.solve(x.data(), y.data());
    const double t_solve = seconds_since(start) / kSolves;
    Eigen::VectorXd t(Kff.rows()), u(Kff.rows());
    start = std::chrono::steady_clock::now();
    for (int i = 0; i < kSolves; ++i) u.noalias() = Mff * x;
    const double t_product = seconds_since(start) / kSolves;
    start = std::chrono::steady_clock::now();
    for (int i = 0; i < kSolves; ++i) {
      factor.solve_upper(x.data(), t.data());
      factor.solve_lower(t.data(), y.data());
    }
    const double t_halves = seconds_since(start) / kSolves;
    std::printf(
        "factorisation alone %.2f s (%.1f GFlop/s), %.2f s CPU; one solve %.3f s, two half "
        "solves %.3f s, one M product %.3f s\n",
        t_factor, estimate.flops / t_factor / 1e9, cpu_factor, t_solve, t_halves, t_product);
  }

  stickslip::ModalOptions modal;
  modal.num_modes = num_modes;
  modal.block_size = block_size;
  start = std::chrono::steady_clock::now();
  const double cpu_modes_start = cpu_seconds();
  const stickslip::ModalResult result = stickslip::solve_modes(Kff, Mff, modal);
  const double t_modes = seconds_since(start), cpu_modes = cpu_seconds() - cpu_modes_start;

  std::printf(
      "%d modes             %8.2f s  (factorisation %.2f s, Lanczos %.2f s, %d "
      "operator applications), %.2f s CPU\n",
      num_modes, t_modes, result.summary.factorization_seconds, result.summary.iteration_seconds,
      result.summary.operations, cpu_modes);
  std::printf("summary: %s\n", result.summary.message.c_str());
  if (result.eigenvalues.size() > 0) {
    const Eigen::VectorXd f = result.frequencies_hz();
    std::printf("f1 = %.3f Hz, f%d = %.3f Hz\n", f(0), static_cast<int>(f.size()), f(f.size() - 1));
  }
  return result.summary.ok() ? 0 : 1;
}

// petsc_reduction_driver: the Craig–Bampton reduction of a generated body by either path, for
// the tests of the PETSc reduction under mpirun (petsc_reduction_test.cpp) and its measurement
// (docs/performance.md, "Distributed reduction").
//
//   petsc_reduction_driver SOLVER EX EY EZ MASTERS MODES OUT [basis]
//
// SOLVER: direct (reduction/craig_bampton.h, this process alone) or petsc
// (model/petsc_reduction.h, collective over the processes of mpirun). The body: a structured
// C3D8 steel box 1.0 x 0.2 x 0.2 m of EX x EY x EZ elements (docs/performance.md's box:
// 99 25 25), clamped at x = 0, its masters the first MASTERS nodes of the free end face (row by
// row), MODES fixed-interface modes. Every process writes OUT.<rank> (rank from mpirun's
// environment): the text line "stickslip-cb nb m n" then K_r, M_r (column-major), the
// eigenvalues and, with `basis`, T, as little-endian doubles. Prints one line of JSON: sizes,
// seconds of each phase, peak resident memory (KiB) of this process and, for petsc, the
// plugin's numbers.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "fe/assembly.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"
#include "model/petsc_reduction.h"
#include "reduction/craig_bampton.h"

namespace {

using namespace stickslip;

int environment_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"}) {
    if (const char* v = std::getenv(name)) return std::atoi(v);
  }
  return 0;
}

void write_doubles(std::ofstream& out, const double* data, Eigen::Index count) {
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count * 8));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 8) {
    std::fprintf(stderr, "usage: %s direct|petsc EX EY EZ MASTERS MODES OUT [basis]\n", argv[0]);
    return 2;
  }
  const std::string solver = argv[1];
  const int ex = std::atoi(argv[2]), ey = std::atoi(argv[3]), ez = std::atoi(argv[4]);
  const int masters = std::atoi(argv[5]), modes = std::atoi(argv[6]);
  const std::string out_path = std::string(argv[7]) + "." + std::to_string(environment_rank());
  const bool basis = argc > 8 && std::string(argv[8]) == "basis";
  const int nx = ex + 1, ny = ey + 1, nz = ez + 1;
  auto node = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  const Mesh mesh =
      structured_hex_box(ex, ey, ez, Eigen::Vector3d(1.0, 0.2, 0.2), ElementType::kC3D8);
  const IsotropicMaterial steel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &K, &M);
  std::vector<int> constrained, boundary;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int d = 0; d < 3; ++d) constrained.push_back(3 * node(0, j, k) + d);
  for (int a = 0; a < masters && a < ny * nz; ++a)
    for (int d = 0; d < 3; ++d) boundary.push_back(3 * node(ex, a % ny, a / ny) + d);
  CraigBamptonOptions options;
  options.num_modes = modes;
  options.keep_basis = basis;
  const auto t0 = std::chrono::steady_clock::now();
  PetscReductionInfo info;
  CraigBamptonResult r;
  try {
    if (solver == "petsc") {
      set_petsc_reduction_collective(true);
      r = craig_bampton_petsc(K, M, constrained, boundary, options, &info);
    } else {
      r = craig_bampton(K, M, constrained, boundary, options);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!r.summary.ok()) {
    std::fprintf(stderr, "error: %s\n", r.summary.message.c_str());
    return 1;
  }
  std::ofstream out(out_path, std::ios::binary);
  const int nb = r.summary.num_boundary, m = r.summary.num_modes;
  out << "stickslip-cb " << nb << ' ' << m << ' ' << r.summary.num_dofs << '\n';
  write_doubles(out, r.body.K.data(), r.body.K.size());
  write_doubles(out, r.body.M.data(), r.body.M.size());
  write_doubles(out, r.mode_eigenvalues.data(), r.mode_eigenvalues.size());
  if (basis) write_doubles(out, r.T.data(), r.T.size());
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf(
      "{\"rank\": %d, \"solver\": \"%s\", \"dofs\": %d, \"boundary\": %d, \"modes\": %d, "
      "\"seconds\": %.3f, \"s_constraint\": %.3f, \"s_modes\": %.3f, \"s_projection\": %.3f, "
      "\"peak_rss_kb\": %ld, \"processes\": %d, \"petsc_solver\": \"%s\", "
      "\"krylov_iterations\": %d, \"eigen_iterations\": %d, \"max_eigen_residual\": %.3g, "
      "\"peak_rss_kb_max\": %ld, \"peak_rss_kb_min\": %ld, \"nnz_L\": %.0f}\n",
      environment_rank(), solver.c_str(), r.summary.num_dofs, nb, m, seconds,
      r.summary.seconds_constraint + r.summary.seconds_factor, r.summary.seconds_modes,
      r.summary.seconds_projection, usage.ru_maxrss, info.processes, info.solver.c_str(),
      info.constraint_iterations, info.eigen_iterations, info.max_eigen_residual,
      info.peak_rss_kb_max, info.peak_rss_kb_min, r.summary.factor_nonzeros);
  return 0;
}

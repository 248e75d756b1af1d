// Assembly of K and M for structured 8-node hexahedral meshes of about 10k, 100k and 1M DOFs.
// Run: build/<dir>/bench/fe_assembly_bench --benchmark_filter=Hex8
// Counters: dofs, nnz per matrix.
#include <benchmark/benchmark.h>

#include "fe/assembly.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"

namespace {

using namespace stickslip;

// n x n x n cells of the unit cube; (n+1)^3 nodes, 3 (n+1)^3 DOFs.
Mesh cube_mesh(int n, ElementType type) {
  return structured_hex_box(n, n, n, Eigen::Vector3d::Ones(), type);
}

void BM_AssembleHex8(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const ElementType type = state.range(1) != 0 ? ElementType::kC3D8I : ElementType::kC3D8;
  const Mesh mesh = cube_mesh(n, type);
  const IsotropicMaterial steel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
  AssemblyOptions options;
  options.num_threads = static_cast<int>(state.range(2));
  SparseMatrix K, M;
  for (auto _ : state) {
    assemble_stiffness_mass(mesh, steel, options, &K, &M);
    benchmark::DoNotOptimize(K.valuePtr());
  }
  state.counters["dofs"] = static_cast<double>(mesh.num_dofs());
  state.counters["nnz"] = static_cast<double>(K.nonZeros());
}

// (cells per edge, incompatible modes?, threads): 16 -> 14.7k DOFs, 35 -> 140k, 69 -> 1.03M.
BENCHMARK(BM_AssembleHex8)
    ->ArgsProduct({{16, 35, 69}, {0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();

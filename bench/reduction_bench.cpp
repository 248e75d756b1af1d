// Craig–Bampton reduction (reduction/craig_bampton.h) of
//   - BM_ReduceReferenceBeam: beam 1 of the reference model (io/two_beam_model.h, default butt
//     mesh, C3D8I) onto its contact-face nodes and forced node, 60 fixed-interface modes;
//   - BM_ReduceBox: a structured C3D8 steel box 1.0 x 0.2 x 0.2 m with 99 x 25 x 25 elements
//     (100 x 26 x 26 nodes = 202,800 DOFs), clamped at x = 0, onto 300 master nodes (a 15 x 20
//     grid of the 26 x 26 nodes of the free end face: 900 boundary DOFs) and 60 modes.
// Only the reduction is timed (assembly is set-up). Counters: DOFs, boundary DOFs, nnz(L) of
// K_ii, and the seconds of each phase from CraigBamptonSummary.
// Run: build/<dir>/bench/reduction_bench --benchmark_filter=Box/1   (peak memory: /usr/bin/time -v)
#include <benchmark/benchmark.h>

#include <vector>

#include "fe/assembly.h"
#include "io/two_beam_model.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"
#include "reduction/craig_bampton.h"

namespace {

using namespace stickslip;

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};

void report(benchmark::State& state, const CraigBamptonResult& r) {
  if (!r.summary.ok()) state.SkipWithError(r.summary.message.c_str());
  state.counters["dofs"] = r.summary.num_dofs;
  state.counters["boundary_dofs"] = r.summary.num_boundary;
  state.counters["modes"] = r.summary.num_modes;
  state.counters["nnz_L"] = r.summary.factor_nonzeros;
  state.counters["coupled_last"] = r.summary.coupled_last;
  state.counters["s_factor"] = r.summary.seconds_factor;
  state.counters["s_constraint"] = r.summary.seconds_constraint;
  state.counters["s_modes"] = r.summary.seconds_modes;
  state.counters["s_modes_factor"] = r.summary.modal.factorization_seconds;
  state.counters["lanczos_ops"] = r.summary.modal.operations;
  state.counters["lanczos_block"] = r.summary.modal.block_size;
  state.counters["s_lanczos"] = r.summary.modal.iteration_seconds;
  state.counters["s_projection"] = r.summary.seconds_projection;
  state.counters["cpu_factor"] = r.summary.cpu_seconds_factor;
  state.counters["cpu_constraint"] = r.summary.cpu_seconds_constraint;
  state.counters["cpu_modes"] = r.summary.cpu_seconds_modes;
  state.counters["cpu_projection"] = r.summary.cpu_seconds_projection;
  state.counters["cpu_total"] = r.summary.cpu_seconds_factor + r.summary.cpu_seconds_constraint +
                                r.summary.cpu_seconds_modes + r.summary.cpu_seconds_projection;
}

void BM_ReduceReferenceBeam(benchmark::State& state) {
  const TwoBeamModel model = make_two_beam_model();
  const Mesh& mesh = model.mesh;
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, mesh.element_sets.at("BEAM1"), kSteel, AssemblyOptions{}, &K, &M);
  // Constrain the clamp and every node not on beam 1 (the matrices span both beams).
  std::vector<char> on_beam(mesh.num_nodes(), 0);
  for (int n : mesh.node_sets.at("BEAM1")) on_beam[n] = 1;
  std::vector<int> constrained, boundary;
  for (int n = 0; n < mesh.num_nodes(); ++n)
    if (!on_beam[n])
      for (int d = 0; d < 3; ++d) constrained.push_back(3 * n + d);
  for (int n : mesh.node_sets.at("CLAMP1"))
    for (int d = 0; d < 3; ++d) constrained.push_back(3 * n + d);
  std::vector<int> masters = mesh.node_sets.at("CONTACT1");
  masters.push_back(model.force_node_1);
  for (int n : masters)
    for (int d = 0; d < 3; ++d) boundary.push_back(3 * n + d);
  CraigBamptonOptions options;  // 60 modes
  CraigBamptonResult r;
  for (auto _ : state) {
    r = craig_bampton(K, M, constrained, boundary, options);
    benchmark::DoNotOptimize(r.body.K.data());
  }
  report(state, r);
  state.counters["dofs"] = 3.0 * mesh.node_sets.at("BEAM1").size();
}

void BM_ReduceBox(benchmark::State& state) {
  const int ex = 99, ey = 25, ez = 25;
  const int nx = ex + 1, ny = ey + 1, nz = ez + 1;
  auto node = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  const Mesh mesh =
      structured_hex_box(ex, ey, ez, Eigen::Vector3d(1.0, 0.2, 0.2), ElementType::kC3D8);
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, kSteel, AssemblyOptions{}, &K, &M);
  std::vector<int> constrained, boundary;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int d = 0; d < 3; ++d) constrained.push_back(3 * node(0, j, k) + d);
  for (int a = 0; a < 15; ++a)    // 15 of the 26 rows in z (every other from 0, up to 24)...
    for (int b = 0; b < 20; ++b)  // ...times 20 consecutive columns in y: 300 nodes
      for (int d = 0; d < 3; ++d) boundary.push_back(3 * node(ex, 3 + b, (a * 25) / 14) + d);
  CraigBamptonOptions options;  // 60 modes
  if (state.range(0) == 0) {
    // Before issue 3's tuning: a second factorisation (of K_ii + M_ii) for the eigen-solve and
    // single-vector Lanczos.
    options.modal.shift = -1.0;
    options.modal.block_size = 1;
  } else if (state.range(0) == -1) {
    // Defaults, but CHOLMOD's own ordering of K_ii (constraint modes by full solves).
    options.coupled_last = LastOrdering::kNever;
  } else if (state.range(0) >= 2) {
    options.modal.block_size = static_cast<int>(state.range(0));  // block Lanczos of this size
  }
  CraigBamptonResult r;
  for (auto _ : state) {
    r = craig_bampton(K, M, constrained, boundary, options);
    benchmark::DoNotOptimize(r.T.data());
  }
  report(state, r);
}

BENCHMARK(BM_ReduceReferenceBeam)->Unit(benchmark::kMillisecond)->Iterations(1);
// Box/1: defaults (the eigen-solve reuses the factor of K_ii; block Lanczos). Box/0: the
// previous configuration (second factorisation, single-vector Lanczos), for comparison.
// Box/k, k >= 2: defaults with a block Lanczos of k vectors. Box/-1: defaults without the
// trailing ordering of the boundary-coupled interior DOFs.
BENCHMARK(BM_ReduceBox)
    ->Arg(1)
    ->Arg(-1)
    ->Arg(0)
    ->Arg(8)
    ->Arg(15)
    ->Arg(24)
    ->Arg(32)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();

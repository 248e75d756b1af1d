// Mortar coupling (mesh/mortar.h) of a flat contact surface A of n_a x n_a quadrilaterals to a
// surface B of n_b x n_b (non-matching) quadrilaterals on the same unit square: the target of issue
// 23 is 10,000 A points against 100,000 B faces in under 5 s.
// Run: build/<dir>/bench/mortar_bench
// Counters: a_points, b_faces.
#include <benchmark/benchmark.h>

#include "mesh/mesh_tools.h"
#include "mesh/mortar.h"
#include "mesh/surface_area.h"

namespace {

using namespace stickslip;

void BM_MortarCoupling(benchmark::State& state) {
  const int na = static_cast<int>(state.range(0)), nb = static_cast<int>(state.range(1));
  const Mesh a = structured_hex_box(na, na, 1, {1.0, 1.0, 0.1}, ElementType::kC3D8);
  Mesh b = structured_hex_box(nb, nb, 1, {1.0, 1.0, 0.1}, ElementType::kC3D8);
  b.coordinates.row(2).array() += 0.1;
  const std::vector<ElementFace> fa = faces_within(a, nodes_on_plane(a, {0, 0, 0.1}, {0, 0, 1}, 1e-9));
  const std::vector<ElementFace> fb = faces_within(b, nodes_on_plane(b, {0, 0, 0.1}, {0, 0, 1}, 1e-9));
  size_t points = 0;
  for (auto _ : state) {
    const MortarCoupling c = mortar_coupling(a, fa, b, fb);
    points = c.points.size();
    benchmark::DoNotOptimize(c.points.data());
  }
  state.counters["a_points"] = static_cast<double>(points);
  state.counters["b_faces"] = static_cast<double>(fb.size());
}

// (A cells per edge, B cells per edge): the reference joint's size (5 x 6 ≈ 30 points), 1k x 10k,
// and 10k points x 100k faces.
BENCHMARK(BM_MortarCoupling)
    ->Args({5, 7})
    ->Args({31, 100})
    ->Args({99, 316})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace

BENCHMARK_MAIN();

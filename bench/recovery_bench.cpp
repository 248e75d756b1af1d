// Benchmark of full-model recovery per frequency point (issue 5), modal method.
//
// A steel box of nx x ny x nz cubic C3D8I elements of 2.5 mm (medium = the reference beam's
// 0.25 x 0.05 x 0.03 m; large = a 2.75 m rod of 40 x 40 mm section, whose slender shape keeps the
// Cholesky factor of a million DOFs in a few GB), clamped at x = 0, loaded at 30 "contact" nodes of
// the free end face x = L (all three directions, seeded random complex forces) for harmonics 0..H.
// One-off: assembly and ModalRecovery with n modes, the static residual correction and the
// attachment modes of the 90 loaded DOFs, and the sparse nodal-stress operator (fe/stress.h,
// NodalStressOperator). Per point (a new Ω each time), timed apart and summed as a "full point":
// the displacement of every harmonic 0..H (ModalRecovery), the complex nodal stresses of every
// harmonic (NodalStressOperator, one pass for all harmonics, real and imaginary parts), the
// envelope over the period (recovery/stress_envelope.h: closed-form principal stresses, maxima
// refined between samples, automatic sample count). For comparison, in the same process: the
// previous envelope (64 samples, an Eigen 3x3 eigen-solve per sample, one thread: "legacy"),
// element-by-element nodal_stress (below 300k DOFs), and the modal stress basis (two separate
// products vs one, below 300k DOFs or with RECOVERY_BENCH_STRESS_BASIS=1).
//
// Usage: recovery_bench [small|medium|large|<nx> <ny> <nz>] [num_modes] [harmonics H] [points]
//   reference (beam 1 of the two-beam reference model, default mesh, 4.7k DOFs),
//   small 40x8x5 (6.6k DOFs), medium 100x20x12 (83k DOFs), large 1100x16x16 (954k DOFs). Defaults:
//   medium, 100 modes, H = 1, 5 points. Optional env RECOVERY_BENCH_DIRECT=1 also times one
//   DirectRecovery point (UMFPACK).
// A plain main rather than Google Benchmark: the one-off setup takes minutes for the large sizes
// and peak memory is measured per process (/usr/bin/time -v); docs/performance.md has results.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/stress.h"
#include "io/two_beam_model.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"
#include "recovery/harmonic_response.h"
#include "recovery/stress_envelope.h"

namespace {

using namespace stickslip;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Cubic C3D8I elements of 2.5 mm: medium (100 x 20 x 12) is the reference beam's
// 0.25 x 0.05 x 0.03 m. `clamped` gets the face x = 0, `end_face` the face x = 2.5 mm nx.
Mesh box_mesh(int nx, int ny, int nz, std::vector<int>* clamped, std::vector<int>* end_face) {
  const double h = 0.0025;
  Mesh mesh = structured_hex_box(nx, ny, nz, h * Eigen::Vector3d(nx, ny, nz), ElementType::kC3D8I);
  for (int n = 0; n < mesh.num_nodes(); n += nx + 1) {
    clamped->push_back(n);        // i = 0
    end_face->push_back(n + nx);  // i = nx
  }
  return mesh;
}

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// The envelope as it was before the closed-form/refined one (kept here only to time it in the
// same process): 64 samples, Eigen's 3x3 computeDirect eigenvalues per sample, one thread.
Eigen::VectorXd legacy_von_mises_max(const std::vector<ComplexStressMatrix>& S,
                                     const std::vector<int>& harmonics, Eigen::VectorXd* p1) {
  const int N = 64;
  const Eigen::Index num_nodes = S[0].cols();
  Eigen::VectorXd vm_max(num_nodes);
  p1->resize(num_nodes);
  for (Eigen::Index n = 0; n < num_nodes; ++n) {
    double best = 0.0, best_p = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < N; ++j) {
      Eigen::Matrix<double, 6, 1> s = Eigen::Matrix<double, 6, 1>::Zero();
      for (size_t h = 0; h < harmonics.size(); ++h) {
        const double theta = 2.0 * kPi * ((harmonics[h] * j) % N) / N;
        s += S[h].col(n).real() * std::cos(theta) - S[h].col(n).imag() * std::sin(theta);
      }
      const double a = s(0) - s(1), b = s(1) - s(2), c = s(2) - s(0);
      best = std::max(best, std::sqrt(0.5 * (a * a + b * b + c * c) +
                                      3.0 * (s(3) * s(3) + s(4) * s(4) + s(5) * s(5))));
      Eigen::Matrix3d t;
      t << s(0), s(3), s(4), s(3), s(1), s(5), s(4), s(5), s(2);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(t, Eigen::EigenvaluesOnly);
      best_p = std::max(best_p, solver.eigenvalues()(2));
    }
    vm_max(n) = best;
    (*p1)(n) = best_p;
  }
  return vm_max;
}

}  // namespace

int main(int argc, char** argv) {
  int nx = 100, ny = 20, nz = 12;
  std::string size = argc > 1 ? argv[1] : "medium";
  int arg = 2;
  if (size == "reference") {
    // the two-beam reference model's beam 1, below
  } else if (size == "small") {
    nx = 40, ny = 8, nz = 5;
  } else if (size == "medium") {
    nx = 100, ny = 20, nz = 12;
  } else if (size == "large") {
    nx = 1100, ny = 16, nz = 16;
  } else {
    if (argc < 4) {
      std::fprintf(stderr, "usage: %s [small|medium|large|nx ny nz] [modes] [H] [points]\n",
                   argv[0]);
      return 2;
    }
    nx = std::atoi(argv[1]), ny = std::atoi(argv[2]), nz = std::atoi(argv[3]);
    arg = 4;
  }
  const int num_modes = argc > arg ? std::atoi(argv[arg]) : 100;
  const int H = argc > arg + 1 ? std::atoi(argv[arg + 1]) : 1;
  const int points = argc > arg + 2 ? std::atoi(argv[arg + 2]) : 5;
  const IsotropicMaterial steel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};

  auto start = std::chrono::steady_clock::now();
  std::vector<int> clamped, end_face;
  Mesh mesh;
  std::vector<int> loaded;
  if (size == "reference") {
    // Beam 1 of the reference model (docs/conventions.md, default butt mesh): clamped end, the
    // contact face nodes and the forced node carry the loads.
    const TwoBeamModel model = make_two_beam_model();
    const SubMesh beam = extract_element_set(model.mesh, "BEAM1");
    mesh = beam.mesh;
    clamped = find_node_set(mesh, "CLAMP1");
    loaded = find_node_set(mesh, "CONTACT1");
    loaded.push_back(find_node_set(mesh, "FORCE1")[0]);
    nx = ny = nz = 0;
  } else {
    mesh = box_mesh(nx, ny, nz, &clamped, &end_face);
    // 30 loaded nodes spread over the end face (like the reference case's contact pairs).
    const size_t stride = std::max<size_t>(1, end_face.size() / 30);
    for (size_t i = 0; i < end_face.size() && loaded.size() < 30; i += stride) {
      loaded.push_back(end_face[i]);
    }
  }
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, steel, {}, &K, &M);
  const DofMap dofs = DofMap::from_nodes(mesh.num_nodes(), clamped);
  std::printf("mesh %s (%d x %d x %d): %d nodes, %d DOFs (%d free); assembly %.2f s\n",
              size.c_str(), nx, ny, nz, mesh.num_nodes(), mesh.num_dofs(), dofs.num_free(),
              seconds_since(start));
  std::vector<int> load_dofs;
  for (int n : loaded) {
    for (int d = 0; d < 3; ++d) load_dofs.push_back(3 * n + d);
  }
  std::vector<int> harmonics;
  for (int k = 0; k <= H; ++k) harmonics.push_back(k);
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-100.0, 100.0);
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(mesh.num_dofs(), H + 1);
  for (int d : load_dofs) {
    for (int k = 0; k <= H; ++k) {
      loads(d, k) =
          k == 0 ? std::complex<double>(u(rng), 0.0) : std::complex<double>(u(rng), u(rng));
    }
  }

  const RayleighDamping damping{.alpha = 5.0, .beta = 0.0};
  ModalRecoveryOptions options;
  options.num_modes = num_modes;
  options.load_dofs = load_dofs;
  start = std::chrono::steady_clock::now();
  const ModalRecovery modal(K, M, dofs, damping, options);
  const double t_setup = seconds_since(start);
  if (!modal.ok()) {
    std::printf("modal setup failed: %s\n", modal.message().c_str());
    return 1;
  }
  const double f1 = std::sqrt(modal.eigenvalues()(0)) / (2 * kPi);
  std::printf(
      "one-off: %d modes + residual attachment modes of %zu DOFs: %.2f s (eigen-solve "
      "factorisation %.2f s, Lanczos %.2f s); f1 = %.1f Hz, f%d = %.1f Hz\n",
      num_modes, load_dofs.size(), t_setup, modal.modal_summary().factorization_seconds,
      modal.modal_summary().iteration_seconds, f1, num_modes,
      std::sqrt(modal.eigenvalues()(num_modes - 1)) / (2 * kPi));

  start = std::chrono::steady_clock::now();
  const NodalStressOperator G(mesh, steel, {});
  std::printf("one-off: nodal stress operator %.2f s (%lld blocks, %.2f GB)\n",
              seconds_since(start), static_cast<long long>(G.num_blocks()),
              18.0 * 8.0 * static_cast<double>(G.num_blocks()) / 1e9);
  const StressEnvelopeOptions env_options;  // automatic samples, refined, all hardware threads
  std::printf("envelope: %d samples per period (automatic), refined; %u hardware threads\n",
              envelope_time_samples(env_options, H), std::thread::hardware_concurrency());

  double t_disp = 0.0, t_stress = 0.0, t_env = 0.0, t_legacy = 0.0;
  double c_disp = 0.0, c_stress = 0.0, c_env = 0.0, c_legacy = 0.0;
  double worst_vm = 0.0, worst_p = 0.0;  // refined vs legacy 64-sample maxima, relative to max
  for (int p = 0; p < points; ++p) {
    const double omega = hz_to_rad_s(f1 * (0.9 + 0.05 * p));
    start = std::chrono::steady_clock::now();
    double c0 = cpu_seconds();
    RecoverySummary summary;
    const Eigen::MatrixXcd x = harmonic_response(modal, loads, harmonics, omega, &summary);
    t_disp += seconds_since(start);
    c_disp += cpu_seconds() - c0;
    start = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    const std::vector<ComplexStressMatrix> S = G.apply(x);
    t_stress += seconds_since(start);
    c_stress += cpu_seconds() - c0;
    start = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    const StressEnvelope env = stress_envelope(S, harmonics, env_options);
    t_env += seconds_since(start);
    c_env += cpu_seconds() - c0;
    start = std::chrono::steady_clock::now();
    c0 = cpu_seconds();
    Eigen::VectorXd legacy_p1;
    const Eigen::VectorXd legacy_vm = legacy_von_mises_max(S, harmonics, &legacy_p1);
    t_legacy += seconds_since(start);
    c_legacy += cpu_seconds() - c0;
    const double vm_scale = legacy_vm.maxCoeff(), p_scale = legacy_p1.cwiseAbs().maxCoeff();
    worst_vm = std::max(worst_vm, (env.von_mises_max - legacy_vm).cwiseAbs().maxCoeff() / vm_scale);
    worst_p =
        std::max(worst_p, (env.max_principal_max - legacy_p1).cwiseAbs().maxCoeff() / p_scale);
    if (!(env.von_mises_max.array() >= legacy_vm.array() - 1e-9 * vm_scale).all()) {
      std::printf("WARNING: refined von Mises maximum below the 64-sample one\n");
    }
    if (p == 0) {
      std::printf("point 0: %s; max |x| = %.3e m, max von Mises over the period = %.3e Pa\n",
                  summary.ok() ? "solved" : summary.message.c_str(), x.cwiseAbs().maxCoeff(),
                  env.von_mises_max.maxCoeff());
    }
  }
  std::printf(
      "per point (H = %d, %d points), wall (CPU): displacement %.3f s (%.3f), nodal stresses "
      "(operator) %.3f s (%.3f), envelope %.3f s (%.3f); full point %.3f s (%.3f)\n",
      H, points, t_disp / points, c_disp / points, t_stress / points, c_stress / points,
      t_env / points, c_env / points, (t_disp + t_stress + t_env) / points,
      (c_disp + c_stress + c_env) / points);
  std::printf(
      "legacy envelope (64 samples, Eigen eigenvalues, 1 thread): %.3f s (%.3f) per point; "
      "refined - legacy: max |diff| / max = %.2e (von Mises), %.2e (max principal)\n",
      t_legacy / points, c_legacy / points, worst_vm, worst_p);
  if (mesh.num_dofs() < 300000) {
    const double omega = hz_to_rad_s(f1 * 0.9);
    const Eigen::MatrixXcd x = harmonic_response(modal, loads, harmonics, omega);
    start = std::chrono::steady_clock::now();
    std::vector<ComplexStressMatrix> S;
    for (int k = 0; k <= H; ++k) {
      S.push_back(nodal_stress(mesh, steel, {}, Eigen::VectorXcd(x.col(k))));
    }
    const double t_elem = seconds_since(start);
    const std::vector<ComplexStressMatrix> SG = G.apply(x);
    double diff = 0.0;
    for (int k = 0; k <= H; ++k) {
      diff = std::max(diff, (S[k] - SG[k]).cwiseAbs().maxCoeff() / S[k].cwiseAbs().maxCoeff());
    }
    std::printf("element-by-element nodal_stress: %.3f s per point; operator vs it: %.1e\n", t_elem,
                diff);
  }

  // Modal stress recovery: the stresses of the basis vectors once (through the operator), then
  // dense products per point: the former two passes (real, imaginary) vs the one pass.
  const char* basis_env = std::getenv("RECOVERY_BENCH_STRESS_BASIS");
  if (mesh.num_dofs() < 300000 || (basis_env != nullptr && std::string(basis_env) == "1")) {
    start = std::chrono::steady_clock::now();
    const ModalStressBasis basis(modal, G);
    const double t_basis = seconds_since(start);
    double t_one = 0.0, t_two = 0.0;
    for (int p = 0; p < points; ++p) {
      const double omega = hz_to_rad_s(f1 * (0.9 + 0.05 * p));
      start = std::chrono::steady_clock::now();
      const std::vector<ComplexStressMatrix> S = basis.stresses(modal, loads, harmonics, omega);
      t_one += seconds_since(start);
      start = std::chrono::steady_clock::now();
      const Eigen::MatrixXcd c = modal.coordinates(loads, harmonics, omega);
      const Eigen::MatrixXd re = basis.matrix() * c.real(), im = basis.matrix() * c.imag();
      t_two += seconds_since(start);
    }
    std::printf(
        "modal stress basis: one-off %.2f s (%d columns, %.2f GB); per point: one pass %.3f s, "
        "two passes (before) %.3f s\n",
        t_basis, modal.num_basis_columns(), 8.0 * basis.matrix().size() / 1e9, t_one / points,
        t_two / points);
  }

  // For comparison: a load off the precomputed DOFs (one sparse solve per harmonic).
  Eigen::MatrixXcd other = loads;
  other(3 * mesh.num_nodes() / 2, 1) = 1.0;
  start = std::chrono::steady_clock::now();
  (void)harmonic_response(modal, other, harmonics, hz_to_rad_s(f1));
  std::printf("per point with a load off the attachment DOFs (factor solves): %.3f s\n",
              seconds_since(start));

  if (const char* direct_env = std::getenv("RECOVERY_BENCH_DIRECT");
      direct_env != nullptr && std::string(direct_env) == "1") {
    start = std::chrono::steady_clock::now();
    const DirectRecovery direct(K, M, dofs, damping);
    const double t_direct_setup = seconds_since(start);
    start = std::chrono::steady_clock::now();
    const Eigen::MatrixXcd xd = harmonic_response(direct, loads, harmonics, hz_to_rad_s(f1));
    std::printf(
        "direct: setup (Cholesky of K_ff) %.2f s, one point (UMFPACK LU per harmonic "
        ">= 1) %.2f s\n",
        t_direct_setup, seconds_since(start));
    const Eigen::MatrixXcd xm = harmonic_response(modal, loads, harmonics, hz_to_rad_s(f1));
    std::vector<int> all(static_cast<size_t>(mesh.num_dofs()));
    for (int d = 0; d < mesh.num_dofs(); ++d) all[static_cast<size_t>(d)] = d;
    const ResponseDifference diff = compare_responses(xm, xd, all);
    for (int k = 0; k <= H; ++k) {
      std::printf("modal vs direct, harmonic %d: max relative %.2e, rms %.2e\n", k,
                  diff.max_relative[static_cast<size_t>(k)],
                  diff.rms_relative[static_cast<size_t>(k)]);
    }
  }
  return 0;
}

// Issue 16 item 1: a large friction interface, generated. A steel plate L x w x t (0.3 x 0.1 x
// 0.01 m, C3D8I, 3n x n x 2 elements) clamped at x = 0; the square patch of its bottom face over
// 0.1 <= x <= 0.2 is pressed onto a rigid flat by a clamp force (a static pressure p0 = 10 MPa on
// the patch's top face: 100 kN): each of the (n + 1)² patch nodes is a FrictionContact3D pair with
// the ground (t1 = x, t2 = y, normal −z, no typed preload: the static load closes the joint), its
// stiffnesses those of a contact over the node's tributary area (corner nodes a quarter, edge
// nodes half of an inner node's): kn = 5e13 Pa/m, kt = 4e13 Pa/m, μ = 0.5. Excitation: a
// harmonic force in z spread evenly over the nodes of the free end x = L (the overhang bends and
// the patch's edge at x = 0.2 slips first). The structure's model: its lowest nm modes
// (mass-normalised, shift-invert Lanczos on the clamped sparse K, M), Rayleigh α = 5 s⁻¹,
// restricted to the master rows the harmonic balance needs (the patch nodes, the pressed and the
// excited nodes): a truncated modal model, nm fixed while the interface grows. H = 3, N = 32,
// uncoupled statics; the sweep: points over [0.97, 1.01] of the stuck resonance with the largest
// tangential (x) motion of the patch (the stuck structure's modes probed by its modal FRF),
// stepped, no arc-length fallback. A plain main (one size per process, so that the peak memory is
// that size's):
//   large_interface_bench N [modes=200] [points=100] [solver=low_rank|structured|dense]
//                           [force=200] [build_only=0]
//   large_interface_bench compare [N=9] [modes=60] [points=20] [force=200]  (dense, low rank)
// Results and commands: docs/performance.md, "Large interfaces (issue 16 item 1)".
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "contact/friction_contact.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "linalg/modal.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

constexpr double kLength = 0.3, kWidth = 0.1, kThickness = 0.01;  // m
constexpr int kLayers = 2;
constexpr double kNormalStiffness = 5e13, kTangentStiffness = 4e13;  // Pa/m
constexpr double kPressure = 10e6;                                   // Pa
constexpr double kFriction = 0.5;
constexpr double kAlpha = 5.0;  // 1/s

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double peak_rss_gb() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1e6;  // kB -> GB
}

double load_average() {
  std::ifstream in("/proc/loadavg");
  double one = -1;
  in >> one;
  return one;
}

struct GeneratedCase {
  LinearModel model;
  std::vector<ContactPair> pairs;
  Excitation excitation;
  double omega_peak = 0;  // rad/s: the stuck resonance that moves the interface in x
  double build_seconds = 0;
};

GeneratedCase generate(int n, int modes, double force) {
  const auto start = std::chrono::steady_clock::now();
  const Mesh mesh = structured_hex_box(
      3 * n, n, kLayers, Eigen::Vector3d(kLength, kWidth, kThickness), ElementType::kC3D8I);
  const auto node = [n](int i, int j, int k) { return i + (3 * n + 1) * (j + (n + 1) * k); };
  std::vector<int> clamped, contact, pressed, loaded;
  for (int k = 0; k <= kLayers; ++k) {
    for (int j = 0; j <= n; ++j) {
      clamped.push_back(node(0, j, k));
      loaded.push_back(node(3 * n, j, k));
    }
  }
  for (int j = 0; j <= n; ++j) {
    for (int i = n; i <= 2 * n; ++i) {
      contact.push_back(node(i, j, 0));
      pressed.push_back(node(i, j, kLayers));
    }
  }
  const IsotropicMaterial steel{2.0e11, 0.3, 7800.0};
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &K, &M);
  const DofMap dofs = DofMap::from_nodes(mesh.num_nodes(), clamped);
  ModalOptions mo;
  mo.num_modes = modes;
  const ModalResult eig = solve_modes(dofs.restrict(K), dofs.restrict(M), mo);
  if (!eig.summary.ok()) {
    std::fprintf(stderr, "modes failed: %s\n", eig.summary.message.c_str());
    std::exit(1);
  }

  // Master rows: 3 per contact node, then 3 per pressed node, then 3 per loaded node.
  GeneratedCase c;
  std::vector<int> masters(contact);
  masters.insert(masters.end(), pressed.begin(), pressed.end());
  masters.insert(masters.end(), loaded.begin(), loaded.end());
  const int ndof = 3 * static_cast<int>(masters.size());
  c.model.omega2 = eig.eigenvalues.cwiseMax(0.0);
  c.model.Phi.resize(ndof, modes);
  for (size_t m = 0; m < masters.size(); ++m) {
    for (int d = 0; d < 3; ++d) {
      c.model.Phi.row(3 * m + d) = eig.modes.row(dofs.free_index(3 * masters[m] + d));
    }
  }
  c.model.modal_damping = rayleigh_modal_damping(c.model.omega2, kAlpha, 0.0);

  const double cell = (kWidth / n) * (kWidth / n);
  const auto tributary = [&](int i, int j) {
    return cell * ((i == 0 || i == n) ? 0.5 : 1.0) * ((j == 0 || j == n) ? 0.5 : 1.0);
  };
  Eigen::Matrix3d frame;
  frame << 1, 0, 0, 0, 1, 0, 0, 0, -1;  // t1 = x, t2 = y, n = −z (into the flat)
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double area = tributary(i, j);
      const FrictionContactParameters p{.kt = kTangentStiffness * area,
                                        .kn = kNormalStiffness * area,
                                        .mu = kFriction,
                                        .normal_preload = 0.0};
      const int m = i + (n + 1) * j;
      c.pairs.push_back({.dofs_a = {3 * m, 3 * m + 1, 3 * m + 2},
                         .dofs_b = {},
                         .frame = frame,
                         .element = std::make_shared<FrictionContact3D>(p)});
    }
  }
  // The clamp force: −z on the pressed nodes (tributary areas of the patch's top face).
  const int first_pressed = 3 * static_cast<int>(contact.size());
  const int first_loaded = first_pressed + 3 * static_cast<int>(pressed.size());
  Eigen::VectorXcd f0 = Eigen::VectorXcd::Zero(ndof), f = Eigen::VectorXcd::Zero(ndof);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i)
      f0[first_pressed + 3 * (i + (n + 1) * j) + 2] = -kPressure * tributary(i, j);
  }
  for (size_t l = 0; l < loaded.size(); ++l) f[first_loaded + 3 * l + 2] = force / loaded.size();
  c.excitation.harmonics[0] = f0;
  c.excitation.harmonics[1] = f;

  // The stuck structure's FRF in modal coordinates: (diag(ω²) + Ψᵀ K_c Ψ − Ω² + iΩ diag(c)) q =
  // Φᵀ F, K_c = diag(kt, kt, kn) per pair; the mean |u_x| of the contact nodes, largest over a
  // logarithmic scan, then refined.
  const int nu = 3 * static_cast<int>(contact.size());
  Eigen::MatrixXd Psi(nu, modes), KPsi(nu, modes);
  for (int r = 0; r < nu; ++r) Psi.row(r) = c.model.Phi.row(r) * (r % 3 == 2 ? -1.0 : 1.0);
  for (int r = 0; r < nu; ++r) {
    const auto& p = static_cast<const FrictionContact3D&>(*c.pairs[r / 3].element).parameters();
    KPsi.row(r) = Psi.row(r) * (r % 3 == 2 ? p.kn : p.kt);
  }
  const Eigen::MatrixXd S = Psi.transpose() * KPsi;
  const Eigen::VectorXcd q0 = c.model.Phi.transpose().cast<Complex>() * f;
  const auto response = [&](double w) {
    Eigen::MatrixXcd Z = S.cast<Complex>();
    for (int r = 0; r < modes; ++r)
      Z(r, r) += Complex(c.model.omega2[r] - w * w, w * c.model.modal_damping[r]);
    const Eigen::VectorXcd u = Psi.cast<Complex>() * Z.partialPivLu().solve(q0);
    double sum = 0;
    for (int r = 0; r < nu; r += 3) sum += std::abs(u[r]);
    return sum / (nu / 3);
  };
  // The stuck modes (undamped: diag(ω²) + S), each probed at its frequency, the largest
  // response refined over ±1.5 % (a scan over the band misses resonances of 0.1 % width).
  const double w_low = std::sqrt(c.model.omega2[0]), w_high = std::sqrt(c.model.omega2[modes - 1]);
  Eigen::MatrixXd stuck = S;
  stuck.diagonal() += c.model.omega2;
  const Eigen::VectorXd stuck_w2 =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(stuck, Eigen::EigenvaluesOnly).eigenvalues();
  double best = 0;
  for (Eigen::Index r = 0; r < stuck_w2.size(); ++r) {
    const double w = std::sqrt(std::max(stuck_w2[r], 0.0));
    const double a = response(w);
    if (a > best) best = a, c.omega_peak = w;
  }
  const double coarse = c.omega_peak;
  for (int i = 0; i <= 400; ++i) {
    const double w = coarse * (0.985 + 0.03 * i / 400.0);
    const double a = response(w);
    if (a > best) best = a, c.omega_peak = w;
  }
  c.build_seconds = seconds_since(start);
  std::printf(
      "case: %d x %d patch nodes (%zu pairs, %d rows), %d DOFs (%d free), %d modes "
      "(%.0f..%.0f Hz), %d master rows; stuck x-resonance %.2f Hz (mean |u_x| %.3g m); "
      "generated in %.1f s\n",
      n + 1, n + 1, c.pairs.size(), nu, mesh.num_dofs(), dofs.num_free(), modes, w_low / (2 * M_PI),
      w_high / (2 * M_PI), ndof, c.omega_peak / (2 * M_PI), best, c.build_seconds);
  return c;
}

std::vector<double> sweep_omegas(double peak, int points) {
  std::vector<double> omegas;
  for (int i = 0; i < points; ++i)
    omegas.push_back(peak * (0.97 + 0.04 * i / std::max(points - 1, 1)));
  return omegas;
}

HarmonicBalanceOptions hbm_options(HbmLinearSolver solver) {
  HarmonicBalanceOptions o;
  o.harmonics = 3;
  o.time_samples = 32;
  o.linear_solver = solver;
  return o;
}

struct SweepResult {
  FrequencyResponse response;
  double seconds = 0;
  int converged = 0, iterations = 0, slipping_pairs = 0;
  double max_slip = 0;
};

SweepResult sweep(const HarmonicBalanceSystem& system, const std::vector<double>& omegas) {
  FrequencyResponseOptions o;
  o.omegas = omegas;
  o.sweep.jump_max_points = 0;  // no arc-length fallback (it needs the dense Jacobian)
  SweepResult s;
  const auto start = std::chrono::steady_clock::now();
  s.response = frequency_response(system, o);
  s.seconds = seconds_since(start);
  std::vector<double> slip(system.pairs().size(), 0.0);
  for (const FrequencyPoint& p : s.response.points) {
    s.converged += p.converged;
    s.iterations += p.iterations;
    for (size_t q = 0; q < p.pairs.size(); ++q)
      slip[q] = std::max(slip[q], p.pairs[q].cycle.slip_fraction);
  }
  for (double v : slip) {
    s.max_slip = std::max(s.max_slip, v);
    s.slipping_pairs += v > 0;
  }
  return s;
}

HbmLinearSolver parse_solver(const std::string& name) {
  if (name == "low_rank") return HbmLinearSolver::kLowRank;
  if (name == "structured") return HbmLinearSolver::kStructured;
  if (name == "dense") return HbmLinearSolver::kDense;
  std::fprintf(stderr, "unknown solver '%s' (low_rank, structured, dense)\n", name.c_str());
  std::exit(2);
}

int run(int n, int modes, int points, const std::string& solver_name, double force,
        bool build_only) {
  const GeneratedCase c = generate(n, modes, force);
  std::printf("after generation: peak RSS %.2f GB, load %.1f\n", peak_rss_gb(), load_average());
  std::fflush(stdout);
  auto start = std::chrono::steady_clock::now();
  const HarmonicBalanceSystem system(c.model, c.pairs, c.excitation,
                                     hbm_options(parse_solver(solver_name)));
  std::printf(
      "system (%s, %d unknowns): built in %.2f s (static: %s, %d steps), peak RSS "
      "%.2f GB\n",
      system.low_rank() ? "low rank" : solver_name.c_str(), system.size(), seconds_since(start),
      system.static_summary().converged() ? "converged" : "FAILED",
      system.static_summary().iterations, peak_rss_gb());
  std::fflush(stdout);
  const std::vector<double> omegas = sweep_omegas(c.omega_peak, points);
  start = std::chrono::steady_clock::now();
  Eigen::VectorXd x = system.linear_guess(omegas[points / 2], true);
  std::printf("one new frequency + stuck guess: %.2f s (GMRES %d), peak RSS %.2f GB\n",
              seconds_since(start), system.last_gmres_iterations(), peak_rss_gb());
  std::fflush(stdout);
  if (build_only) return 0;
  const SweepResult s = sweep(system, omegas);
  std::printf(
      "sweep: %d points in %.1f s wall, %d converged, %.2f Newton iterations per point, "
      "%d of %zu pairs slip somewhere (max slip fraction %.2f), last GMRES %d; peak RSS "
      "%.2f GB, load %.1f\n",
      points, s.seconds, s.converged, static_cast<double>(s.iterations) / points, s.slipping_pairs,
      c.pairs.size(), s.max_slip, system.last_gmres_iterations(), peak_rss_gb(), load_average());
  return s.converged == points ? 0 : 1;
}

// The smaller copy: the same generated case through the dense solver and the low-rank one.
int compare(int n, int modes, int points, double force) {
  const GeneratedCase c = generate(n, modes, force);
  const HarmonicBalanceSystem dense(c.model, c.pairs, c.excitation,
                                    hbm_options(HbmLinearSolver::kDense));
  const HarmonicBalanceSystem low(c.model, c.pairs, c.excitation,
                                  hbm_options(HbmLinearSolver::kLowRank));
  const std::vector<double> omegas = sweep_omegas(c.omega_peak, points);
  const SweepResult d = sweep(dense, omegas), l = sweep(low, omegas);
  double worst = 0, worst_master = 0;
  for (size_t i = 0; i < omegas.size(); ++i) {
    const FrequencyPoint &a = d.response.points[i], &b = l.response.points[i];
    worst = std::max(worst, (a.unknowns - b.unknowns).norm() / a.unknowns.norm());
    worst_master = std::max(worst_master, (a.master - b.master).norm() / a.master.norm());
  }
  std::printf(
      "compare %zu pairs, %d points: dense %d converged (%.2f s), low rank %d converged "
      "(%.2f s); Newton iterations %d / %d; pairs slipping %d / %d (max slip %.2f / "
      "%.2f); largest relative difference: unknowns %.2e, master response %.2e\n",
      c.pairs.size(), points, d.converged, d.seconds, l.converged, l.seconds, d.iterations,
      l.iterations, d.slipping_pairs, l.slipping_pairs, d.max_slip, l.max_slip, worst,
      worst_master);
  return d.converged == points && l.converged == points ? 0 : 1;
}

}  // namespace
}  // namespace stickslip

int main(int argc, char** argv) {
  const auto arg = [&](int i, const char* fallback) {
    return std::string(argc > i ? argv[i] : fallback);
  };
  if (arg(1, "") == "compare") {
    return stickslip::compare(std::stoi(arg(2, "9")), std::stoi(arg(3, "60")),
                              std::stoi(arg(4, "20")), std::stod(arg(5, "200")));
  }
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s N [modes] [points] [solver] [force] [build_only] | compare "
                 "[N] [modes] [points] [force]\n",
                 argv[0]);
    return 2;
  }
  return stickslip::run(std::stoi(arg(1, "54")), std::stoi(arg(2, "200")), std::stoi(arg(3, "100")),
                        arg(4, "low_rank"), std::stod(arg(5, "200")), std::stoi(arg(6, "0")) != 0);
}

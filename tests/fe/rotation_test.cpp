// Rotation (fe/rotation.h): the centrifugal load against the closed form of a spinning rod and
// against CalculiX's *DLOAD CENTRIF on the same mesh; stress stiffening and spin softening
// against the Southwell coefficient of a rotating cantilever and against CalculiX's *FREQUENCY
// after a centrifugal *STATIC step (PERTURBATION).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include "../ccx_dat.h"
#include "../required_tool.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/rotation.h"
#include "fe/stress.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};

bool near(double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b)); }

// Static solution of K u = f with the DOFs of `constraints` held.
Eigen::VectorXd solve_static(const SparseMatrix& K, const Eigen::VectorXd& f,
                             const DofMap& constraints) {
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(constraints.restrict(K));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  return constraints.expand(Eigen::VectorXd(ldlt.solve(constraints.restrict_load(f))));
}

// Eigenvalues ω² (ascending) of (K, M) with the DOFs of `constraints` held, dense.
Eigen::VectorXd eigenvalues(const SparseMatrix& K, const SparseMatrix& M,
                            const DofMap& constraints) {
  const Eigen::MatrixXd Kf = Eigen::MatrixXd(constraints.restrict(K));
  const Eigen::MatrixXd Mf = Eigen::MatrixXd(constraints.restrict(M));
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      0.5 * (Kf + Kf.transpose()), 0.5 * (Mf + Mf.transpose()), Eigen::EigenvaluesOnly);
  EXPECT_EQ(solver.info(), Eigen::Success);
  return solver.eigenvalues();
}

std::vector<int> nodes_at_x(const Mesh& mesh, double x) {
  std::vector<int> out;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    if (std::abs(mesh.coordinates(0, n) - x) < 1e-12) out.push_back(n);
  }
  return out;
}

TEST(Rotation, CentrifugalLoadSumsToTheMassTimesTheCentroidsAcceleration) {
  // A box off the axis: Σ f = Ω² m r⊥(centroid), m = ρV (the box is a parallelepiped: its mass
  // centre is the box centre), for a tilted axis through an arbitrary point.
  for (ElementType type : {ElementType::kC3D8, ElementType::kC3D20, ElementType::kC3D10}) {
    const Eigen::Vector3d size(0.4, 0.1, 0.2);
    Mesh mesh = testing::box_mesh(type, 4, 2, 2, size);
    mesh.coordinates.colwise() += Eigen::Vector3d(0.3, -0.2, 0.1);
    SparseMatrix M;
    assemble_stiffness_mass(mesh, kSteel, {}, nullptr, &M);
    const RotationAxis axis{Eigen::Vector3d(0.05, 0.02, -0.3), Eigen::Vector3d(1.0, 2.0, 3.0)};
    const Eigen::VectorXd f = centrifugal_force_per_speed_squared(M, mesh, axis);
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (int n = 0; n < mesh.num_nodes(); ++n) total += f.segment<3>(3 * n);
    const Eigen::Vector3d a = axis.direction.normalized();
    const Eigen::Vector3d c = Eigen::Vector3d(0.3, -0.2, 0.1) + 0.5 * size - axis.point;
    const Eigen::Vector3d expected = kSteel.density * size.prod() * (c - a * a.dot(c));
    EXPECT_LT((total - expected).norm(), 1e-12 * expected.norm()) << element_type_name(type);
  }
}

TEST(Rotation, SpinningRodWithoutPoissonHasTheClosedFormDisplacementAtElementCorners) {
  // A rod along x, spinning about the z axis through (0, c, ·) (c the rod's mid-width), held
  // axially at x = 0 (a hub). With ν = 0 the 3D problem splits into 1D ones with the exact
  // solution
  //   u_x = ρΩ²(L²x − x³/3)/(2E),   u_y = ρΩ²((W/2)² ŷ − ŷ³/3)/(2E),  ŷ = y − c,   u_z = 0,
  //   σ_xx = ρΩ²(L² − x²)/2 (the classical rod spinning about one end), σ_yy = ρΩ²(W²/4 − ŷ²)/2.
  // The 1D Galerkin solution is exact at element end points (its Green's function is piecewise
  // linear), and the 3D one with ν = 0 is the 1D one in each direction on this box when the load is
  // the consistent one: so the element corners are exact to round-off.
  const double L = 1.0, W = 0.04, omega = 800.0;
  const IsotropicMaterial mat{.youngs_modulus = 2e11, .poisson_ratio = 0.0, .density = 7800};
  const Mesh mesh = testing::box_mesh(ElementType::kC3D20, 10, 2, 2, Eigen::Vector3d(L, W, W));
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, mat, {}, &K, &M);
  const double c = W / 2;
  const RotationAxis axis{Eigen::Vector3d(0.0, c, 0.0), Eigen::Vector3d::UnitZ()};
  const Eigen::VectorXd f = omega * omega * centrifugal_force_per_speed_squared(M, mesh, axis);
  std::vector<int> held;
  for (int n : nodes_at_x(mesh, 0.0)) {
    held.push_back(3 * n);      // axial
    held.push_back(3 * n + 2);  // z (the exact u_z is 0): no rigid motion in z or about x, y
    if (std::abs(mesh.coordinates(1, n) - c) < 1e-12) held.push_back(3 * n + 1);  // ŷ = 0
  }
  const Eigen::VectorXd u = solve_static(K, f, DofMap(mesh.num_dofs(), held));
  const double k = mat.density * omega * omega / (2.0 * mat.youngs_modulus);
  double worst = 0.0, scale = k * (L * L * L * 2.0 / 3.0);
  int corners = 0;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const double x = mesh.coordinates(0, n), y = mesh.coordinates(1, n) - c;
    const bool corner = std::abs(x * 10 / L - std::round(x * 10 / L)) < 1e-9 &&
                        std::abs(mesh.coordinates(1, n) * 2 / W -
                                 std::round(mesh.coordinates(1, n) * 2 / W)) < 1e-9;
    if (!corner) continue;
    ++corners;
    const Eigen::Vector3d exact(k * (L * L * x - x * x * x / 3.0),
                                k * (W * W / 4.0 * y - y * y * y / 3.0), 0.0);
    worst = std::max(worst, (u.segment<3>(3 * n) - exact).lpNorm<Eigen::Infinity>());
  }
  EXPECT_GT(corners, 30);
  EXPECT_LT(worst, 1e-10 * scale);
  // The hub stress σ_xx(0) = ρΩ²L²/2 at the nodes of x = 0 (extrapolated from the integration
  // points of quadratic elements: a quadratic stress is not exact in them, O(h²) = 1 %).
  const StressMatrix s = nodal_stress(mesh, mat, {}, u);
  const double hub = mat.density * omega * omega * L * L / 2.0;
  for (int n : nodes_at_x(mesh, 0.5)) {
    EXPECT_NEAR(s(0, n), mat.density * omega * omega * (L * L - 0.25) / 2.0, 2e-3 * hub);
  }
}

// --- CalculiX on the same mesh ---

bool ccx_available() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

// Mesh, material and the nodes of FIX, up to and including the first "*STEP" line.
void write_ccx_model(std::ostream& inp, const Mesh& mesh, const std::vector<int>& clamped) {
  // ccx reads at most 20 characters per field: 13 significant digits fit any coordinate; the mesh
  // it reads then differs from ours by 5e-14 relative, far below what is compared.
  inp.precision(13);
  inp << "*NODE\n";
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    inp << mesh.node_ids[n] << ", " << mesh.coordinates(0, n) << ", " << mesh.coordinates(1, n)
        << ", " << mesh.coordinates(2, n) << "\n";
  }
  inp << "*ELEMENT, TYPE=" << element_type_name(mesh.element_types[0]) << ", ELSET=EALL\n";
  for (int e = 0; e < mesh.num_elements(); ++e) {
    inp << mesh.element_ids[e];
    int count = 1;
    for (int n : mesh.element_nodes(e)) {
      inp << (count % 16 == 0 ? ",\n" : ", ") << mesh.node_ids[n];
      ++count;
    }
    inp << "\n";
  }
  inp << "*NSET, NSET=NOUT\n";
  for (int n = 0; n < mesh.num_nodes(); ++n) inp << mesh.node_ids[n] << ",\n";
  inp << "*NSET, NSET=FIX\n";
  for (int n : clamped) inp << mesh.node_ids[n] << ",\n";
  inp << "*MATERIAL, NAME=STEEL\n*ELASTIC\n"
      << kSteel.youngs_modulus << ", " << kSteel.poisson_ratio << "\n*DENSITY\n"
      << kSteel.density << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*BOUNDARY\nFIX, 1, 3\n";
}

// "*DLOAD\nEALL, CENTRIF, Ω², point, direction" (ccx: the magnitude is Ω² in rad²/s²).
std::string centrif_line(double omega, const RotationAxis& axis) {
  std::ostringstream os;
  os.precision(13);
  const Eigen::Vector3d a = axis.direction.normalized();
  os << "*DLOAD\nEALL, CENTRIF, " << omega * omega << ", " << axis.point(0) << ", " << axis.point(1)
     << ", " << axis.point(2) << ", " << a(0) << ", " << a(1) << ", " << a(2) << "\n";
  return os.str();
}

std::string run_ccx(const std::filesystem::path& dir, const std::string& inp_text) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "job.inp") << inp_text;
  const std::string cmd =
      "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job > ccx.log 2>&1";
  if (std::system(cmd.c_str()) != 0) return {};
  std::ostringstream dat;
  dat << std::ifstream(dir / "job.dat").rdbuf();
  return dat.str();
}

// A distorted C3D8 bar clamped at its end x = 0.1 m, away from a tilted axis through an
// off-origin point: no symmetry hides a wrong sign or a missing term.
struct TiltedBar {
  Mesh mesh;
  std::vector<int> clamped;
  RotationAxis axis{Eigen::Vector3d(-0.2, 0.05, 0.03), Eigen::Vector3d(0.2, -0.1, 1.0)};
  // `size` with nx x 2 x 2 elements, nodes moved by up to `distortion` (m).
  TiltedBar(const Eigen::Vector3d& size, int nx, double distortion) {
    mesh = testing::box_mesh(ElementType::kC3D8, nx, 2, 2, size);
    testing::perturb_nodes(mesh, size, distortion, 7u, false);
    mesh.coordinates.colwise() += Eigen::Vector3d(0.1, 0.0, 0.0);
    const double xmin = mesh.coordinates.row(0).minCoeff();
    for (int n = 0; n < mesh.num_nodes(); ++n) {
      if (mesh.coordinates(0, n) < xmin + 3 * distortion) clamped.push_back(n);
    }
  }
};

TEST(RotationCalculix, CentrifugalStaticDisplacementsMatchCentrifOnTheSameMesh) {
  STICKSLIP_REQUIRE_TOOL(ccx_available(), "CalculiX (ccx)");
  const TiltedBar bar(Eigen::Vector3d(0.6, 0.1, 0.08), 12, 0.004);
  const double omega = 300.0;
  SparseMatrix K, M;
  assemble_stiffness_mass(bar.mesh, kSteel, {}, &K, &M);
  const DofMap held = DofMap::from_nodes(bar.mesh.num_nodes(), bar.clamped);
  const Eigen::VectorXd u = solve_static(
      K, omega * omega * centrifugal_force_per_speed_squared(M, bar.mesh, bar.axis), held);

  std::ostringstream inp;
  write_ccx_model(inp, bar.mesh, bar.clamped);
  inp << "*STEP\n*STATIC\n"
      << centrif_line(omega, bar.axis) << "*NODE PRINT, NSET=NOUT\nU\n"
      << "*END STEP\n";
  const std::filesystem::path dir =
      std::filesystem::path(STICKSLIP_BINARY_DIR) / "fe_rotation_test" / "centrif_static";
  const auto theirs = ccx_dat::displacements(run_ccx(dir, inp.str()));
  ASSERT_EQ(static_cast<int>(theirs.size()), bar.mesh.num_nodes()) << "see " << dir;
  double worst = 0.0;
  for (int n = 0; n < bar.mesh.num_nodes(); ++n) {
    const auto& t = theirs.at(bar.mesh.node_ids[n]);
    worst = std::max(
        worst, (u.segment<3>(3 * n) - Eigen::Vector3d(t[0], t[1], t[2])).lpNorm<Eigen::Infinity>());
  }
  // ccx prints 7 significant digits (E13.6): half a unit of the last one is 5e-7 of a value.
  EXPECT_LT(worst, 1e-6 * u.lpNorm<Eigen::Infinity>());
  EXPECT_GT(u.lpNorm<Eigen::Infinity>(), 1e-6);  // a load that moves the bar
}

// Eigenvalues ω² of K + Ω²(K_σ1 − S) (ours) and of ccx's PERTURBATION step after a CENTRIF
// *STATIC step at Ω, the `n` lowest, on `bar`; and the unloaded ones.
struct PrestressedEigenvalues {
  Eigen::VectorXd ours, unloaded;
  std::vector<double> theirs;
};
PrestressedEigenvalues prestressed_eigenvalues(const TiltedBar& bar, double omega, int n,
                                               const std::string& name) {
  SparseMatrix K, M;
  assemble_stiffness_mass(bar.mesh, kSteel, {}, &K, &M);
  const DofMap held = DofMap::from_nodes(bar.mesh.num_nodes(), bar.clamped);
  const Eigen::VectorXd u1 =
      solve_static(K, centrifugal_force_per_speed_squared(M, bar.mesh, bar.axis), held);
  const SparseMatrix G = geometric_stiffness(bar.mesh, kSteel, {}, u1);
  const SparseMatrix S = spin_softening_matrix(M, bar.axis);
  PrestressedEigenvalues out;
  out.ours = eigenvalues(K + omega * omega * (G - S), M, held).head(n);
  out.unloaded = eigenvalues(K, M, held).head(n);
  std::ostringstream inp;
  write_ccx_model(inp, bar.mesh, bar.clamped);
  inp << "*STEP\n*STATIC\n"
      << centrif_line(omega, bar.axis) << "*END STEP\n"
      << "*STEP, PERTURBATION\n*FREQUENCY\n"
      << n << "\n*END STEP\n";
  const std::filesystem::path dir =
      std::filesystem::path(STICKSLIP_BINARY_DIR) / "fe_rotation_test" / name;
  out.theirs = ccx_dat::eigenvalues(run_ccx(dir, inp.str()));
  EXPECT_EQ(static_cast<int>(out.theirs.size()), n) << "see " << dir;
  out.theirs.resize(static_cast<size_t>(n), std::nan(""));
  return out;
}

TEST(RotationCalculix, PrestressedFrequenciesMatchAPerturbationStepAfterCentrif) {
  // ccx 2.20: a *FREQUENCY step with PERTURBATION after a linear *STATIC step under CENTRIF
  // includes the stress stiffening of the static stresses and the spin softening of the
  // centrifugal load (which stays active in the frequency step); without the static step
  // neither (checked by hand: its eigenvalues are then the unloaded ones). It also takes the
  // stiffness at the displaced state (the initial-displacement matrix of the static
  // displacement), which stickslip leaves out: a change of order ε0 (the largest centrifugal
  // strain) relative, against the stiffening's ε0 (L/h)² for bending. A slender bar (1 m x 3 cm x
  // 2 cm) at a low speed keeps ε0 = 2e-7, below ccx's 7 printed digits, while the first bending
  // modes move by 4e-4 and 1e-4.
  STICKSLIP_REQUIRE_TOOL(ccx_available(), "CalculiX (ccx)");
  const TiltedBar bar(Eigen::Vector3d(1.0, 0.03, 0.02), 20, 0.001);
  const int n = 6;
  const PrestressedEigenvalues slow = prestressed_eigenvalues(bar, 3.0, n, "centrif_frequency");
  for (int i = 0; i < n; ++i) {
    // ccx prints eigenvalues with 7 significant digits.
    EXPECT_NEAR(slow.ours(i), slow.theirs[i], 1e-6 * slow.theirs[i]) << "mode " << i + 1;
  }
  for (int i = 0; i < 2; ++i) {  // the first flapwise and lead-lag modes: far beyond 1e-6
    EXPECT_GT(std::abs(slow.ours(i) - slow.unloaded(i)), 1e-4 * slow.unloaded(i))
        << "mode " << i + 1;
  }
  // Ten times faster (ε0 = 2e-5): the shifts are 100 times larger (up to 3.6 %) and the
  // difference to ccx grows like ε0, within 5 ε0 (measured 0.3 to 2.9 ε0 over the six modes).
  const PrestressedEigenvalues fast = prestressed_eigenvalues(bar, 30.0, n, "centrif_frequency_30");
  const double r_max = 1.1 + 0.2 + 0.03;  // bound of the largest radius from the axis, m
  const double strain = kSteel.density * 900.0 * r_max * r_max / (2 * kSteel.youngs_modulus);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(fast.ours(i), fast.theirs[i], 5 * strain * fast.theirs[i]) << "mode " << i + 1;
  }
  EXPECT_GT(std::abs(fast.ours(0) / fast.unloaded(0) - 1), 1e-2);
}

TEST(Rotation, RotatingCantileverFollowsTheSouthwellCoefficient) {
  // A uniform cantilever clamped on the axis, spinning about z: its first flapwise (z) bending
  // frequency follows ω² = ω0² + S Ω² with the Southwell coefficient S = 1.193 of a uniform
  // Euler–Bernoulli cantilever with zero hub radius (Wright, Smith, Thresher, Wang, J. Appl.
  // Mech. 49, 1982), and the first lead-lag (y, in the plane of rotation) one ω² = ω0² + (S − 1)
  // Ω²: the spin softening takes Ω² off the in-plane direction only. S is the slope at Ω → 0
  // (a small speed here). Tolerance: the 3D solid is not an Euler–Bernoulli beam (shear, rotary
  // inertia and the geometric stiffness of the bending's axial strain, (h/L)² = 1.6e-3) and the
  // mesh's discretisation error (measured: 1.1932, 1.1938 stiffened; 0.1938 and 1.1926 with
  // both; 1.1927 to 1.1934 with 24 and 48 elements).
  const double L = 1.0, h = 0.04;
  // ν = 0: a clamped root restrains no lateral strain, so the 3D solid is the beam up to terms of
  // order (h/L)² (with ν = 0.3 the root's restraint makes S converge like O(h): 1.2006, 1.1972,
  // 1.1958, 1.1952 with 12, 24, 48, 96 elements).
  const IsotropicMaterial kBeam{.youngs_modulus = 2e11, .poisson_ratio = 0.0, .density = 7800};
  const Mesh mesh = testing::box_mesh(ElementType::kC3D20, 12, 1, 1, Eigen::Vector3d(L, h, h));
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, kBeam, {}, &K, &M);
  const DofMap held = DofMap::from_nodes(mesh.num_nodes(), nodes_at_x(mesh, 0.0));
  const RotationAxis axis{Eigen::Vector3d(0.0, h / 2, h / 2), Eigen::Vector3d::UnitZ()};
  const Eigen::VectorXd u1 =
      solve_static(K, centrifugal_force_per_speed_squared(M, mesh, axis), held);
  const SparseMatrix G = geometric_stiffness(mesh, kBeam, {}, u1);
  const SparseMatrix S = spin_softening_matrix(M, axis);
  const double omega2 = 20.0;  // Ω² (rad/s)², 0.05 % of ω0²: the slope at Ω → 0
  const Eigen::VectorXd w0 = eigenvalues(K, M, held);
  const Eigen::VectorXd stiffened = eigenvalues(K + omega2 * G, M, held);
  const Eigen::VectorXd both = eigenvalues(K + omega2 * (G - S), M, held);
  // The square section makes the first flapwise and lead-lag modes a double pair at rest; the
  // stress stiffening raises both alike, the spin softening splits them.
  constexpr double kSouthwell = 1.193;
  constexpr double kBeamTolerance = 1.5e-3;
  EXPECT_NEAR((stiffened(0) - w0(0)) / omega2, kSouthwell, kBeamTolerance);
  EXPECT_NEAR((stiffened(1) - w0(1)) / omega2, kSouthwell, kBeamTolerance);
  EXPECT_NEAR((both(0) - w0(0)) / omega2, kSouthwell - 1.0, kBeamTolerance);
  EXPECT_NEAR((both(1) - w0(1)) / omega2, kSouthwell, kBeamTolerance);
}

TEST(Rotation, SpinSofteningIsTheMassProjectedOffTheAxis) {
  const Mesh mesh = testing::box_mesh(ElementType::kC3D10, 2, 1, 1, Eigen::Vector3d(1, 1, 1));
  SparseMatrix M;
  assemble_stiffness_mass(mesh, kSteel, {}, nullptr, &M);
  const RotationAxis axis{Eigen::Vector3d(0.3, 0.0, 0.0), Eigen::Vector3d(1.0, 1.0, 0.0)};
  const SparseMatrix S = spin_softening_matrix(M, axis);
  // A translation along the axis feels nothing; one normal to it the whole mass.
  const Eigen::Vector3d a = axis.direction.normalized(), b(0.0, 0.0, 1.0);
  Eigen::VectorXd ua(mesh.num_dofs()), ub(mesh.num_dofs());
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    ua.segment<3>(3 * n) = a;
    ub.segment<3>(3 * n) = b;
  }
  EXPECT_LT((S * ua).norm(), 1e-12 * (M * ua).norm());
  EXPECT_LT((S * ub - M * ub).norm(), 1e-12 * (M * ub).norm());
  EXPECT_TRUE(near((S * ub).dot(ub), kSteel.density));  // ρ V, V = 1
  EXPECT_LT((Eigen::MatrixXd(S) - Eigen::MatrixXd(S).transpose()).norm(), 1e-12 * S.norm());
}

TEST(Rotation, BadAxisIsRefused) {
  const Mesh mesh = testing::box_mesh(ElementType::kC3D8, 1, 1, 1, Eigen::Vector3d(1, 1, 1));
  SparseMatrix M;
  assemble_stiffness_mass(mesh, kSteel, {}, nullptr, &M);
  EXPECT_THROW(spin_softening_matrix(M, {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()}),
               InvalidInput);
  EXPECT_THROW(geometric_stiffness(mesh, kSteel, {}, Eigen::VectorXd::Zero(3)), InvalidInput);
  EXPECT_NEAR(rpm_to_rad_per_s(60.0), 2.0 * kPi, 1e-15);
}

}  // namespace
}  // namespace stickslip

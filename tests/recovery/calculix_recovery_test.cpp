// The CalculiX deck of io/calculix_deck.h, run with ccx by the test, against stickslip's recovery.
// ccx's *STEADY STATE DYNAMICS is mode superposition without residual correction (see the deck
// header), so harmonics >= 1 are compared with ModalRecovery using the same number of modes and
// no residual term; harmonic 0 is ccx's exact *STATIC step, compared with DirectRecovery. The
// truncation error of ccx's modal result against the exact direct one is printed for reference.
#include <cmath>
#include <complex>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "fe/assembly.h"
#include "io/calculix_deck.h"
#include "recovery/harmonic_response.h"
#include "recovery_test_util.h"
#include "../required_tool.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;
using testing::kSteel;
using testing::nodes_at;

// ccx prints displacements with 7 significant digits (E13.6): 5e-7 of each value; relative to
// the largest displacement of the field the printing error is below 1e-6. 1e-5 leaves room for
// ccx's eigenvalue tolerance and stays well inside the 1e-4.
constexpr double kCcxTolerance = 1e-5;

bool have_ccx() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

// Displacement blocks of the .dat file in order ("displacements (vx,vy,vz) for set ..."), each
// 3 num_nodes (DOF 3 index + d; nodes not printed stay NaN).
std::vector<Eigen::VectorXd> read_displacement_blocks(const std::filesystem::path& dat,
                                                      const Mesh& mesh) {
  const auto index = node_index_by_id(mesh);
  std::vector<Eigen::VectorXd> blocks;
  std::ifstream in(dat);
  std::string line;
  bool in_block = false, seen_data = false;  // a block: header, blank line, data, blank line
  while (std::getline(in, line)) {
    if (line.find("displacements (vx,vy,vz)") != std::string::npos) {
      blocks.push_back(Eigen::VectorXd::Constant(mesh.num_dofs(), std::nan("")));
      in_block = true;
      seen_data = false;
      continue;
    }
    if (!in_block) continue;
    std::istringstream ss(line);
    int id;
    double x, y, z;
    if (ss >> id >> x >> y >> z && index.count(id) != 0) {
      blocks.back().segment<3>(3 * index.at(id)) << x, y, z;
      seen_data = true;
    } else if (seen_data) {
      in_block = false;
    }
  }
  return blocks;
}

ModalRecoveryOptions modal_options_with(int num_modes) {
  ModalRecoveryOptions options;
  options.num_modes = num_modes;
  options.residual_correction = false;
  return options;
}

double max_relative(const Eigen::VectorXcd& a, const Eigen::VectorXcd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

TEST(CalculixRecovery, SteadyStateDynamicsDeckReproducesTheRecovery) {
  STICKSLIP_REQUIRE_TOOL(have_ccx(), "ccx (CalculiX)");
  const Mesh mesh = testing::bar_mesh(8, 2, 2, {0.4, 0.1, 0.1}, ElementType::kC3D8);
  // ccx's C3D8 (full integration) and its mass matrix (the stiffness rule).
  AssemblyOptions assembly;
  assembly.hex8 = AssemblyOptions::Hex8Formulation::kFull;
  assembly.mass_integration = MassIntegration::kStiffnessRule;
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, kSteel, assembly, &K, &M);
  const std::vector<int> clamped = nodes_at(mesh, 0, 0.0);
  const DofMap dofs = DofMap::from_nodes(mesh.num_nodes(), clamped);
  // Strong damping (ζ ≈ 2.4% in mode 1), so a wrong damping law or phase convention shows.
  const RayleighDamping damping{.alpha = 50.0, .beta = 1e-5};
  // Modes come in degenerate pairs (square section: bending in y and z). A truncation that
  // splits a pair depends on the arbitrary basis each eigen-solver picks inside the pair's
  // eigenspace (12 modes split the pair 12/13 here and ccx then differs by 5e-4), so the count
  // must end at a gap in the spectrum: 11 does (checked below).
  const int num_modes = 11;
  const double f = 400.0;  // Hz; harmonic 2 at 800 Hz lies between modes 2 and 3
  const std::vector<int> harmonics{0, 1, 2};

  const std::vector<int> tip = nodes_at(mesh, 0, 0.4);
  const int mid = nodes_at(mesh, 0, 0.2)[4];
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(mesh.num_dofs(), 3);
  loads.block<3, 1>(3 * tip.back(), 0) << 20.0, -50.0, 100.0;
  loads.block<3, 1>(3 * tip.back(), 1) << Complex(10, -5), Complex(100, 0), Complex(0, 50);
  loads.block<3, 1>(3 * tip[0], 1) << Complex(-30, 12), Complex(0, -25), Complex(40, 40);
  loads.block<3, 1>(3 * mid, 2) << Complex(0, 0), Complex(15, -60), Complex(-35, 5);
  loads.block<3, 1>(3 * tip[0], 2) << Complex(5, 0), Complex(0, 8), Complex(-12, -3);

  CalculixDeckOptions options;
  options.youngs_modulus = kSteel.youngs_modulus;
  options.poisson_ratio = kSteel.poisson_ratio;
  options.density = kSteel.density;
  options.clamped_nodes = clamped;
  options.alpha = damping.alpha;
  options.beta = damping.beta;
  options.frequency_hz = f;
  options.harmonics = harmonics;
  options.num_modes = num_modes;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("stickslip_recovery_ccx_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_calculix_deck((dir / "job.inp").string(), mesh, loads, options);
  const std::string cmd =
      "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job > ccx.log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "ccx failed, see " << dir / "ccx.log";
  const auto blocks = read_displacement_blocks(dir / "job.dat", mesh);
  // Static, then real and imaginary parts of harmonics 1 and 2.
  ASSERT_EQ(blocks.size(), 5u) << "unexpected ccx output, see " << dir;

  const DirectRecovery direct(K, M, dofs, damping);
  ModalRecoveryOptions modal_options;
  modal_options.num_modes = num_modes;
  modal_options.residual_correction = false;
  const ModalRecovery modal(K, M, dofs, damping, modal_options);
  ASSERT_TRUE(direct.ok() && modal.ok()) << modal.message();
  {
    const ModalRecovery probe(K, M, dofs, damping, modal_options_with(num_modes + 1));
    const Eigen::VectorXd& ev = probe.eigenvalues();
    ASSERT_GT(ev(num_modes) - ev(num_modes - 1), 1e-3 * ev(num_modes)) << "truncation in a pair";
  }
  const double omega = hz_to_rad_s(f);
  const Eigen::MatrixXcd x_direct = harmonic_response(direct, loads, harmonics, omega);
  const Eigen::MatrixXcd x_modal = harmonic_response(modal, loads, harmonics, omega);

  Eigen::VectorXcd ccx0(mesh.num_dofs());
  ccx0.real() = blocks[0];
  ccx0.imag().setZero();
  const double e0 = max_relative(ccx0, x_direct.col(0));
  std::printf("harmonic 0: ccx *STATIC vs direct %.2e\n", e0);
  EXPECT_LT(e0, kCcxTolerance);
  for (int h = 1; h <= 2; ++h) {
    Eigen::VectorXcd ccx(mesh.num_dofs());
    ccx.real() = blocks[2 * h - 1];
    ccx.imag() = blocks[2 * h];
    const double e_modal = max_relative(ccx, x_modal.col(h));
    const double e_direct = max_relative(ccx, x_direct.col(h));
    std::printf("harmonic %d: ccx vs modal (%d modes, no residual) %.2e; vs direct %.2e\n", h,
                num_modes, e_modal, e_direct);
    EXPECT_LT(e_modal, kCcxTolerance) << "harmonic " << h;
  }
  if (!HasFailure()) std::filesystem::remove_all(dir);  // kept for inspection on failure
}

}  // namespace
}  // namespace stickslip

// Static solutions against CalculiX (ccx, an external program run by the test) on the same
// distorted mesh: clamped bar with tip forces, every element type.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/SparseCholesky>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/loads.h"
#include "fe_test_util.h"

namespace stickslip {
namespace {

const IsotropicMaterial kSteel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
// ccx prints displacements with 7 significant digits (format E13.6); its direct solver adds
// round-off far below that.
constexpr double kCcxPrintTolerance = 1e-5;

std::string scientific(double v) {
  std::ostringstream os;
  os << std::scientific << v;
  return os.str();
}

void write_list(std::ostream& os, const std::vector<int>& ids) {
  for (size_t i = 0; i < ids.size(); ++i) {
    os << ids[i] << ((i + 1) % 8 == 0 || i + 1 == ids.size() ? ",\n" : ", ");
  }
}

// Writes the job, runs ccx in `dir`, returns the displacements read from the .dat file
// (3 num_nodes, DOF 3*index + d); empty on failure.
Eigen::VectorXd run_ccx(const Mesh& mesh, const std::vector<int>& clamped,
                        const std::vector<NodalForce>& forces, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream inp(dir / "job.inp");
    inp.precision(17);
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
    std::vector<int> all(mesh.node_ids), fix;
    for (int n : clamped) fix.push_back(mesh.node_ids[n]);
    inp << "*NSET, NSET=NOUT\n";
    write_list(inp, all);
    inp << "*NSET, NSET=FIX\n";
    write_list(inp, fix);
    inp << "*MATERIAL, NAME=STEEL\n*ELASTIC\n"
        << kSteel.youngs_modulus << ", " << kSteel.poisson_ratio << "\n*DENSITY\n"
        << kSteel.density << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n"
        << "*STEP\n*STATIC\n*BOUNDARY\nFIX, 1, 3\n*CLOAD\n";
    for (const NodalForce& f : forces) {
      for (int d = 0; d < 3; ++d) {
        if (f.force(d) != 0.0)
          inp << mesh.node_ids[f.node] << ", " << d + 1 << ", " << f.force(d) << "\n";
      }
    }
    inp << "*NODE PRINT, NSET=NOUT\nU\n*END STEP\n";
  }
  const std::string cmd =
      "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 ccx -i job > ccx.log 2>&1";
  if (std::system(cmd.c_str()) != 0) return {};
  std::ifstream dat(dir / "job.dat");
  Eigen::VectorXd u = Eigen::VectorXd::Constant(mesh.num_dofs(), std::nan(""));
  const auto index = node_index_by_id(mesh);
  std::string line;
  while (std::getline(dat, line)) {
    std::istringstream ss(line);
    int id;
    double x, y, z;
    if (ss >> id >> x >> y >> z && index.count(id) != 0) {
      u.segment<3>(3 * index.at(id)) << x, y, z;
    }
  }
  return u;
}

// Max |u - u_ccx| / max |u| for a clamped bar 1 x 0.3 x 0.2 m with tip forces; interior nodes
// moved by up to `distortion` (m).
double ccx_difference(ElementType type, double distortion) {
  const Eigen::Vector3d size(1.0, 0.3, 0.2);
  const bool tet = type == ElementType::kC3D4 || type == ElementType::kC3D10;
  Mesh mesh = testing::box_mesh(type, tet ? 4 : 5, 2, 2, size);
  testing::perturb_nodes(mesh, size, distortion, 41, true);
  std::vector<int> clamped;
  std::vector<NodalForce> forces;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d x = mesh.coordinates.col(n);
    if (std::abs(x(0)) < 1e-12) clamped.push_back(n);
    if (std::abs(x(0) - size(0)) < 1e-12 && std::abs(x(1) - size(1)) < 1e-12) {
      forces.push_back({n, Eigen::Vector3d(100.0, 1000.0, -500.0)});
    }
  }
  SparseMatrix K;
  assemble_stiffness_mass(mesh, kSteel, {}, &K, nullptr);
  const DofMap map = DofMap::from_nodes(mesh.num_nodes(), clamped);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(map.restrict(K));
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  const Eigen::VectorXd f = nodal_force_vector(mesh.num_nodes(), forces);
  const Eigen::VectorXd u = map.expand(Eigen::VectorXd(ldlt.solve(map.restrict(f))));

  const std::filesystem::path dir =
      std::filesystem::path(STICKSLIP_BINARY_DIR) / "fe_ccx_test" /
      (std::string(element_type_name(type)) + (distortion > 0 ? "_distorted" : "_regular"));
  const Eigen::VectorXd u_ccx = run_ccx(mesh, clamped, forces, dir);
  EXPECT_EQ(u_ccx.size(), u.size()) << "ccx failed; see " << (dir / "ccx.log");
  EXPECT_FALSE(u_ccx.hasNaN()) << "incomplete ccx output in " << (dir / "job.dat");
  if (u_ccx.size() != u.size() || u_ccx.hasNaN()) return 1.0;
  return (u - u_ccx).lpNorm<Eigen::Infinity>() / u.lpNorm<Eigen::Infinity>();
}

class CalculixStatic : public ::testing::TestWithParam<ElementType> {};

TEST_P(CalculixStatic, DisplacementsMatchCalculixOnTheSameMesh) {
  const ElementType type = GetParam();
  // C3D8I only on the regular mesh: see the next test.
  const double diff = ccx_difference(type, type == ElementType::kC3D8I ? 0.0 : 0.02);
  RecordProperty("max_relative_difference", scientific(diff));
  EXPECT_LT(diff, kCcxPrintTolerance) << element_type_name(type);
}

// CalculiX's C3D8I evaluates the incompatible-mode derivatives with J0 but integrates them with
// det J, without Taylor's det J0 / det J factor (shape8hu.f), so it does not pass the patch test
// exactly on distorted bricks; ours does. On parallelepipeds (det J = det J0) the two coincide
// (previous test); on this mesh with 2 cm of distortion they differ by a few 1e-4.
TEST(CalculixStatic, C3D8IDiffersFromCalculixOnlyThroughTheTaylorFactor) {
  const double diff = ccx_difference(ElementType::kC3D8I, 0.02);
  RecordProperty("max_relative_difference", scientific(diff));
  EXPECT_GT(diff, 10 * kCcxPrintTolerance);
  EXPECT_LT(diff, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(AllTypes, CalculixStatic,
                         ::testing::Values(ElementType::kC3D8, ElementType::kC3D8I,
                                           ElementType::kC3D20, ElementType::kC3D20R,
                                           ElementType::kC3D4, ElementType::kC3D10),
                         [](const auto& info) { return element_type_name(info.param); });

}  // namespace
}  // namespace stickslip

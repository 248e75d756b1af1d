// The Craig–Bampton reduction over PETSc and SLEPc (model/petsc_reduction.h,
// docs/distributed-reduction.md) against the direct reduction (reduction/craig_bampton.h, itself
// tested against full-model references in tests/reduction/craig_bampton_test.cpp) of the same
// body:
//  - in this process (one PETSc process): K_r, M_r, the fixed-interface eigenvalues and T, the
//    modes' signs aligned; and K_r, M_r equal TᵀKT, TᵀMT formed plainly from its own T;
//  - under `mpirun -n 2` and `-n 3` (the interior rows shared by the processes): every process
//    gets the same body, that of the direct reduction; with CG and algebraic multigrid (GAMG)
//    instead of MUMPS for the constraint modes, and then for the eigen-solve's shift-invert too
//    (no factor at all), the same to the Krylov tolerance;
//  - `stickslip run` of the coarse joint with `reduction_solver: petsc`, alone and under
//    `mpirun -n 2` (one stepped sweep: the processes reduce together), gives the points of the
//    direct run;
//  - a floating interior is refused with the reason; a missing plugin is exit code 5.
// Tolerances. Both reductions solve the same systems: the constraint modes by a sparse Cholesky
// each (CHOLMOD, MUMPS: differences of round-off times the condition of K_ii, ~1e-12 here), the
// modes to a relative residual of 1e-10 each (Spectra's tolerance, SLEPc's). An eigenvalue is
// then good to the square of that (~1e-16 relative, checked to 1e-11), a mode shape to the
// residual over the relative gap to the next eigenvalue (≥ 1 % here: 1e-8), and so are T's
// modal columns and M_bη; checked to 1e-7 of the largest entry.
// Tests that need the plugin are skipped when it is not built (STICKSLIP_PETSC, PETSc/SLEPc).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_test_support.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "mesh/mesh.h"
#include "mesh/mesh_tools.h"
#include "model/petsc_reduction.h"
#include "reduction/craig_bampton.h"

namespace stickslip::cli_test {
namespace {

const fs::path kPetscPlugin = fs::path(STICKSLIP_BINARY_DIR) / "lib" / "libstickslip_petsc.so";
const std::string kDriver = STICKSLIP_PETSC_DRIVER;

bool petsc_available() { return fs::exists(kPetscPlugin); }
bool mpirun_available() { return shell("command -v mpirun", "/dev/null") == 0; }

#define SKIP_WITHOUT_PETSC()                     \
  if (!petsc_available())                        \
  GTEST_SKIP() << "no " << kPetscPlugin.string() \
               << " (STICKSLIP_PETSC, libpetsc-real-dev, libslepc-real-dev)"

// A process that ran PETSc itself (the tests above, in this process) is an MPI singleton whose
// environment (OMPI_*, PMIX_*) would make a child mpirun fail at once: not passed on.
std::string mpirun(int processes) {
  return "for v in $(env | sed -n 's/^\\(OMPI_[^=]*\\|PMIX_[^=]*\\)=.*/\\1/p'); do unset $v; "
         "done; timeout 600 mpirun --allow-run-as-root --oversubscribe -n " +
         std::to_string(processes) + " ";
}

// The driver's box (petsc_reduction_driver.cpp): 9 x 3 x 3 C3D8 elements, clamped at x = 0,
// 8 master nodes on the free end, 10 modes.
constexpr int kEx = 9, kEy = 3, kEz = 3, kMasters = 8, kModes = 10;

struct Box {
  SparseMatrix K, M;
  std::vector<int> constrained, boundary;
};

Box driver_box() {
  const int nx = kEx + 1, ny = kEy + 1, nz = kEz + 1;
  auto node = [&](int i, int j, int k) { return i + nx * (j + ny * k); };
  const Mesh mesh =
      structured_hex_box(kEx, kEy, kEz, Eigen::Vector3d(1.0, 0.2, 0.2), ElementType::kC3D8);
  const IsotropicMaterial steel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
  Box b;
  assemble_stiffness_mass(mesh, steel, AssemblyOptions{}, &b.K, &b.M);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int d = 0; d < 3; ++d) b.constrained.push_back(3 * node(0, j, k) + d);
  for (int a = 0; a < kMasters; ++a)
    for (int d = 0; d < 3; ++d) b.boundary.push_back(3 * node(kEx, a % ny, a / ny) + d);
  return b;
}

CraigBamptonResult direct_reduction(const Box& b) {
  CraigBamptonOptions options;
  options.num_modes = kModes;
  CraigBamptonResult r = craig_bampton(b.K, b.M, b.constrained, b.boundary, options);
  EXPECT_TRUE(r.summary.ok()) << r.summary.message;
  return r;
}

struct Reduced {
  Eigen::MatrixXd K, M, T;
  Eigen::VectorXd eigenvalues;
};

// A file of the driver (its header, then K_r, M_r, eigenvalues, T).
Reduced read_driver_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string tag;
  int nb = 0, m = 0, n = 0;
  in >> tag >> nb >> m >> n;
  in.get();
  EXPECT_EQ(tag, "stickslip-cb") << p;
  Reduced r;
  const int nr = nb + m;
  r.K.resize(nr, nr);
  r.M.resize(nr, nr);
  r.eigenvalues.resize(m);
  r.T.resize(n, nr);
  for (Eigen::MatrixXd* a : {&r.K, &r.M})
    in.read(reinterpret_cast<char*>(a->data()), a->size() * 8);
  in.read(reinterpret_cast<char*>(r.eigenvalues.data()), m * 8);
  in.read(reinterpret_cast<char*>(r.T.data()), r.T.size() * 8);
  EXPECT_TRUE(in.good()) << p << " ends early";
  return r;
}

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// `got` against `want` (the direct reduction): each mode's sign taken from T.
void expect_same_body(const Reduced& got, const CraigBamptonResult& want, double tolerance,
                      const std::string& what) {
  SCOPED_TRACE(what);
  const int nb = static_cast<int>(want.body.K.rows()) - kModes;
  ASSERT_EQ(got.K.rows(), want.body.K.rows());
  ASSERT_EQ(got.T.rows(), want.T.rows());
  Eigen::VectorXd sign = Eigen::VectorXd::Ones(nb + kModes);
  for (int j = 0; j < kModes; ++j) {
    sign(nb + j) = got.T.col(nb + j).dot(want.T.col(nb + j)) < 0 ? -1.0 : 1.0;
  }
  const Eigen::MatrixXd S = sign.asDiagonal();
  EXPECT_LT(relative(got.eigenvalues, want.mode_eigenvalues), 1e-11);
  EXPECT_LT(relative(S * got.K * S, want.body.K), tolerance);
  EXPECT_LT(relative(S * got.M * S, want.body.M), tolerance);
  EXPECT_LT(relative(got.T * S, want.T), tolerance);
  // The static part (boundary block) is solved directly by both: closer.
  EXPECT_LT(relative(got.K.topLeftCorner(nb, nb), want.body.K.topLeftCorner(nb, nb)), 1e-9);
}

TEST(PetscReduction, OneProcessGivesTheDirectReductionsBodyAndItsOwnProjections) {
  SKIP_WITHOUT_PETSC();
  const Box b = driver_box();
  const CraigBamptonResult want = direct_reduction(b);
  CraigBamptonOptions options;
  options.num_modes = kModes;
  PetscReductionInfo info;
  const CraigBamptonResult got =
      craig_bampton_petsc(b.K, b.M, b.constrained, b.boundary, options, &info);
  ASSERT_TRUE(got.summary.ok()) << got.summary.message;
  EXPECT_EQ(info.processes, 1);
  EXPECT_EQ(info.solver, "preonly+cholesky(mumps)");
  EXPECT_LT(info.max_eigen_residual, 1e-10);
  expect_same_body({got.body.K, got.body.M, got.T, got.mode_eigenvalues}, want, 1e-7, "alone");
  // Its reduced matrices are the projections through its own basis, formed plainly.
  const Eigen::MatrixXd T = got.T;
  const Eigen::MatrixXd KT = b.K * T, MT = b.M * T;
  EXPECT_LT(relative(got.body.K, T.transpose() * KT), 1e-10);
  EXPECT_LT(relative(got.body.M, T.transpose() * MT), 1e-10);
  // Same DOF map as the direct reduction.
  ASSERT_EQ(got.body.dofs.size(), want.body.dofs.size());
  for (size_t k = 0; k < got.body.dofs.size(); ++k) {
    EXPECT_EQ(got.body.dofs[k].kind, want.body.dofs[k].kind);
    EXPECT_EQ(got.body.dofs[k].full_dof, want.body.dofs[k].full_dof);
    EXPECT_NEAR(got.body.dofs[k].frequency_hz, want.body.dofs[k].frequency_hz,
                1e-9 * want.body.dofs[k].frequency_hz);
  }
}

TEST(PetscReduction, AFloatingInteriorIsReportedWithTheReason) {
  SKIP_WITHOUT_PETSC();
  Box b = driver_box();
  b.constrained.clear();  // free–free: K_ii singular (its rigid motions)
  b.boundary.clear();
  CraigBamptonOptions options;
  options.num_modes = kModes;
  const CraigBamptonResult got = craig_bampton_petsc(b.K, b.M, b.constrained, b.boundary, options);
  EXPECT_FALSE(got.summary.ok());
  EXPECT_NE(got.summary.message.find("floating interior"), std::string::npos)
      << got.summary.message;
}

TEST(PetscReduction, TooManyModesIsInvalidInput) {
  const Box b = driver_box();
  CraigBamptonOptions options;
  options.num_modes = static_cast<int>(b.K.rows());
  EXPECT_THROW(craig_bampton_petsc(b.K, b.M, b.constrained, b.boundary, options), InvalidInput);
}

// The driver under mpirun with P processes: every process's file, compared with the direct
// reduction; the JSON line of rank 0.
nlohmann::json run_driver(int processes, const fs::path& dir, const std::string& env,
                          double tolerance) {
  const CraigBamptonResult want = direct_reduction(driver_box());
  const fs::path out = dir / ("p" + std::to_string(processes));
  const fs::path log = dir / ("p" + std::to_string(processes) + ".log");
  const std::string command = mpirun(processes) + env + kDriver + " petsc " + std::to_string(kEx) +
                              " " + std::to_string(kEy) + " " + std::to_string(kEz) + " " +
                              std::to_string(kMasters) + " " + std::to_string(kModes) + " " +
                              out.string() + " basis";
  EXPECT_EQ(shell(command, log), 0) << command << "\n" << slurp(log);
  for (int rank = 0; rank < processes; ++rank) {
    const fs::path file = out.string() + "." + std::to_string(rank);
    EXPECT_TRUE(fs::exists(file)) << file;
    if (!fs::exists(file)) continue;
    expect_same_body(read_driver_file(file), want, tolerance,
                     std::to_string(processes) + " processes, rank " + std::to_string(rank));
  }
  std::istringstream lines(slurp(log));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("{\"rank\": 0,", 0) == 0) return nlohmann::json::parse(line);
  }
  ADD_FAILURE() << "no line of rank 0 in\n" << slurp(log);
  return {};
}

TEST(PetscReduction, TwoAndThreeProcessesUnderMpirunGiveEveryProcessTheDirectReductionsBody) {
  SKIP_WITHOUT_PETSC();
  if (!mpirun_available()) GTEST_SKIP() << "no mpirun";
  const fs::path dir = fresh_dir("petsc_mpirun");
  for (int p : {2, 3}) {
    const nlohmann::json info = run_driver(p, dir, "", 1e-7);
    EXPECT_EQ(info.value("processes", 0), p);
    EXPECT_EQ(info.value("petsc_solver", ""), "preonly+cholesky(mumps)");
  }
}

TEST(PetscReduction, CgWithAlgebraicMultigridUnderMpirunGivesTheSameBodyToItsTolerance) {
  SKIP_WITHOUT_PETSC();
  if (!mpirun_available()) GTEST_SKIP() << "no mpirun";
  const fs::path dir = fresh_dir("petsc_gamg");
  // Relative residual 1e-12 per solve (the plugin's default for a Krylov solver): the error of
  // a solution is at most cond(K_ii) times that (~1e5 for this box): 1e-7 still holds.
  const nlohmann::json info = run_driver(
      2, dir, "-x PETSC_OPTIONS='-cb_constraint_ksp_type cg -cb_constraint_pc_type gamg' ", 1e-7);
  EXPECT_EQ(info.value("petsc_solver", ""), "cg+gamg");
  EXPECT_GT(info.value("krylov_iterations", 0), 0);
  const nlohmann::json all_iterative =
      run_driver(2, fresh_dir("petsc_gamg_modes"),
                 "-x PETSC_OPTIONS='-cb_constraint_ksp_type cg -cb_constraint_pc_type gamg "
                 "-cb_modes_st_ksp_type cg -cb_modes_st_pc_type gamg' ",
                 1e-7);
  EXPECT_EQ(all_iterative.value("petsc_solver", ""), "cg+gamg");
}

// The coarse joint (two C3D8 beams, 4 modes each) in 7 frequency steps, `reduction_solver` as
// given for both beams.
std::string joint_case(const std::string& solver) {
  std::string text = coarse_joint_head(3, 1) + "output: {plots: false}\n";
  for (size_t at = text.find("modes: 4}"); at != std::string::npos;
       at = text.find("modes: 4}", at + 1)) {
    text.replace(at, 9, "modes: 4, reduction_solver: " + solver + "}");
  }
  return text;
}

// A results table of `actual` against `expected`: every number within `tolerance` of its
// column's largest magnitude. Not compared: the columns that measure the solve's round-off
// (Newton's residual, the static mismatch: ~1e-13 of their scale, noise in both runs) and
// Newton's iterations (0 or 1 at a point whose start already meets the tolerance to round-off;
// under mpirun a segment's points start from elsewhere, cli/distributed_run.h).
void expect_close_csv(const fs::path& expected, const fs::path& actual, double tolerance) {
  SCOPED_TRACE(actual.string());
  const auto e = read_csv(expected), a = read_csv(actual);
  ASSERT_FALSE(e.empty());
  ASSERT_EQ(e.size(), a.size());
  std::map<std::string, double> scale;
  for (const auto& row : e) {
    for (const auto& [column, cell] : row) {
      double x;
      if (parse_number(cell, &x)) scale[column] = std::max(scale[column], std::abs(x));
    }
  }
  int compared = 0;
  for (size_t i = 0; i < e.size(); ++i) {
    for (const auto& [column, cell] : e[i]) {
      double x, y;
      if (!parse_number(cell, &x) || column == "residual_m" || column == "residual_relative" ||
          column == "static_mismatch" || column == "iterations") {
        continue;
      }
      ASSERT_TRUE(parse_number(a[i].at(column), &y)) << column;
      EXPECT_LE(std::abs(x - y), tolerance * scale[column] + 1e-300)
          << "row " << i << " " << column << ": " << x << " vs " << y;
      ++compared;
    }
  }
  EXPECT_GT(compared, 20);
}

TEST(PetscReduction, RunAloneAndUnderMpirunGivesThePointsOfTheDirectReduction) {
  SKIP_WITHOUT_PETSC();
  const fs::path dir = fresh_dir("petsc_run");
  const fs::path direct = write_case(dir, "direct", joint_case("direct"));
  const fs::path petsc = write_case(dir, "petsc", joint_case("petsc"));
  ASSERT_EQ(run("run " + direct.string() + " -o " + (dir / "direct").string(), dir / "direct.log"),
            0)
      << slurp(dir / "direct.log");
  ASSERT_EQ(run("run " + petsc.string() + " -o " + (dir / "petsc").string(), dir / "petsc.log"), 0)
      << slurp(dir / "petsc.log");
  // The responses through the modes: to the modes' accuracy (1e-8, above) times the
  // amplification of the nearby resonance; 1e-6 of each column's largest value.
  for (const std::string f : {"points.csv", "master_response.csv"}) {
    expect_close_csv(dir / "direct" / f, dir / "petsc" / f, 1e-6);
  }
  if (!mpirun_available() ||
      !fs::exists(fs::path(STICKSLIP_BINARY_DIR) / "lib" / "libstickslip_mpi.so")) {
    GTEST_SKIP() << "no mpirun or no MPI plugin: the run under mpirun is not tried";
  }
  ASSERT_EQ(
      shell(mpirun(2) + kProgram + " run " + petsc.string() + " -o " + (dir / "petsc2").string(),
            dir / "petsc2.log"),
      0)
      << slurp(dir / "petsc2.log");
  for (const std::string f : {"points.csv", "master_response.csv"}) {
    expect_close_csv(dir / "direct" / f, dir / "petsc2" / f, 1e-6);
  }
}

TEST(PetscReduction, AMissingPluginIsExitCodeFiveWithThePathsTried) {
  const fs::path dir = fresh_dir("petsc_missing");
  const fs::path c = write_case(dir, "petsc", joint_case("petsc"));
  const fs::path log = dir / "log";
  EXPECT_EQ(shell("STICKSLIP_PETSC_PLUGIN=" + (dir / "nowhere.so").string() + " " + kProgram +
                      " run " + c.string() + " -o " + (dir / "out").string(),
                  log),
            5)
      << slurp(log);
  EXPECT_NE(slurp(log).find("nowhere.so: no such file"), std::string::npos) << slurp(log);
}

TEST(PetscReduction, AnUnknownSolverIsRefusedAtTheKey) {
  const fs::path dir = fresh_dir("petsc_key");
  const fs::path c = write_case(dir, "bad", joint_case("iterative"));
  const fs::path log = dir / "log";
  EXPECT_EQ(run("run " + c.string() + " -o " + (dir / "out").string(), log), 2) << slurp(log);
  EXPECT_NE(slurp(log).find("reduction_solver"), std::string::npos) << slurp(log);
}

}  // namespace
}  // namespace stickslip::cli_test

// cli/results_files.h: reading back a solve folder written by hand (values chosen here, not by
// the program), the errors with file and line, reduce's manifest, the dense matrix file, and the
// fingerprint hash against the published FNV-1a 64 test vectors.
#include "cli/results_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_support.h"
#include "core/errors.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) { return cli_test::fresh_dir("results_files_" + name); }

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// Two points, one 1D pair (axis u) of contact "c" between nodes 7 and 9, harmonics 0 and 1.
fs::path solve_folder(const std::string& name) {
  const fs::path dir = fresh(name);
  write(dir / "summary.json",
        "{\n  \"program\": \"stickslip\",\n  \"title\": \"a \\\"quoted\\\" title\",\n"
        "  \"fingerprint\": \"0123456789abcdef\",\n  \"frf\": [\"b:7:y\"]\n}\n");
  write(dir / "points.csv",
        "point,frequency_hz,converged,iterations,residual,dissipated_energy,residual_relative\n"
        "0,100.5,1,3,1e-12,0.5,1e-9\n1,101.25,0,30,1e-3,0,1e-2\n");
  std::string forces = "point,contact,pair,node_a,node_b,frame,axis,harmonic,real,imag\n";
  for (int p = 0; p < 2; ++p) {
    forces += std::to_string(p) + ",c,0,7,9,local,u,0,1.5,0\n";
    forces += std::to_string(p) + ",c,0,7,9,local,u,1,0.25,-0.125\n";
    for (const char* axis : {"x", "y", "z"}) {
      forces += std::to_string(p) + ",c,0,7,9,global," + axis + ",0," +
                (std::string(axis) == "y" ? "1.5" : "0") + ",0\n";
      forces += std::to_string(p) + ",c,0,7,9,global," + axis + ",1," +
                (std::string(axis) == "y" ? "0.25,-0.125" : "0,0") + "\n";
    }
  }
  write(dir / "contact_forces.csv", forces);
  write(dir / "contact_state.csv",
        "point,contact,pair,node_a,node_b,stick,slip,separation,dissipated_energy\n"
        "0,c,0,7,9,0.75,0.25,0,0.5\n1,c,0,7,9,1,0,0,0\n");
  write(dir / "master_response.csv",
        "point,body,node,dof,harmonic,real,imag\n0,b,7,y,1,3e-6,-4e-6\n1,b,7,y,1,1e-6,0\n");
  write(dir / "histories.csv",
        "point,contact,pair,sample,t_over_period,axis,displacement,force\n"
        "0,c,0,0,0,u,1e-6,2\n0,c,0,1,0.5,u,-1e-6,-2\n");
  return dir;
}

std::string error_of(const fs::path& dir) {
  try {
    read_solve_results(dir, "stickslip solve x.yaml -o out");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(ResultsFiles, ReadsBackWhatAHandWrittenSolveFolderSays) {
  const SolveResults r = read_solve_results(solve_folder("good"), "hint");
  EXPECT_EQ(r.title, "a \"quoted\" title");
  EXPECT_EQ(r.fingerprint, "0123456789abcdef");
  ASSERT_EQ(r.frf.size(), 1u);
  EXPECT_EQ(r.frf[0].body, "b");
  EXPECT_EQ(r.frf[0].node, 7);
  EXPECT_EQ(r.frf[0].direction, 1);
  ASSERT_EQ(r.response.points.size(), 2u);
  EXPECT_DOUBLE_EQ(r.response.points[0].omega, 2 * 3.14159265358979323846 * 100.5);
  EXPECT_TRUE(r.response.points[0].converged);
  EXPECT_FALSE(r.response.points[1].converged);
  EXPECT_EQ(r.response.points[1].iterations, 30);
  EXPECT_EQ(r.response.harmonics, (std::vector<int>{0, 1}));
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_EQ(r.pairs[0].contact, "c");
  EXPECT_EQ(r.pairs[0].node_a, 7);
  EXPECT_EQ(r.pairs[0].node_b, 9);
  EXPECT_EQ(r.pairs[0].local_rows, 1);
  const PairResponse& pr = r.response.points[1].pairs[0];
  EXPECT_EQ(pr.force_local(0, 1), std::complex<double>(0.25, -0.125));
  EXPECT_EQ(pr.force_global(1, 0), std::complex<double>(1.5, 0));
  EXPECT_EQ(pr.force_global(2, 1), std::complex<double>(0, 0));
  EXPECT_EQ(r.response.points[0].pairs[0].cycle.slip_fraction, 0.25);
  EXPECT_EQ(r.response.points[0].pairs[0].history.u.cols(), 2);
  EXPECT_EQ(r.response.points[0].pairs[0].history.f(0, 1), -2.0);
  EXPECT_EQ(r.master.at(MasterDofKey{"b", 7, 1})(0, 1), std::complex<double>(3e-6, -4e-6));
}

TEST(ResultsFiles, ACaseWithoutContactPairsTakesItsHarmonicsFromTheMasterResponse) {
  const fs::path dir = solve_folder("no_pairs");
  write(dir / "contact_forces.csv",
        "point,contact,pair,node_a,node_b,frame,axis,harmonic,real,imag\n");
  write(dir / "contact_state.csv",
        "point,contact,pair,node_a,node_b,stick,slip,separation,dissipated_energy\n");
  fs::remove(dir / "histories.csv");
  write(dir / "master_response.csv",
        "point,body,node,dof,harmonic,real,imag\n0,b,7,y,0,1,0\n0,b,7,y,2,3,4\n"
        "1,b,7,y,0,1,0\n1,b,7,y,2,5,6\n");
  const SolveResults r = read_solve_results(dir, "hint");
  EXPECT_TRUE(r.pairs.empty());
  EXPECT_EQ(r.response.harmonics, (std::vector<int>{0, 2}));
  EXPECT_EQ(r.master.at(MasterDofKey{"b", 7, 1})(1, 1), std::complex<double>(5, 6));
}

// The error of reading the solve folder `name` in which `file` holds `text`.
std::string error_with(const std::string& name, const std::string& file, const std::string& text) {
  const fs::path dir = solve_folder(name);
  write(dir / file, text);
  return error_of(dir);
}

TEST(ResultsFiles, ErrorsNameTheFileTheLineAndTheCommand) {
  fs::path dir = solve_folder("missing");
  fs::remove(dir / "points.csv");
  std::string e = error_of(dir);
  EXPECT_NE(e.find("points.csv: missing: run `stickslip solve x.yaml -o out` first"),
            std::string::npos)
      << e;

  e = error_with("column", "contact_state.csv", "point,contact,pair,stick,slip\n0,c,0,1,0\n");
  EXPECT_NE(e.find("contact_state.csv:1"), std::string::npos) << e;
  EXPECT_NE(e.find("no column 'separation'"), std::string::npos) << e;

  e = error_with("fields", "master_response.csv",
                 "point,body,node,dof,harmonic,real,imag\n0,b,7,y,1,3e-6,-4e-6\n1,b,7,y,1,1e-6\n");
  EXPECT_NE(e.find("master_response.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("6 fields, the header has 7"), std::string::npos) << e;

  dir = solve_folder("twice");
  std::ofstream(dir / "contact_forces.csv", std::ios::app) << "1,c,0,7,9,local,u,1,0.25,-0.125\n";
  e = error_of(dir);
  EXPECT_NE(e.find("contact_forces.csv:18"), std::string::npos) << e;
  EXPECT_NE(e.find("given twice"), std::string::npos) << e;

  e = error_with("point", "contact_state.csv",
                 "point,contact,pair,node_a,node_b,stick,slip,separation,dissipated_energy\n"
                 "0,c,0,7,9,0.75,0.25,0,0.5\n2,c,0,7,9,1,0,0,0\n");
  EXPECT_NE(e.find("contact_state.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("point 2 is not in points.csv"), std::string::npos) << e;

  e = error_with("frf", "summary.json",
                 "{\n  \"fingerprint\": \"00\",\n  \"frf\": [\"b:1\"]\n}\n");
  EXPECT_NE(e.find("summary.json:3: frf"), std::string::npos) << e;

  e = error_with("axis", "histories.csv",
                 "point,contact,pair,sample,t_over_period,axis,displacement,force\n"
                 "0,c,0,0,0,t2,1,2\n");
  EXPECT_NE(e.find("histories.csv:2"), std::string::npos) << e;
}

TEST(ResultsFiles, ManifestAndDenseMatrixRoundTripAndDamageIsReported) {
  const fs::path dir = fresh("manifest");
  ReduceManifest m;
  m.case_file = "/some where/case.yaml";
  m.body_fingerprint = {{"beam1", "00000000000000ff"}, {"beam2", "abcdef0123456789"}};
  write_reduce_manifest(dir / "manifest.txt", m);
  const ReduceManifest back = read_reduce_manifest(dir / "manifest.txt");
  EXPECT_EQ(back.case_file, m.case_file);
  EXPECT_EQ(back.body_fingerprint, m.body_fingerprint);
  std::ofstream(dir / "manifest.txt", std::ios::app) << "body only_a_name\n";
  try {
    read_reduce_manifest(dir / "manifest.txt");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, 7) << e.what();  // 3 comment lines, case, 2 bodies, the bad one
  }

  Eigen::MatrixXd T(3, 2);
  T << 1.0 / 3.0, -2e-300, 5.5, 1e300, -0.0, 7;
  write_dense_matrix(dir / "T.bin", T);
  const Eigen::MatrixXd T2 = read_dense_matrix(dir / "T.bin");
  ASSERT_EQ(T2.rows(), 3);
  ASSERT_EQ(T2.cols(), 2);
  EXPECT_EQ((T2 - T).cwiseAbs().maxCoeff(), 0.0);  // bit-exact
  fs::resize_file(dir / "T.bin", fs::file_size(dir / "T.bin") - 8);
  EXPECT_THROW(read_dense_matrix(dir / "T.bin"), InvalidInput);
}

TEST(ResultsFiles, FingerprintIsFnv1a64) {
  // Published FNV-1a 64-bit test vectors (Fowler, Noll, Vo).
  EXPECT_EQ(fingerprint_hex(""), "cbf29ce484222325");
  EXPECT_EQ(fingerprint_hex("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(fingerprint_hex("foobar"), "85944171f73967e8");
  const fs::path dir = fresh("fnv");
  write(dir / "f.txt", "foobar");
  EXPECT_EQ(file_fingerprint_hex((dir / "f.txt").string()), "85944171f73967e8");
}

}  // namespace
}  // namespace stickslip

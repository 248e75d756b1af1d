// End-to-end: an Abaqus/CAE deck with *PART, *ASSEMBLY and two *INSTANCEs (one translated and
// rotated, tied to the other by *EQUATIONs on qualified node names) as a case's mesh.
// CalculiX does not read parts, so the references are the same beam written flat by hand
// (tests/abaqus_parts_decks.h): its K and M assembled by us, and CalculiX *FREQUENCY run by the
// test on the flat deck.
#include <gtest/gtest.h>

#include "../abaqus_parts_decks.h"
#include "cli_test_support.h"
#include "fe/assembly.h"
#include "io/inp_reader.h"

#include <cstdio>
#include <fstream>
#include <string>

namespace {

using namespace stickslip::cli_test;
namespace decks = stickslip::parts_decks;

TEST(AbaqusPartsCli, PartDeckHasTheFlatDecksStiffnessAndMass) {
  const fs::path dir = fresh_dir("parts_km");
  std::ofstream(dir / "parts.inp") << decks::part_deck();
  std::ofstream(dir / "flat.inp") << decks::flat_deck();
  const stickslip::IsotropicMaterial steel{2e11, 0.3, 7800};
  stickslip::SparseMatrix K[2], M[2];
  const char* files[2] = {"parts.inp", "flat.inp"};
  for (int f = 0; f < 2; ++f) {
    const stickslip::Mesh mesh = stickslip::read_inp((dir / files[f]).string());
    stickslip::assemble_stiffness_mass(mesh, steel, {}, &K[f], &M[f]);
  }
  // The rotated instance's coordinates differ from the hand-written ones by round-off (1e-17 m
  // on 0.1 m elements): relative differences of K and M of that order.
  constexpr double kRoundOff = 1e-13;
  const double k_scale = Eigen::MatrixXd(K[1]).cwiseAbs().maxCoeff();
  const double m_scale = Eigen::MatrixXd(M[1]).cwiseAbs().maxCoeff();
  EXPECT_LE(Eigen::MatrixXd(K[0] - K[1]).cwiseAbs().maxCoeff(), kRoundOff * k_scale);
  EXPECT_LE(Eigen::MatrixXd(M[0] - M[1]).cwiseAbs().maxCoeff(), kRoundOff * m_scale);
  fs::remove_all(dir);
}

TEST(AbaqusPartsCli, PartDeckModesMatchCalculixOnTheFlatDeck) {
  constexpr int kModes = 6;
  const fs::path dir = fresh_dir("parts_ccx");
  std::ofstream(dir / "parts.inp") << decks::part_deck();
  std::ofstream(dir / "job.inp")
      << decks::flat_deck() << decks::kMaterial
      << "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n*STEP\n*FREQUENCY\n"
      << kModes << "\n*BOUNDARY\nFIX, 1, 3\n*END STEP\n";
  const std::string log =
      run_stage("modes", write_case(dir, "l", tip_spring_bar_case((dir / "parts.inp").string())),
                dir / "out");
  EXPECT_EQ(log.find("PART"), std::string::npos) << log;  // nothing of the parts ignored
  const auto rows = read_csv(dir / "out" / "modes" / "frequencies.csv");
  ASSERT_GE(static_cast<int>(rows.size()), kModes);
  const std::vector<double> lambda = ccx_job_eigenvalues(dir);
  ASSERT_EQ(static_cast<int>(lambda.size()), kModes) << slurp(dir / "ccx.log");
  // ccx prints eigenvalues with 7 significant digits (frequencies to 2.5e-7); the reduction keeps
  // every fixed-interface mode, so it is exact.
  constexpr double kFrequencyTolerance = 1e-6;
  const double worst = expect_frequencies_match(rows, lambda, kModes, kFrequencyTolerance);
  std::printf("[ CalculiX ] L beam of two instances: max relative frequency difference %.2e\n",
              worst);
  RecordProperty("max_relative_frequency_difference_to_ccx", std::to_string(worst));
  fs::remove_all(dir);
}

}  // namespace

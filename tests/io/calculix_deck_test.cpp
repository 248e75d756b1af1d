// CalculiX deck content against hand-written expected lines for a one-element mesh. (The deck run
// by ccx against stickslip's recovery: tests/recovery/calculix_recovery_test.cpp.)
#include "io/calculix_deck.h"

#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

Mesh one_hex() {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.add_node(101 + i,
                  Eigen::Vector3d((i & 1) ? 1.0 : 0.0, (i & 2) ? 1.0 : 0.0, (i & 4) ? 1.0 : 0.0));
  }
  const std::vector<int> nodes{0, 1, 3, 2, 4, 5, 7, 6};
  mesh.add_element(7, ElementType::kC3D8, nodes);
  return mesh;
}

CalculixDeckOptions steel_options() {
  CalculixDeckOptions options;
  options.youngs_modulus = 2e11;
  options.poisson_ratio = 0.3;
  options.density = 7800.0;
  options.clamped_nodes = {1, 0, 1};
  options.alpha = 5.0;
  options.beta = 1e-6;
  options.frequency_hz = 1854.5;
  options.harmonics = {0, 2};
  options.num_modes = 5;
  return options;
}

TEST(CalculixDeck, StepsAndLoadsMatchHandWrittenLines) {
  const Mesh mesh = one_hex();
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(24, 2);
  loads.block<3, 1>(3 * 2, 0) << 0.0, 0.0, 50.0;  // id 103, mean
  // id 108, harmonic 2: x(t) = a cos 2Ωt + b sin 2Ωt with a = (1.5, 0, −2), b = (0.25, 3, 0),
  // X = a − i b: real part a (LOAD CASE=1), imaginary part −b (LOAD CASE=2).
  loads.block<3, 1>(3 * 7, 1) << Complex(1.5, -0.25), Complex(0.0, -3.0), Complex(-2.0, 0.0);
  std::ostringstream out;
  write_calculix_deck(out, mesh, loads, steel_options());
  const std::string deck = out.str();
  EXPECT_NE(deck.find("*NSET, NSET=SS_FIXED\n101, 102\n"), std::string::npos) << deck;
  EXPECT_NE(deck.find("*ELSET, ELSET=SS_EALL\n7\n"), std::string::npos) << deck;
  EXPECT_NE(deck.find("*NSET, NSET=SS_OUT\n101, 102, 103, 104, 105, 106, 107, 108\n"),
            std::string::npos);
  const std::string expected_tail =
      "*MATERIAL, NAME=SS_MATERIAL\n"
      "*ELASTIC\n"
      "2e+11, 0.3\n"
      "*DENSITY\n"
      "7800\n"
      "*SOLID SECTION, ELSET=SS_EALL, MATERIAL=SS_MATERIAL\n"
      "*BOUNDARY\n"
      "SS_FIXED, 1, 3\n"
      "** modes for *STEADY STATE DYNAMICS\n"
      "*STEP\n"
      "*FREQUENCY, STORAGE=YES\n"
      "5\n"
      "*END STEP\n"
      "** harmonic 0 (static mean)\n"
      "*STEP\n"
      "*STATIC\n"
      "*CLOAD, OP=NEW\n"
      "103, 1, 0\n"
      "103, 2, 0\n"
      "103, 3, 50\n"
      "*NODE PRINT, NSET=SS_OUT\nU\n*NODE FILE\nU\n*EL FILE\nS\n"
      "*END STEP\n"
      "** harmonic 2\n"
      "*STEP\n"
      "*STEADY STATE DYNAMICS\n"
      "3709, 3709, 2\n"
      "*MODAL DAMPING, RAYLEIGH\n"
      ", , 5, 1e-06\n"
      "*CLOAD, OP=NEW, LOAD CASE=1\n"
      "108, 1, 1.5\n"
      "108, 2, 0\n"
      "108, 3, -2\n"
      "*CLOAD, OP=NEW, LOAD CASE=2\n"
      "108, 1, -0.25\n"
      "108, 2, -3\n"
      "108, 3, 0\n"
      "*NODE PRINT, NSET=SS_OUT\nU\n*NODE FILE\nU\n*EL FILE\nS\n"
      "*END STEP\n";
  const size_t at = deck.find("*MATERIAL");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(deck.substr(at), expected_tail);
}

TEST(CalculixDeck, StaticOnlyHasNoFrequencyStep) {
  const Mesh mesh = one_hex();
  CalculixDeckOptions options = steel_options();
  options.harmonics = {0};
  options.frequency_hz = 0.0;  // not needed without dynamic harmonics
  options.output_nodes = {7, 3};
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(24, 1);
  loads(23, 0) = -10.0;
  std::ostringstream out;
  write_calculix_deck(out, mesh, loads, options);
  const std::string deck = out.str();
  EXPECT_EQ(deck.find("*FREQUENCY"), std::string::npos);
  EXPECT_NE(deck.find("*NSET, NSET=SS_OUT\n104, 108\n"), std::string::npos);
  EXPECT_NE(deck.find("108, 3, -10\n"), std::string::npos);
}

// ccx has no B-bar brick: C3D8B goes out as C3D8, and the deck says so.
TEST(CalculixDeck, BbarBricksAreWrittenAsC3D8WithAComment) {
  Mesh mesh = one_hex();
  mesh.element_types[0] = ElementType::kC3D8B;
  CalculixDeckOptions options = steel_options();
  options.harmonics = {0};
  options.frequency_hz = 0.0;
  std::ostringstream out;
  write_calculix_deck(out, mesh, Eigen::MatrixXcd::Zero(24, 1), options);
  const std::string deck = out.str();
  EXPECT_NE(deck.find("*ELEMENT, TYPE=C3D8\n7, "), std::string::npos) << deck;
  EXPECT_EQ(deck.find("TYPE=C3D8B"), std::string::npos) << deck;
  EXPECT_NE(deck.find("** C3D8B (B-bar, ANSYS SOLID185) elements are written as C3D8"),
            std::string::npos)
      << deck;
}

// ccx has no pyramid: a C3D13 goes out as the C3D20 it is (fe/element.h), nodes 5-8 and 13-16
// on the apex, its base mid-edge nodes as 9-12 and lateral ones as 17-20; C3D8R is ccx's own.
TEST(CalculixDeck, QuadraticPyramidsAreWrittenAsCollapsedC3D20AndC3D8RAsItself) {
  Mesh mesh = one_hex();
  mesh.element_types[0] = ElementType::kC3D8R;
  // A pyramid on the hexahedron's top face (nodes 104 105 107 106 in C3D8 order 5 6 7 8),
  // apex 109 above it, mid-edge nodes 110-117.
  for (int i = 0; i < 9; ++i) mesh.add_node(109 + i, Eigen::Vector3d(0.1 * i, 0.5, 2.0));
  const std::vector<int> pyramid{4, 5, 7, 6, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  mesh.add_element(8, ElementType::kC3D13, pyramid);
  CalculixDeckOptions options = steel_options();
  options.harmonics = {0};
  options.frequency_hz = 0.0;
  std::ostringstream out;
  write_calculix_deck(out, mesh, Eigen::MatrixXcd::Zero(3 * mesh.num_nodes(), 1), options);
  const std::string deck = out.str();
  EXPECT_NE(deck.find("*ELEMENT, TYPE=C3D8R\n7, 101, 102, 104, 103, 105, 106, 108, 107\n"),
            std::string::npos)
      << deck;
  EXPECT_NE(deck.find("*ELEMENT, TYPE=C3D20\n8, 105, 106, 108, 107, 109, 109, 109, 109, 110, 111, "
                      "112, 113, 109, 109, 109,\n109, 114, 115, 116, 117\n"),
            std::string::npos)
      << deck;
  EXPECT_EQ(deck.find("C3D13"), std::string::npos) << deck;
}

TEST(CalculixDeck, BadInputThrows) {
  Mesh mesh = one_hex();
  const Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(24, 2);
  std::ostringstream out;
  CalculixDeckOptions options = steel_options();
  options.poisson_ratio = 0.5;
  EXPECT_THROW(write_calculix_deck(out, mesh, loads, options), InvalidInput);
  options = steel_options();
  options.clamped_nodes = {8};
  EXPECT_THROW(write_calculix_deck(out, mesh, loads, options), InvalidInput);
  options = steel_options();
  options.num_modes = 0;
  EXPECT_THROW(write_calculix_deck(out, mesh, loads, options), InvalidInput);
  options = steel_options();
  EXPECT_THROW(write_calculix_deck(out, mesh, Eigen::MatrixXcd::Zero(24, 3), options),
               InvalidInput);
  Eigen::MatrixXcd imaginary_mean = loads;
  imaginary_mean(0, 0) = Complex(0.0, 1.0);
  EXPECT_THROW(write_calculix_deck(out, mesh, imaginary_mean, options), InvalidInput);
  mesh.node_sets["SS_FIXED"] = {0};
  EXPECT_THROW(write_calculix_deck(out, mesh, loads, options), InvalidInput);
}

}  // namespace
}  // namespace stickslip

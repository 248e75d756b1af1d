// APDL macro content, line by line, against lines computed by hand from docs/conventions.md's
// convention (X_k = a_k − i b_k: VALUE = a_k, VALUE2 = −b_k) for a one-element mesh with external
// ids.
#include "io/apdl_macro.h"

#include <complex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/errors.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// One hexahedron, node ids 101..108 (indices 0..7).
Mesh one_hex() {
  Mesh mesh;
  for (int i = 0; i < 8; ++i) {
    mesh.add_node(101 + i,
                  Eigen::Vector3d((i & 1) ? 1.0 : 0.0, (i & 2) ? 1.0 : 0.0, (i & 4) ? 1.0 : 0.0));
  }
  const std::vector<int> nodes{0, 1, 3, 2, 4, 5, 7, 6};
  mesh.add_element(1, ElementType::kC3D8, nodes);
  return mesh;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

// Harmonic loads given as cosine/sine coefficients (a, b) per direction: X = a − i b.
Eigen::Vector3cd from_cos_sin(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3cd x;
  for (int d = 0; d < 3; ++d) x(d) = Complex(a(d), -b(d));
  return x;
}

TEST(ApdlMacro, LinesMatchHandComputedCommands) {
  const Mesh mesh = one_hex();
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(24, 3);
  loads.block<3, 1>(3 * 2, 0) << 0.0, 0.0, 50.0;  // mean: 50 N along z at id 103
  // Harmonic 1 at id 101: a = (1.5, 0, −2), b = (0.25, 3, 0).
  loads.block<3, 1>(0, 1) = from_cos_sin({1.5, 0.0, -2.0}, {0.25, 3.0, 0.0});
  // Harmonic 1 at id 108: a = (0, 0, 0.001), b = (0, 0, −0.002).
  loads.block<3, 1>(3 * 7, 1) = from_cos_sin({0.0, 0.0, 0.001}, {0.0, 0.0, -0.002});
  // Harmonic 3 at id 104: a = (−7, 0, 0), b = 0.
  loads.block<3, 1>(3 * 3, 2) = from_cos_sin({-7.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  ApdlMacroOptions options;
  options.frequency_hz = 1854.5;
  options.harmonics = {0, 1, 3};
  options.alpha = 5.0;
  std::ostringstream out;
  write_apdl_macro(out, mesh, loads, options);
  const std::vector<std::string> expected{
      "! stickslip: harmonic loads of one frequency point, f = 1854.5 Hz (N, global axes)",
      "! F,node,label,Re,Im with X_k = a_k - i b_k, x(t) = Re(X_k exp(i k Omega t))",
      "FINISH",
      "/SOLU",
      "ANTYPE,STATIC",
      "FDELE,ALL,ALL",
      "F,103,FX,0",
      "F,103,FY,0",
      "F,103,FZ,50",
      "SOLVE",
      "FINISH",
      "/SOLU",
      "ANTYPE,HARMIC",
      "HROPT,FULL",
      "HROUT,ON",
      "KBC,1",
      "NSUBST,1",
      "ALPHAD,5",
      "BETAD,0",
      "FDELE,ALL,ALL",
      "HARFRQ,1854.5",
      "F,101,FX,1.5,-0.25",
      "F,101,FY,0,-3",
      "F,101,FZ,-2,0",
      "F,108,FX,0,0",
      "F,108,FY,0,0",
      "F,108,FZ,0.001,0.002",
      "SOLVE",
      "FDELE,ALL,ALL",
      "HARFRQ,5563.5",
      "F,104,FX,-7,0",
      "F,104,FY,0,0",
      "F,104,FZ,0,0",
      "SOLVE",
      "FINISH"};
  const std::vector<std::string> got = lines_of(out.str());
  ASSERT_EQ(got.size(), expected.size()) << out.str();
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(got[i], expected[i]) << "line " << i + 1;
}

TEST(ApdlMacro, ModeSuperpositionOption) {
  const Mesh mesh = one_hex();
  Eigen::MatrixXcd loads = Eigen::MatrixXcd::Zero(24, 1);
  loads(5, 0) = Complex(1.0, 2.0);
  ApdlMacroOptions options;
  options.frequency_hz = 100.0;
  options.harmonics = {1};
  options.msup_modes = 60;
  options.beta = 1e-6;
  std::ostringstream out;
  write_apdl_macro(out, mesh, loads, options);
  const std::string text = out.str();
  EXPECT_NE(text.find("\nHROPT,MSUP,60\n"), std::string::npos);
  EXPECT_NE(text.find("\nBETAD,1e-06\n"), std::string::npos);
  EXPECT_NE(text.find("\nF,102,FZ,1,2\n"), std::string::npos);
  EXPECT_EQ(text.find("ANTYPE,STATIC"), std::string::npos);
}

TEST(ApdlMacro, ShortestDecimalRoundTrips) {
  EXPECT_EQ(shortest_decimal(50.0), "50");
  EXPECT_EQ(shortest_decimal(-0.25), "-0.25");
  EXPECT_EQ(shortest_decimal(-0.0), "0");
  for (double v : {0.1, 1.0 / 3.0, -2.718281828459045e-7, 6.02214076e23}) {
    EXPECT_EQ(std::stod(shortest_decimal(v)), v);
  }
}

TEST(ApdlMacro, DecimalInWidthFitsTwentyCharactersWithThirteenOrMoreDigits) {
  // The field that stopped ccx 2.20 (22 characters).
  EXPECT_EQ(decimal_in_width(-3.442068852166358e-11, 20), "-3.4420688521664e-11");
  EXPECT_EQ(decimal_in_width(0.05, 20), "0.05");  // short values stay exact
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mantissa(-10.0, 10.0);
  std::uniform_int_distribution<int> exponent(-320, 308);
  for (int i = 0; i < 20000; ++i) {
    const double v = mantissa(rng) * std::pow(10.0, exponent(rng));
    if (!std::isfinite(v)) continue;
    const std::string text = decimal_in_width(v, 20);
    ASSERT_LE(text.size(), 20u) << text;
    const double back = std::strtod(text.c_str(), nullptr);
    if (shortest_decimal(v).size() <= 20) {
      EXPECT_EQ(back, v) << text;  // exact when the shortest text fits
    } else if (std::abs(v) >= 1e-300) {
      // 13 significant digits at least: relative rounding error <= 5e-13 (14 digits: 5e-14).
      EXPECT_LE(std::abs(back - v), 5e-13 * std::abs(v)) << text;
    }
  }
}

TEST(ApdlMacro, BadInputThrows) {
  const Mesh mesh = one_hex();
  ApdlMacroOptions options;
  options.frequency_hz = 100.0;
  options.harmonics = {0};
  std::ostringstream out;
  Eigen::MatrixXcd imaginary_mean = Eigen::MatrixXcd::Zero(24, 1);
  imaginary_mean(0, 0) = Complex(1.0, 1.0);
  EXPECT_THROW(write_apdl_macro(out, mesh, imaginary_mean, options), InvalidInput);
  EXPECT_THROW(write_apdl_macro(out, mesh, Eigen::MatrixXcd::Zero(23, 1), options), InvalidInput);
  options.harmonics = {1, 1};
  EXPECT_THROW(write_apdl_macro(out, mesh, Eigen::MatrixXcd::Zero(24, 2), options), InvalidInput);
  options.harmonics = {1};
  options.frequency_hz = 0.0;
  EXPECT_THROW(write_apdl_macro(out, mesh, Eigen::MatrixXcd::Zero(24, 1), options), InvalidInput);
  options.frequency_hz = 10.0;
  options.alpha = -1.0;
  EXPECT_THROW(write_apdl_macro(out, mesh, Eigen::MatrixXcd::Zero(24, 1), options), InvalidInput);
}

}  // namespace
}  // namespace stickslip

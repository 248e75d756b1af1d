#include "fe/material.h"

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "core/errors.h"

namespace stickslip {
namespace {

TEST(IsotropicMaterial, ValidateRejectsOutOfRangeFields) {
  const IsotropicMaterial steel{.youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};
  EXPECT_NO_THROW(validate(steel));
  IsotropicMaterial bad = steel;
  bad.youngs_modulus = 0.0;
  EXPECT_THROW(validate(bad), InvalidInput);
  bad = steel;
  bad.poisson_ratio = 0.5;
  EXPECT_THROW(validate(bad), InvalidInput);
  bad.poisson_ratio = -1.0;
  EXPECT_THROW(validate(bad), InvalidInput);
  bad = steel;
  bad.density = -1.0;
  try {
    validate(bad);
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("density"), std::string::npos);
  }
}

// Uniaxial stress s_xx = s, all other stresses zero: the compliance D^-1 must give
// e_xx = s/E, e_yy = e_zz = -nu s/E (closed form of Hooke's law); pure shear s_xy = t gives
// engineering strain g_xy = t/G with G = E/(2(1+nu)).
TEST(IsotropicMaterial, ElasticityMatrixReproducesHookesLaw) {
  const IsotropicMaterial m{.youngs_modulus = 7e10, .poisson_ratio = 0.33, .density = 2700};
  const VoigtMatrix D = elasticity_matrix(m);
  constexpr double kTol = 1e-14;  // a 6x6 solve in double precision
  EXPECT_LT((D - D.transpose()).norm(), kTol * D.norm());
  Eigen::Matrix<double, 6, 1> s = Eigen::Matrix<double, 6, 1>::Zero();
  s(0) = 1e8;
  const Eigen::Matrix<double, 6, 1> e = D.inverse() * s;
  EXPECT_NEAR(e(0), 1e8 / 7e10, kTol * 10);
  EXPECT_NEAR(e(1), -0.33 * 1e8 / 7e10, kTol * 10);
  EXPECT_NEAR(e(2), -0.33 * 1e8 / 7e10, kTol * 10);
  for (int i = 3; i < 6; ++i) EXPECT_NEAR(e(i), 0.0, kTol);
  for (int k = 3; k < 6; ++k) {
    s.setZero();
    s(k) = 1e8;
    const Eigen::Matrix<double, 6, 1> g = D.inverse() * s;
    EXPECT_NEAR(g(k), 1e8 * 2.0 * 1.33 / 7e10, 1e-12);
  }
}

}  // namespace
}  // namespace stickslip

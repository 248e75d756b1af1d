#include "fe/material.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/errors.h"

namespace stickslip {

namespace {
std::string str(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}
}  // namespace

void validate(const IsotropicMaterial& material) {
  require(std::isfinite(material.youngs_modulus) && material.youngs_modulus > 0.0,
          "IsotropicMaterial::youngs_modulus", str(material.youngs_modulus), "E > 0");
  require(std::isfinite(material.poisson_ratio) && material.poisson_ratio > -1.0 &&
              material.poisson_ratio < 0.5,
          "IsotropicMaterial::poisson_ratio", str(material.poisson_ratio), "-1 < nu < 0.5");
  require(std::isfinite(material.density) && material.density > 0.0, "IsotropicMaterial::density",
          str(material.density), "rho > 0");
}

double lame_lambda(const IsotropicMaterial& material) {
  const double nu = material.poisson_ratio;
  return material.youngs_modulus * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
}

double shear_modulus(const IsotropicMaterial& material) {
  return material.youngs_modulus / (2.0 * (1.0 + material.poisson_ratio));
}

VoigtMatrix elasticity_matrix(const IsotropicMaterial& material) {
  const double l = lame_lambda(material);
  const double m = shear_modulus(material);
  VoigtMatrix D = VoigtMatrix::Zero();
  D.topLeftCorner<3, 3>().setConstant(l);
  for (int i = 0; i < 3; ++i) {
    D(i, i) = l + 2.0 * m;
    D(3 + i, 3 + i) = m;
  }
  return D;
}

}  // namespace stickslip

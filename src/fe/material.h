// Isotropic linear elastic material (SI units: E and stresses in Pa, density in kg/m^3).
//
// Voigt order used everywhere in stickslip (the order CalculiX uses for its stress output):
//   strain  e = [e_xx, e_yy, e_zz, g_xy, g_xz, g_yz]   (g = engineering shear strain = 2 e_ij)
//   stress  s = [s_xx, s_yy, s_zz, s_xy, s_xz, s_yz]
// and s = D e with D = elasticity_matrix(material):
//   D = [[l+2m, l, l, 0, 0, 0], [l, l+2m, l, ...], [l, l, l+2m, ...], diag(m, m, m) below],
//   l = E nu / ((1 + nu)(1 - 2 nu))  (Lame's first parameter),  m = E / (2 (1 + nu))  (shear
//   modulus).
#pragma once

#include <Eigen/Core>

namespace stickslip {

constexpr int kVoigtSize = 6;
using VoigtMatrix = Eigen::Matrix<double, kVoigtSize, kVoigtSize>;

struct IsotropicMaterial {
  double youngs_modulus = 0.0;  // E, Pa; > 0
  double poisson_ratio = 0.0;   // nu; -1 < nu < 0.5
  double density = 0.0;         // rho, kg/m^3; > 0
};

// Throws InvalidInput naming the field, its value and the rule it broke.
void validate(const IsotropicMaterial& material);

double lame_lambda(const IsotropicMaterial& material);    // l above, Pa
double shear_modulus(const IsotropicMaterial& material);  // m above, Pa

// The 6x6 matrix D above (symmetric, positive definite for a valid material).
VoigtMatrix elasticity_matrix(const IsotropicMaterial& material);

}  // namespace stickslip

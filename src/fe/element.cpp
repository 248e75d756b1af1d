#include "fe/element.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <Eigen/Dense>

#include "core/errors.h"

namespace stickslip {

namespace {

using Eigen::Matrix;
using Eigen::Matrix3d;
using Eigen::Vector3d;

// ---------------------------------------------------------------- quadrature rules

struct Rule {
  std::vector<Vector3d> xi;
  std::vector<double> w;
};

Rule gauss_hex_rule(int n) {
  const double a = 1.0 / std::sqrt(3.0);
  const double b = std::sqrt(0.6);
  const double c = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2));
  const double d = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
  const double wc = (18.0 + std::sqrt(30.0)) / 36.0, wd = (18.0 - std::sqrt(30.0)) / 36.0;
  const double p2[] = {-a, a}, w2[] = {1.0, 1.0};
  const double p3[] = {-b, 0.0, b}, w3[] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double p4[] = {-d, -c, c, d}, w4[] = {wd, wc, wc, wd};
  const double* p = n == 2 ? p2 : (n == 3 ? p3 : p4);
  const double* w = n == 2 ? w2 : (n == 3 ? w3 : w4);
  Rule r;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        r.xi.emplace_back(p[i], p[j], p[k]);
        r.w.push_back(w[i] * w[j] * w[k]);
      }
    }
  }
  return r;
}

Rule tet_rule_1() { return Rule{{Vector3d(0.25, 0.25, 0.25)}, {1.0 / 6.0}}; }

// Degree-2 rule: points (a,b,b) and permutations, a = (5 + 3 sqrt5)/20, b = (5 - sqrt5)/20.
Rule tet_rule_4() {
  const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0;
  const double b = (5.0 - std::sqrt(5.0)) / 20.0;
  Rule r;
  r.xi = {Vector3d(b, b, b), Vector3d(a, b, b), Vector3d(b, a, b), Vector3d(b, b, a)};
  r.w.assign(4, 1.0 / 24.0);
  return r;
}

// Collapsed (Duffy) 4x4x4 Gauss-Legendre rule: xi = u, eta = (1-u) v, zeta = (1-u)(1-v) w,
// Jacobian (1-u)^2 (1-v). Exact for polynomials of total degree <= 5 on the tetrahedron.
Rule tet_rule_64() {
  const double s[] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                      0.8611363115940526};
  const double ws[] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                       0.3478548451374538};
  Rule r;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      for (int k = 0; k < 4; ++k) {
        const double u = 0.5 * (1.0 + s[i]), v = 0.5 * (1.0 + s[j]), w = 0.5 * (1.0 + s[k]);
        r.xi.emplace_back(u, (1.0 - u) * v, (1.0 - u) * (1.0 - v) * w);
        r.w.push_back(0.125 * ws[i] * ws[j] * ws[k] * (1.0 - u) * (1.0 - u) * (1.0 - v));
      }
    }
  }
  return r;
}

// Wedge rules: a triangle rule in (xi, eta) (weights summing to the triangle's area 1/2) times
// an n-point Gauss rule in zeta.
struct TriangleRule {
  std::vector<std::pair<double, double>> p;
  std::vector<double> w;
};

// 1 point (degree 1).
TriangleRule triangle_rule_1() { return {{{1.0 / 3.0, 1.0 / 3.0}}, {0.5}}; }
// 3 interior points (degree 2): (1/6, 1/6), (2/3, 1/6), (1/6, 2/3).
TriangleRule triangle_rule_3() {
  return {{{1.0 / 6.0, 1.0 / 6.0}, {2.0 / 3.0, 1.0 / 6.0}, {1.0 / 6.0, 2.0 / 3.0}},
          {1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0}};
}
// 7 points (degree 5, Radon): the centroid and two orbits (a, a), (1 - 2a, a), (a, 1 - 2a).
TriangleRule triangle_rule_7() {
  const double s15 = std::sqrt(15.0);
  TriangleRule r{{{1.0 / 3.0, 1.0 / 3.0}}, {0.5 * 9.0 / 40.0}};
  for (const auto& [a, w] : {std::pair{(6.0 - s15) / 21.0, (155.0 - s15) / 1200.0},
                             std::pair{(6.0 + s15) / 21.0, (155.0 + s15) / 1200.0}}) {
    for (const auto& q : {std::pair{a, a}, std::pair{1.0 - 2.0 * a, a}, std::pair{a, 1.0 - 2.0 * a}}) {
      r.p.push_back(q);
      r.w.push_back(0.5 * w);
    }
  }
  return r;
}

Rule wedge_rule(const TriangleRule& t, int n) {
  const double a = 1.0 / std::sqrt(3.0), b = std::sqrt(0.6);
  const double c = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2));
  const double d = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
  const double wc = (18.0 + std::sqrt(30.0)) / 36.0, wd = (18.0 - std::sqrt(30.0)) / 36.0;
  std::vector<double> z, wz;
  if (n == 2) {
    z = {-a, a};
    wz = {1.0, 1.0};
  } else if (n == 3) {
    z = {-b, 0.0, b};
    wz = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  } else {
    z = {-d, -c, c, d};
    wz = {wd, wc, wc, wd};
  }
  Rule r;
  for (size_t k = 0; k < z.size(); ++k) {
    for (size_t i = 0; i < t.p.size(); ++i) {
      r.xi.emplace_back(t.p[i].first, t.p[i].second, z[k]);
      r.w.push_back(t.w[i] * wz[k]);
    }
  }
  return r;
}

// ---------------------------------------------------------------- shape functions

constexpr double kHexNodes[20][3] = {
    {-1, -1, -1}, {1, -1, -1}, {1, 1, -1},  {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1},
    {-1, 1, 1},   {0, -1, -1}, {1, 0, -1},  {0, 1, -1},  {-1, 0, -1}, {0, -1, 1}, {1, 0, 1},
    {0, 1, 1},    {-1, 0, 1},  {-1, -1, 0}, {1, -1, 0},  {1, 1, 0},   {-1, 1, 0}};

constexpr double kTetNodes[10][3] = {{0, 0, 0},     {1, 0, 0},     {0, 1, 0},   {0, 0, 1},
                                     {0.5, 0, 0},   {0.5, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0.5},
                                     {0.5, 0, 0.5}, {0, 0.5, 0.5}};
constexpr int kTetEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};

void shape_hex8(const Vector3d& p, Matrix<double, 8, 1>& N, Matrix<double, 3, 8>& dN) {
  for (int a = 0; a < 8; ++a) {
    const double* c = kHexNodes[a];
    const double f0 = 1.0 + c[0] * p(0), f1 = 1.0 + c[1] * p(1), f2 = 1.0 + c[2] * p(2);
    N(a) = 0.125 * f0 * f1 * f2;
    dN(0, a) = 0.125 * c[0] * f1 * f2;
    dN(1, a) = 0.125 * c[1] * f0 * f2;
    dN(2, a) = 0.125 * c[2] * f0 * f1;
  }
}

void shape_hex20(const Vector3d& p, Matrix<double, 20, 1>& N, Matrix<double, 3, 20>& dN) {
  for (int a = 0; a < 8; ++a) {
    const double* c = kHexNodes[a];
    const double q0 = c[0] * p(0), q1 = c[1] * p(1), q2 = c[2] * p(2);
    const double f0 = 1.0 + q0, f1 = 1.0 + q1, f2 = 1.0 + q2;
    N(a) = 0.125 * f0 * f1 * f2 * (q0 + q1 + q2 - 2.0);
    dN(0, a) = 0.125 * c[0] * f1 * f2 * (2.0 * q0 + q1 + q2 - 1.0);
    dN(1, a) = 0.125 * c[1] * f0 * f2 * (q0 + 2.0 * q1 + q2 - 1.0);
    dN(2, a) = 0.125 * c[2] * f0 * f1 * (q0 + q1 + 2.0 * q2 - 1.0);
  }
  for (int a = 8; a < 20; ++a) {
    const double* c = kHexNodes[a];
    // The coordinate along the edge (natural coordinate 0 at the node) is `m`.
    const int m = c[0] == 0.0 ? 0 : (c[1] == 0.0 ? 1 : 2);
    const int r = (m + 1) % 3, s = (m + 2) % 3;
    const double bub = 1.0 - p(m) * p(m);
    const double fr = 1.0 + c[r] * p(r), fs = 1.0 + c[s] * p(s);
    N(a) = 0.25 * bub * fr * fs;
    dN(m, a) = -0.5 * p(m) * fr * fs;
    dN(r, a) = 0.25 * bub * c[r] * fs;
    dN(s, a) = 0.25 * bub * fr * c[s];
  }
}

// Barycentric coordinates L and their natural derivatives.
void tet_barycentric(const Vector3d& p, double L[4], Matrix<double, 3, 4>& dL) {
  L[0] = 1.0 - p(0) - p(1) - p(2);
  L[1] = p(0);
  L[2] = p(1);
  L[3] = p(2);
  dL << -1, 1, 0, 0, -1, 0, 1, 0, -1, 0, 0, 1;
}

void shape_tet4(const Vector3d& p, Matrix<double, 4, 1>& N, Matrix<double, 3, 4>& dN) {
  double L[4];
  tet_barycentric(p, L, dN);
  for (int a = 0; a < 4; ++a) N(a) = L[a];
}

void shape_tet10(const Vector3d& p, Matrix<double, 10, 1>& N, Matrix<double, 3, 10>& dN) {
  double L[4];
  Matrix<double, 3, 4> dL;
  tet_barycentric(p, L, dL);
  for (int a = 0; a < 4; ++a) {
    N(a) = L[a] * (2.0 * L[a] - 1.0);
    dN.col(a) = (4.0 * L[a] - 1.0) * dL.col(a);
  }
  for (int e = 0; e < 6; ++e) {
    const int i = kTetEdges[e][0], j = kTetEdges[e][1];
    N(4 + e) = 4.0 * L[i] * L[j];
    dN.col(4 + e) = 4.0 * (L[i] * dL.col(j) + L[j] * dL.col(i));
  }
}


// Wedges: L = (1 - xi - eta, xi, eta) in the triangle, zeta in [-1, 1]; nodes 0-2 at zeta = -1,
// 3-5 at zeta = +1 (CalculiX/Abaqus order).
constexpr double kWedgeNodes[15][3] = {
    {0, 0, -1},   {1, 0, -1},   {0, 1, -1}, {0, 0, 1},   {1, 0, 1},
    {0, 1, 1},    {0.5, 0, -1}, {0.5, 0.5, -1}, {0, 0.5, -1}, {0.5, 0, 1},
    {0.5, 0.5, 1}, {0, 0.5, 1}, {0, 0, 0},  {1, 0, 0},   {0, 1, 0}};

void wedge_barycentric(const Vector3d& p, double L[3], double dL[3][2]) {
  L[0] = 1.0 - p(0) - p(1);
  L[1] = p(0);
  L[2] = p(1);
  dL[0][0] = -1.0, dL[0][1] = -1.0;
  dL[1][0] = 1.0, dL[1][1] = 0.0;
  dL[2][0] = 0.0, dL[2][1] = 1.0;
}

// N_a = L_a (1 ∓ zeta) / 2.
void shape_wedge6(const Vector3d& p, Matrix<double, 6, 1>& N, Matrix<double, 3, 6>& dN) {
  double L[3], dL[3][2];
  wedge_barycentric(p, L, dL);
  for (int a = 0; a < 6; ++a) {
    const int t = a % 3;
    const double s = a < 3 ? -1.0 : 1.0, h = 0.5 * (1.0 + s * p(2));
    N(a) = L[t] * h;
    dN(0, a) = dL[t][0] * h;
    dN(1, a) = dL[t][1] * h;
    dN(2, a) = 0.5 * s * L[t];
  }
}

// Corners: ½ L (2L − 1)(1 ± zeta) − ½ L (1 − zeta²); triangle edges (i, j): 2 L_i L_j (1 ± zeta);
// vertical edges: L (1 − zeta²). Mid-edge nodes 6-8 on (0,1) (1,2) (2,0), 9-11 on (3,4) (4,5)
// (5,3), 12-14 on (0,3) (1,4) (2,5).
void shape_wedge15(const Vector3d& p, Matrix<double, 15, 1>& N, Matrix<double, 3, 15>& dN) {
  double L[3], dL[3][2];
  wedge_barycentric(p, L, dL);
  const double z = p(2), q = 1.0 - z * z;
  for (int a = 0; a < 6; ++a) {
    const int t = a % 3;
    const double s = a < 3 ? -1.0 : 1.0, f = 1.0 + s * z;
    N(a) = 0.5 * L[t] * (2.0 * L[t] - 1.0) * f - 0.5 * L[t] * q;
    const double dLt = 0.5 * (4.0 * L[t] - 1.0) * f - 0.5 * q;  // d N / d L
    dN(0, a) = dLt * dL[t][0];
    dN(1, a) = dLt * dL[t][1];
    dN(2, a) = 0.5 * L[t] * (2.0 * L[t] - 1.0) * s + L[t] * z;
  }
  for (int e = 0; e < 6; ++e) {
    const int i = e % 3, j = (e + 1) % 3;
    const double s = e < 3 ? -1.0 : 1.0, f = 1.0 + s * z;
    N(6 + e) = 2.0 * L[i] * L[j] * f;
    for (int k = 0; k < 2; ++k) dN(k, 6 + e) = 2.0 * (dL[i][k] * L[j] + L[i] * dL[j][k]) * f;
    dN(2, 6 + e) = 2.0 * L[i] * L[j] * s;
  }
  for (int t = 0; t < 3; ++t) {
    N(12 + t) = L[t] * q;
    dN(0, 12 + t) = dL[t][0] * q;
    dN(1, 12 + t) = dL[t][1] * q;
    dN(2, 12 + t) = -2.0 * L[t] * z;
  }
}

// Pyramid C3D5: the 8-node brick with its top face collapsed onto the apex (ANSYS's degenerate
// SOLID185 pyramid, M = N = O = P). Base nodes 0-3 at zeta = -1 as the brick's, apex 4:
//   N_a = (1 + xi_a xi)(1 + eta_a eta)(1 - zeta) / 8 (a = 0..3),  N_4 = (1 + zeta) / 2,
// the sum of the four collapsed brick functions. Natural coordinates of the apex: (0, 0, 1).
void shape_pyr5(const Vector3d& p, Matrix<double, 5, 1>& N, Matrix<double, 3, 5>& dN) {
  for (int a = 0; a < 4; ++a) {
    const double* c = kHexNodes[a];
    const double f0 = 1.0 + c[0] * p(0), f1 = 1.0 + c[1] * p(1), f2 = 1.0 - p(2);
    N(a) = 0.125 * f0 * f1 * f2;
    dN(0, a) = 0.125 * c[0] * f1 * f2;
    dN(1, a) = 0.125 * c[1] * f0 * f2;
    dN(2, a) = -0.125 * f0 * f1;
  }
  N(4) = 0.5 * (1.0 + p(2));
  dN(0, 4) = 0.0;
  dN(1, 4) = 0.0;
  dN(2, 4) = 0.5;
}

// Pyramid C3D13: the 20-node brick with its top face collapsed onto the apex (CalculiX's C3D20
// with nodes 5-8 and 13-16 on one node; ANSYS's SOLID186 pyramid shape M = N = O = P = U = V =
// W = X). Each node's function is the sum of the brick functions of the brick nodes it stands
// for: base corners 0-3 and base mid-edge nodes 5-8 are the brick's 0-3 and 8-11, the apex 4 is
// brick nodes 4-7 and 12-15, the mid-edge nodes 9-12 of the lateral edges 0-4 ... 3-4 are the
// brick's vertical mid-edge nodes 16-19.
void shape_pyr13(const Vector3d& p, Matrix<double, 13, 1>& N, Matrix<double, 3, 13>& dN) {
  Matrix<double, 20, 1> n;
  Matrix<double, 3, 20> d;
  shape_hex20(p, n, d);
  N.head<4>() = n.head<4>();
  dN.leftCols<4>() = d.leftCols<4>();
  N(4) = n.segment<4>(4).sum() + n.segment<4>(12).sum();
  dN.col(4) = d.middleCols<4>(4).rowwise().sum() + d.middleCols<4>(12).rowwise().sum();
  N.segment<4>(5) = n.segment<4>(8);
  dN.middleCols<4>(5) = d.middleCols<4>(8);
  N.segment<4>(9) = n.segment<4>(16);
  dN.middleCols<4>(9) = d.middleCols<4>(16);
}

// ---------------------------------------------------------------- reference data (cached)

template <int NEN>
struct RefData {
  std::vector<Vector3d> xi;
  std::vector<double> w;
  std::vector<Matrix<double, NEN, 1>> N;
  std::vector<Matrix<double, 3, NEN>> dN;
};

template <int NEN, class Shape>
RefData<NEN> make_ref(const Rule& rule, Shape shape) {
  RefData<NEN> r;
  r.xi = rule.xi;
  r.w = rule.w;
  r.N.resize(rule.xi.size());
  r.dN.resize(rule.xi.size());
  for (size_t g = 0; g < rule.xi.size(); ++g) shape(rule.xi[g], r.N[g], r.dN[g]);
  return r;
}

const RefData<8>& hex8_2() {
  static const RefData<8> r = make_ref<8>(gauss_hex_rule(2), shape_hex8);
  return r;
}
const RefData<20>& hex20_2() {
  static const RefData<20> r = make_ref<20>(gauss_hex_rule(2), shape_hex20);
  return r;
}
const RefData<20>& hex20_3() {
  static const RefData<20> r = make_ref<20>(gauss_hex_rule(3), shape_hex20);
  return r;
}
const RefData<4>& tet4_1() {
  static const RefData<4> r = make_ref<4>(tet_rule_1(), shape_tet4);
  return r;
}
const RefData<4>& tet4_4() {
  static const RefData<4> r = make_ref<4>(tet_rule_4(), shape_tet4);
  return r;
}
const RefData<10>& tet10_4() {
  static const RefData<10> r = make_ref<10>(tet_rule_4(), shape_tet10);
  return r;
}
const RefData<10>& tet10_64() {
  static const RefData<10> r = make_ref<10>(tet_rule_64(), shape_tet10);
  return r;
}
// Pyramid: the collapsed brick's 2x2x2 Gauss rule (stiffness) and 3x3x3 (exact mass: N_a N_b
// det J has degree <= 4 in each natural coordinate).
const RefData<5>& pyr5_2() {
  static const RefData<5> r = make_ref<5>(gauss_hex_rule(2), shape_pyr5);
  return r;
}
const RefData<5>& pyr5_3() {
  static const RefData<5> r = make_ref<5>(gauss_hex_rule(3), shape_pyr5);
  return r;
}
// 13-node pyramid: the collapsed 20-node brick's 3x3x3 rule for stiffness (CalculiX's C3D20) and
// 4x4x4 for the exact mass (straight edges: det J has degree <= 2 in each natural coordinate,
// N_a N_b det J up to 6; 4 Gauss points are exact to 7, 3 to 5).
const RefData<13>& pyr13_3() {
  static const RefData<13> r = make_ref<13>(gauss_hex_rule(3), shape_pyr13);
  return r;
}
const RefData<13>& pyr13_4() {
  static const RefData<13> r = make_ref<13>(gauss_hex_rule(4), shape_pyr13);
  return r;
}
// C3D8R: one point at the centre, weight 8 (its stiffness and one-point mass are not integrated
// from it, see stiffness_hex8r and element_mass; the point locates its stresses).
const RefData<8>& hex8_1() {
  static const RefData<8> r = make_ref<8>(Rule{{Vector3d::Zero()}, {8.0}}, shape_hex8);
  return r;
}
// Wedges. Stiffness rules as CalculiX 2.20 (its frequencies to 1e-11, tests/validation):
// C3D6 two points, the triangle's centroid at zeta = ±1/√3; C3D15 nine points, 3 interior
// triangle points at zeta = 0, ±√0.6. Exact mass rules: 7-point degree-5 triangle rule times
// 3 (C3D6) or 4 (C3D15) Gauss points.
const RefData<6>& wedge6_k() {
  static const RefData<6> r = make_ref<6>(wedge_rule(triangle_rule_1(), 2), shape_wedge6);
  return r;
}
const RefData<6>& wedge6_m() {
  static const RefData<6> r = make_ref<6>(wedge_rule(triangle_rule_7(), 3), shape_wedge6);
  return r;
}
const RefData<15>& wedge15_k() {
  static const RefData<15> r = make_ref<15>(wedge_rule(triangle_rule_3(), 3), shape_wedge15);
  return r;
}
const RefData<15>& wedge15_m() {
  static const RefData<15> r = make_ref<15>(wedge_rule(triangle_rule_7(), 4), shape_wedge15);
  return r;
}

// ---------------------------------------------------------------- kernels

[[noreturn]] void throw_bad_jacobian(double det) {
  throw InvalidInput("element Jacobian determinant " + std::to_string(det) +
                     " at an integration point. Violated constraint: det J > 0 (element "
                     "inverted, degenerate or with its nodes in the wrong order)");
}

// Physical gradients G = J^-1 dN (3 x NEN) with J(i, j) = dx_j / dxi_i; returns det J.
template <int NEN>
double gradients(const Matrix<double, 3, NEN>& X, const Matrix<double, 3, NEN>& dN,
                 Matrix<double, 3, NEN>& G) {
  const Matrix3d J = dN * X.transpose();
  const double det = J.determinant();
  if (!(det > 0.0)) throw_bad_jacobian(det);
  G.noalias() = J.inverse() * dN;
  return det;
}

template <int NEN>
double jacobian_det(const Matrix<double, 3, NEN>& X, const Matrix<double, 3, NEN>& dN) {
  const Matrix3d J = dN * X.transpose();
  const double det = J.determinant();
  if (!(det > 0.0)) throw_bad_jacobian(det);
  return det;
}

// Gradient rows of all integration points: row g = sqrt(w_g det J_g) [G(0,:), G(1,:), G(2,:)]
// (G = 3 x M physical gradients at point g). Up to 27 points, no heap allocation.
template <int M>
using GradientRows = Matrix<double, Eigen::Dynamic, 3 * M, Eigen::RowMajor, 27, 3 * M>;

template <int M>
void set_gradient_row(const Matrix<double, 3, M>& G, double c, int g, GradientRows<M>& R) {
  const double s = std::sqrt(c);
  for (int i = 0; i < 3; ++i) R.row(g).template segment<M>(i * M) = s * G.row(i);
}

// K = integral of the isotropic stiffness density from the gradient rows R:
//   A = R^T R,  A(iM+a, jM+b) = sum_g c_g G(i,a) G(j,b),
//   K(3a+i, 3b+j) = lambda A(iM+a, jM+b) + mu A(jM+a, iM+b) + mu delta_ij sum_k A(kM+a, kM+b).
// Only the upper triangle is formed, then mirrored (exact symmetry).
template <int M>
void isotropic_stiffness(const GradientRows<M>& R, double lambda, double mu,
                         Matrix<double, 3 * M, 3 * M>& K) {
  Matrix<double, 3 * M, 3 * M> A;
  A.noalias() = R.transpose() * R;
  for (int b = 0; b < M; ++b) {
    for (int a = 0; a <= b; ++a) {
      const double d = mu * (A(a, b) + A(M + a, M + b) + A(2 * M + a, 2 * M + b));
      for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
          K(3 * a + i, 3 * b + j) =
              lambda * A(i * M + a, j * M + b) + mu * A(j * M + a, i * M + b) + (i == j ? d : 0.0);
        }
      }
    }
  }
  for (int c = 0; c < 3 * M; ++c) {
    for (int r = c + 1; r < 3 * M; ++r) K(r, c) = K(c, r);
  }
}

template <int NEN>
void stiffness_standard(const Matrix<double, 3, NEN>& X, const RefData<NEN>& ref, double lambda,
                        double mu, Matrix<double, 3 * NEN, 3 * NEN>& K) {
  const int ngp = static_cast<int>(ref.w.size());
  GradientRows<NEN> R(ngp, 3 * NEN);
  Matrix<double, 3, NEN> G;
  for (int g = 0; g < ngp; ++g) {
    const double c = ref.w[g] * gradients<NEN>(X, ref.dN[g], G);
    set_gradient_row<NEN>(G, c, g, R);
  }
  isotropic_stiffness<NEN>(R, lambda, mu, K);
}

// Physical gradients of the incompatible modes (Taylor modification) at integration point g,
// given det J there: (det J0 / det J) J0^-1 dP, dP = diag(-2 xi, -2 eta, -2 zeta).
struct Hex8Centre {
  Matrix3d J0inv;
  double det0;
};

Hex8Centre hex8_centre(const Matrix<double, 3, 8>& X) {
  Matrix<double, 8, 1> N;
  Matrix<double, 3, 8> dN;
  shape_hex8(Vector3d::Zero(), N, dN);
  const Matrix3d J0 = dN * X.transpose();
  const double det0 = J0.determinant();
  if (!(det0 > 0.0)) throw_bad_jacobian(det0);
  return {J0.inverse(), det0};
}

Matrix3d incompatible_gradients(const Hex8Centre& c, const Vector3d& xi, double det) {
  return (c.det0 / det) * c.J0inv * (-2.0 * xi).asDiagonal();
}

// C3D8I: K (24x24) after condensation; if T != nullptr, T = -K_aa^-1 K_au (9 x 24) gives the
// internal DOFs alpha = T u.
void stiffness_hex8i(const Matrix<double, 3, 8>& X, double lambda, double mu,
                     Matrix<double, 24, 24>& K, Matrix<double, 9, 24>* T) {
  const RefData<8>& ref = hex8_2();
  const Hex8Centre centre = hex8_centre(X);
  Matrix<double, 33, 33> Ke;
  GradientRows<11> R(8, 33);
  Matrix<double, 3, 8> Gu;
  Matrix<double, 3, 11> G;
  for (int g = 0; g < 8; ++g) {
    const double det = gradients<8>(X, ref.dN[g], Gu);
    G.leftCols<8>() = Gu;
    G.rightCols<3>() = incompatible_gradients(centre, ref.xi[g], det);
    set_gradient_row<11>(G, ref.w[g] * det, g, R);
  }
  isotropic_stiffness<11>(R, lambda, mu, Ke);
  const Eigen::LLT<Matrix<double, 9, 9>> llt(Ke.bottomRightCorner<9, 9>());
  const Matrix<double, 9, 24> S = llt.solve(Ke.bottomLeftCorner<9, 24>());
  K = Ke.topLeftCorner<24, 24>();
  K.noalias() -= Ke.topRightCorner<24, 9>() * S;
  K = 0.5 * (K + K.transpose()).eval();
  if (T != nullptr) *T = -S;
}

template <int NEN>
void mass_standard(const Matrix<double, 3, NEN>& X, const RefData<NEN>& ref, double rho,
                   Matrix<double, 3 * NEN, 3 * NEN>& M) {
  Matrix<double, NEN, NEN> m;
  m.setZero();
  for (size_t g = 0; g < ref.w.size(); ++g) {
    const double c = rho * ref.w[g] * jacobian_det<NEN>(X, ref.dN[g]);
    m.noalias() += c * ref.N[g] * ref.N[g].transpose();
  }
  M.setZero();
  for (int b = 0; b < NEN; ++b) {
    for (int a = 0; a < NEN; ++a) {
      for (int d = 0; d < 3; ++d) M(3 * a + d, 3 * b + d) = m(a, b);
    }
  }
}

template <int NEN>
double volume_standard(const Matrix<double, 3, NEN>& X, const RefData<NEN>& ref) {
  double v = 0.0;
  for (size_t g = 0; g < ref.w.size(); ++g) v += ref.w[g] * jacobian_det<NEN>(X, ref.dN[g]);
  return v;
}

// Voigt strain operator of gradient columns G (3 x M) into B (6 x 3M).
template <int M>
void strain_operator(const Matrix<double, 3, M>& G, Eigen::Ref<Eigen::MatrixXd> B) {
  B.setZero();
  for (int a = 0; a < M; ++a) {
    const double gx = G(0, a), gy = G(1, a), gz = G(2, a);
    B(0, 3 * a) = gx;
    B(1, 3 * a + 1) = gy;
    B(2, 3 * a + 2) = gz;
    B(3, 3 * a) = gy;
    B(3, 3 * a + 1) = gx;
    B(4, 3 * a) = gz;
    B(4, 3 * a + 2) = gx;
    B(5, 3 * a + 1) = gz;
    B(5, 3 * a + 2) = gy;
  }
}

template <int NEN>
void strain_operators_standard(const Matrix<double, 3, NEN>& X, const RefData<NEN>& ref,
                               std::vector<Eigen::MatrixXd>& B) {
  B.resize(ref.w.size());
  Matrix<double, 3, NEN> G;
  for (size_t g = 0; g < ref.w.size(); ++g) {
    gradients<NEN>(X, ref.dN[g], G);
    B[g].resize(6, 3 * NEN);
    strain_operator<NEN>(G, B[g]);
  }
}

void strain_operators_hex8i(const Matrix<double, 3, 8>& X, double lambda, double mu,
                            std::vector<Eigen::MatrixXd>& B) {
  Matrix<double, 24, 24> K;
  Matrix<double, 9, 24> T;
  stiffness_hex8i(X, lambda, mu, K, &T);
  const RefData<8>& ref = hex8_2();
  const Hex8Centre centre = hex8_centre(X);
  B.resize(ref.w.size());
  Matrix<double, 3, 8> Gu;
  Matrix<double, 3, 3> Ga;
  Eigen::MatrixXd Ba(6, 9);
  for (size_t g = 0; g < ref.w.size(); ++g) {
    const double det = gradients<8>(X, ref.dN[g], Gu);
    Ga = incompatible_gradients(centre, ref.xi[g], det);
    B[g].resize(6, 24);
    strain_operator<8>(Gu, B[g]);
    strain_operator<3>(Ga, Ba);
    B[g].noalias() += Ba * T;
  }
}

// C3D8B (B-bar, mean dilatation; Hughes 1980): the volumetric part of the strain at every
// integration point is replaced by its element mean,
//   B̄_g = B_g + (1/3) m (b̄ - b_g)ᵀ,  b_g = mᵀ B_g (divergence row),  b̄ = (1/V) Σ w det J b_g,
// m = [1 1 1 0 0 0]ᵀ. Since D_dev m = 0 for D_dev = D(λ = -2μ/3, μ), the stiffness splits exactly
// into a fully integrated deviatoric part and a rank-one volumetric part:
//   K = Σ w det J B_gᵀ D_dev B_g + κ V b̄ b̄ᵀ,  κ = λ + 2μ/3 (bulk modulus).
// Gbar (3 x 8) holds b̄ by node and direction: b̄(3a + j) = Gbar(j, a).
double mean_gradients_hex8(const Matrix<double, 3, 8>& X, Matrix<double, 3, 8>& Gbar) {
  const RefData<8>& ref = hex8_2();
  Matrix<double, 3, 8> G;
  Gbar.setZero();
  double volume = 0.0;
  for (size_t g = 0; g < ref.w.size(); ++g) {
    const double c = ref.w[g] * gradients<8>(X, ref.dN[g], G);
    Gbar += c * G;
    volume += c;
  }
  Gbar /= volume;
  return volume;
}

void stiffness_hex8b(const Matrix<double, 3, 8>& X, double lambda, double mu,
                     Matrix<double, 24, 24>& K) {
  stiffness_standard<8>(X, hex8_2(), -2.0 * mu / 3.0, mu, K);
  Matrix<double, 3, 8> Gbar;
  const double volume = mean_gradients_hex8(X, Gbar);
  const Eigen::Map<const Matrix<double, 24, 1>> b(Gbar.data());  // column-major: 3a + j
  K.noalias() += (lambda + 2.0 * mu / 3.0) * volume * (b * b.transpose());
}

void strain_operators_hex8b(const Matrix<double, 3, 8>& X, std::vector<Eigen::MatrixXd>& B) {
  strain_operators_standard<8>(X, hex8_2(), B);
  Matrix<double, 3, 8> Gbar;
  mean_gradients_hex8(X, Gbar);
  const Eigen::Map<const Matrix<double, 1, 24>> bbar(Gbar.data());
  for (Eigen::MatrixXd& Bg : B) {
    const Matrix<double, 1, 24> correction = (bbar - Bg.topRows<3>().colwise().sum()) / 3.0;
    for (int i = 0; i < 3; ++i) Bg.row(i) += correction;
  }
}

// C3D8R: CalculiX 2.20's reduced-integration brick (its hourglass stiffness after Flanagan and
// Belytschko 1981; formulation read from ccx's shape8hr.f and hgstiffness.f, written anew here).
// With b̄ (Gbar) the uniform gradients b̄_ja = (1/V) ∂V/∂x_ja = (1/V) ∫ ∂N_a/∂x_j dV
// (mean_gradients_hex8: the 2x2x2 rule integrates them exactly) the one-point part is
// V B̄ᵀ D B̄. The hourglass part acts on each direction alike:
//   K_hg(3a+d, 3b+d) = c Σ_k γ_ka γ_kb,   c = kHourglassFactor · E · Σ_ja (∂V/∂x_ja)² / V,
// γ_k = h_k − Σ_j b̄_j (x_jᵀ h_k) for the base vectors h_k (ηζ, ξζ, ξη, ξηζ at the nodes):
// orthogonal to every linear field (b̄_iᵀ x_j = δ_ij), so rigid motions and the patch test's
// fields carry no hourglass energy. (ccx 2.20 subtracts the z term only, see element.h.)
constexpr double kHourglassFactor = 0.0005;  // CalculiX 2.20's fixed value (shape8hr.f)

void hourglass_vectors_hex8r(const Matrix<double, 3, 8>& X, const Matrix<double, 3, 8>& Gbar,
                             Matrix<double, 8, 4>& gamma) {
  for (int a = 0; a < 8; ++a) {
    const double* c = kHexNodes[a];
    gamma(a, 0) = c[1] * c[2];
    gamma(a, 1) = c[0] * c[2];
    gamma(a, 2) = c[0] * c[1];
    gamma(a, 3) = c[0] * c[1] * c[2];
  }
  const Matrix<double, 3, 4> xh = X * gamma;
  gamma.noalias() -= Gbar.transpose() * xh;
}

void stiffness_hex8r(const Matrix<double, 3, 8>& X, double youngs_modulus, double lambda, double mu,
                     Matrix<double, 24, 24>& K) {
  Matrix<double, 3, 8> Gbar;
  const double volume = mean_gradients_hex8(X, Gbar);
  GradientRows<8> R(1, 24);
  set_gradient_row<8>(Gbar, volume, 0, R);
  isotropic_stiffness<8>(R, lambda, mu, K);
  Matrix<double, 8, 4> gamma;
  hourglass_vectors_hex8r(X, Gbar, gamma);
  // Σ (∂V/∂x)² / V = V Σ b̄².
  const double c = kHourglassFactor * youngs_modulus * volume * Gbar.squaredNorm();
  const Matrix<double, 8, 8> h = c * (gamma * gamma.transpose());
  for (int b = 0; b < 8; ++b) {
    for (int a = 0; a < 8; ++a) {
      for (int d = 0; d < 3; ++d) K(3 * a + d, 3 * b + d) += h(a, b);
    }
  }
}

// The one point's strain operator: the uniform gradients (the hourglass modes carry no strain).
void strain_operators_hex8r(const Matrix<double, 3, 8>& X, std::vector<Eigen::MatrixXd>& B) {
  Matrix<double, 3, 8> Gbar;
  mean_gradients_hex8(X, Gbar);
  B.resize(1);
  B[0].resize(6, 24);
  strain_operator<8>(Gbar, B[0]);
}

template <int NEN>
Matrix<double, 3, NEN> fixed_coordinates(ElementType type, const Eigen::Matrix3Xd& X) {
  if (X.cols() != NEN) {
    throw InvalidInput(std::string("element coordinates: ") + std::to_string(X.cols()) +
                       " columns for a " + element_type_name(type) + " element (needs " +
                       std::to_string(NEN) + ")");
  }
  return X;
}

template <int NEN>
void copy_out(const Matrix<double, 3 * NEN, 3 * NEN>& A, Eigen::MatrixXd& out) {
  out.resize(3 * NEN, 3 * NEN);
  out = A;
}

}  // namespace

void element_stiffness(ElementType type, const Eigen::Matrix3Xd& X,
                       const IsotropicMaterial& material, Eigen::MatrixXd& K) {
  const double l = lame_lambda(material), m = shear_modulus(material);
  switch (type) {
    case ElementType::kC3D8: {
      Matrix<double, 24, 24> k;
      stiffness_standard<8>(fixed_coordinates<8>(type, X), hex8_2(), l, m, k);
      copy_out<8>(k, K);
      return;
    }
    case ElementType::kC3D8I: {
      Matrix<double, 24, 24> k;
      stiffness_hex8i(fixed_coordinates<8>(type, X), l, m, k, nullptr);
      copy_out<8>(k, K);
      return;
    }
    case ElementType::kC3D8B: {
      Matrix<double, 24, 24> k;
      stiffness_hex8b(fixed_coordinates<8>(type, X), l, m, k);
      copy_out<8>(k, K);
      return;
    }
    case ElementType::kC3D8R: {
      Matrix<double, 24, 24> k;
      stiffness_hex8r(fixed_coordinates<8>(type, X), material.youngs_modulus, l, m, k);
      copy_out<8>(k, K);
      return;
    }
    case ElementType::kC3D13: {
      Matrix<double, 39, 39> k;
      stiffness_standard<13>(fixed_coordinates<13>(type, X), pyr13_3(), l, m, k);
      copy_out<13>(k, K);
      return;
    }
    case ElementType::kC3D20:
    case ElementType::kC3D20R: {
      Matrix<double, 60, 60> k;
      stiffness_standard<20>(fixed_coordinates<20>(type, X),
                             type == ElementType::kC3D20 ? hex20_3() : hex20_2(), l, m, k);
      copy_out<20>(k, K);
      return;
    }
    case ElementType::kC3D4: {
      Matrix<double, 12, 12> k;
      stiffness_standard<4>(fixed_coordinates<4>(type, X), tet4_1(), l, m, k);
      copy_out<4>(k, K);
      return;
    }
    case ElementType::kC3D10: {
      Matrix<double, 30, 30> k;
      stiffness_standard<10>(fixed_coordinates<10>(type, X), tet10_4(), l, m, k);
      copy_out<10>(k, K);
      return;
    }
    case ElementType::kC3D5: {
      Matrix<double, 15, 15> k;
      stiffness_standard<5>(fixed_coordinates<5>(type, X), pyr5_2(), l, m, k);
      copy_out<5>(k, K);
      return;
    }
    case ElementType::kC3D6: {
      Matrix<double, 18, 18> k;
      stiffness_standard<6>(fixed_coordinates<6>(type, X), wedge6_k(), l, m, k);
      copy_out<6>(k, K);
      return;
    }
    case ElementType::kC3D15: {
      Matrix<double, 45, 45> k;
      stiffness_standard<15>(fixed_coordinates<15>(type, X), wedge15_k(), l, m, k);
      copy_out<15>(k, K);
      return;
    }
  }
}

void element_mass(ElementType type, const Eigen::Matrix3Xd& X, double density, Eigen::MatrixXd& M,
                  MassIntegration rule) {
  const bool exact = rule == MassIntegration::kExact;
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B: {
      Matrix<double, 24, 24> m;
      mass_standard<8>(fixed_coordinates<8>(type, X), hex8_2(), density, m);
      copy_out<8>(m, M);
      return;
    }
    case ElementType::kC3D8R: {
      Matrix<double, 24, 24> m;
      const Matrix<double, 3, 8> x = fixed_coordinates<8>(type, X);
      if (exact) {
        mass_standard<8>(x, hex8_2(), density, m);
      } else {
        // CalculiX's one point with det J = V / 8 (its exact volume): ρV/64 for every pair.
        m.setZero();
        const double mab = density * volume_standard<8>(x, hex8_2()) / 64.0;
        for (int b = 0; b < 8; ++b) {
          for (int a = 0; a < 8; ++a) {
            for (int d = 0; d < 3; ++d) m(3 * a + d, 3 * b + d) = mab;
          }
        }
      }
      copy_out<8>(m, M);
      return;
    }
    case ElementType::kC3D13: {
      Matrix<double, 39, 39> m;
      mass_standard<13>(fixed_coordinates<13>(type, X), exact ? pyr13_4() : pyr13_3(), density, m);
      copy_out<13>(m, M);
      return;
    }
    case ElementType::kC3D20:
    case ElementType::kC3D20R: {
      Matrix<double, 60, 60> m;
      const bool full = exact || type == ElementType::kC3D20;
      mass_standard<20>(fixed_coordinates<20>(type, X), full ? hex20_3() : hex20_2(), density, m);
      copy_out<20>(m, M);
      return;
    }
    case ElementType::kC3D4: {
      Matrix<double, 12, 12> m;
      mass_standard<4>(fixed_coordinates<4>(type, X), exact ? tet4_4() : tet4_1(), density, m);
      copy_out<4>(m, M);
      return;
    }
    case ElementType::kC3D10: {
      Matrix<double, 30, 30> m;
      mass_standard<10>(fixed_coordinates<10>(type, X), exact ? tet10_64() : tet10_4(), density, m);
      copy_out<10>(m, M);
      return;
    }
    case ElementType::kC3D5: {
      Matrix<double, 15, 15> m;
      mass_standard<5>(fixed_coordinates<5>(type, X), exact ? pyr5_3() : pyr5_2(), density, m);
      copy_out<5>(m, M);
      return;
    }
    case ElementType::kC3D6: {
      Matrix<double, 18, 18> m;
      mass_standard<6>(fixed_coordinates<6>(type, X), exact ? wedge6_m() : wedge6_k(), density, m);
      copy_out<6>(m, M);
      return;
    }
    case ElementType::kC3D15: {
      Matrix<double, 45, 45> m;
      mass_standard<15>(fixed_coordinates<15>(type, X), exact ? wedge15_m() : wedge15_k(), density,
                        m);
      copy_out<15>(m, M);
      return;
    }
  }
}

double element_volume(ElementType type, const Eigen::Matrix3Xd& X) {
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
    case ElementType::kC3D8R:
      return volume_standard<8>(fixed_coordinates<8>(type, X), hex8_2());
    case ElementType::kC3D13:
      return volume_standard<13>(fixed_coordinates<13>(type, X), pyr13_4());
    case ElementType::kC3D20:
    case ElementType::kC3D20R:
      return volume_standard<20>(fixed_coordinates<20>(type, X), hex20_3());
    case ElementType::kC3D4:
      return volume_standard<4>(fixed_coordinates<4>(type, X), tet4_4());
    case ElementType::kC3D10:
      return volume_standard<10>(fixed_coordinates<10>(type, X), tet10_64());
    case ElementType::kC3D5:
      return volume_standard<5>(fixed_coordinates<5>(type, X), pyr5_3());
    case ElementType::kC3D6:
      return volume_standard<6>(fixed_coordinates<6>(type, X), wedge6_m());
    case ElementType::kC3D15:
      return volume_standard<15>(fixed_coordinates<15>(type, X), wedge15_m());
  }
  return 0.0;
}

namespace {

// Over the points of `ref`: the smallest and largest det J, and the largest |det J| relative to
// the product of the lengths of J's rows (Hadamard: at most 1; 0 for a flat element at any scale
// and aspect ratio).
struct DetRange {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  double max_relative = 0.0;
};

template <int NEN>
void det_range(const Matrix<double, 3, NEN>& X, const RefData<NEN>& ref, DetRange* r) {
  for (const auto& dN : ref.dN) {
    const Matrix3d J = dN * X.transpose();
    const double det = J.determinant();
    const double hadamard = J.row(0).norm() * J.row(1).norm() * J.row(2).norm();
    r->lo = std::min(r->lo, det);
    r->hi = std::max(r->hi, det);
    if (hadamard > 0.0) r->max_relative = std::max(r->max_relative, std::abs(det) / hadamard);
  }
}

}  // namespace

std::string element_shape_problem(ElementType type, const Eigen::Matrix3Xd& X) {
  if (X.cols() != nodes_per_element(type)) {
    return "has " + std::to_string(X.cols()) + " nodes, a " + element_type_name(type) +
           " needs " + std::to_string(nodes_per_element(type));
  }
  if (!X.allFinite()) return "a node coordinate is not a finite number";
  // Every point where a kernel evaluates det J: the stiffness rule, the exact and CalculiX mass
  // rules and, for C3D8I, the centre (hex8_centre).
  DetRange r;
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
    case ElementType::kC3D8R: {
      const Matrix<double, 3, 8> x = X;
      det_range<8>(x, hex8_2(), &r);
      static const RefData<8> centre = make_ref<8>(Rule{{Vector3d::Zero()}, {8.0}}, shape_hex8);
      det_range<8>(x, centre, &r);
      break;
    }
    case ElementType::kC3D20:
    case ElementType::kC3D20R: {
      const Matrix<double, 3, 20> x = X;
      det_range<20>(x, hex20_2(), &r);
      det_range<20>(x, hex20_3(), &r);
      break;
    }
    case ElementType::kC3D4: {
      const Matrix<double, 3, 4> x = X;
      det_range<4>(x, tet4_1(), &r);
      det_range<4>(x, tet4_4(), &r);
      break;
    }
    case ElementType::kC3D10: {
      const Matrix<double, 3, 10> x = X;
      det_range<10>(x, tet10_4(), &r);
      det_range<10>(x, tet10_64(), &r);
      break;
    }
    case ElementType::kC3D5: {
      const Matrix<double, 3, 5> x = X;
      det_range<5>(x, pyr5_2(), &r);
      det_range<5>(x, pyr5_3(), &r);
      break;
    }
    case ElementType::kC3D13: {
      const Matrix<double, 3, 13> x = X;
      det_range<13>(x, pyr13_3(), &r);
      det_range<13>(x, pyr13_4(), &r);
      break;
    }
    case ElementType::kC3D6: {
      const Matrix<double, 3, 6> x = X;
      det_range<6>(x, wedge6_k(), &r);
      det_range<6>(x, wedge6_m(), &r);
      break;
    }
    case ElementType::kC3D15: {
      const Matrix<double, 3, 15> x = X;
      det_range<15>(x, wedge15_k(), &r);
      det_range<15>(x, wedge15_m(), &r);
      break;
    }
  }
  const double lo = r.lo;
  if (lo > 0.0) return {};
  std::string what;
  if (!(r.max_relative > kFlatElementTolerance)) {
    what = "the element is flat (no volume: its nodes lie on a plane, a line or a point)";
  } else if (r.hi < 0.0) {
    what = "the element is inverted (its nodes are in the wrong order: mirrored)";
  } else {
    what = "the element is distorted (det J changes sign inside it: a misplaced mid-side node "
           "or a corner out of place)";
  }
  char det[32];
  std::snprintf(det, sizeof det, "%.6g", lo);
  return std::string("Jacobian determinant ") + det +
         " at an integration point (det J > 0 needed): " + what;
}

Eigen::Matrix3Xd natural_node_coordinates(ElementType type) {
  const int n = nodes_per_element(type);
  const bool hex = n == 8 || n == 20;
  const bool wedge = n == 6 || n == 15;
  Eigen::Matrix3Xd P(3, n);
  for (int a = 0; a < n && n != 13; ++a) {
    for (int i = 0; i < 3; ++i) {
      P(i, a) = hex ? kHexNodes[a][i] : (wedge ? kWedgeNodes[a][i] : kTetNodes[a][i]);
    }
  }
  if (n == 5 || n == 13) {  // pyramid: the brick's base, the apex at (0, 0, 1)
    for (int a = 0; a < 4; ++a) P.col(a) = Vector3d(kHexNodes[a][0], kHexNodes[a][1], -1.0);
    P.col(4) = Vector3d(0.0, 0.0, 1.0);
  }
  if (n == 13) {  // base mid-edge nodes as the brick's 9-12, lateral ones as its 17-20
    for (int a = 0; a < 4; ++a) {
      P.col(5 + a) = Vector3d(kHexNodes[8 + a][0], kHexNodes[8 + a][1], kHexNodes[8 + a][2]);
      P.col(9 + a) = Vector3d(kHexNodes[16 + a][0], kHexNodes[16 + a][1], kHexNodes[16 + a][2]);
    }
  }
  return P;
}

namespace {
template <int NEN>
void rule_out(const RefData<NEN>& ref, Eigen::Matrix3Xd* P, Eigen::VectorXd* w) {
  const int n = static_cast<int>(ref.w.size());
  if (P != nullptr) {
    P->resize(3, n);
    for (int g = 0; g < n; ++g) P->col(g) = ref.xi[g];
  }
  if (w != nullptr) w->resize(n);
  for (int g = 0; g < n && w != nullptr; ++g) (*w)(g) = ref.w[g];
}

void stiffness_rule(ElementType type, Eigen::Matrix3Xd* P, Eigen::VectorXd* w) {
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
      return rule_out<8>(hex8_2(), P, w);
    case ElementType::kC3D8R:
      return rule_out<8>(hex8_1(), P, w);
    case ElementType::kC3D13:
      return rule_out<13>(pyr13_3(), P, w);
    case ElementType::kC3D20:
      return rule_out<20>(hex20_3(), P, w);
    case ElementType::kC3D20R:
      return rule_out<20>(hex20_2(), P, w);
    case ElementType::kC3D4:
      return rule_out<4>(tet4_1(), P, w);
    case ElementType::kC3D10:
      return rule_out<10>(tet10_4(), P, w);
    case ElementType::kC3D5:
      return rule_out<5>(pyr5_2(), P, w);
    case ElementType::kC3D6:
      return rule_out<6>(wedge6_k(), P, w);
    case ElementType::kC3D15:
      return rule_out<15>(wedge15_k(), P, w);
  }
}
}  // namespace

Eigen::Matrix3Xd integration_points(ElementType type) {
  Eigen::Matrix3Xd P;
  stiffness_rule(type, &P, nullptr);
  return P;
}

Eigen::VectorXd integration_weights(ElementType type) {
  Eigen::VectorXd w;
  stiffness_rule(type, nullptr, &w);
  return w;
}

namespace {
// One element's fixed-size shape functions into the dynamic N, dN of shape_functions.
template <int kNodes>
void evaluate_shape(void (*shape)(const Vector3d&, Matrix<double, kNodes, 1>&,
                                  Matrix<double, 3, kNodes>&),
                    const Eigen::Vector3d& xi, Eigen::VectorXd& N, Eigen::Matrix3Xd& dN) {
  Matrix<double, kNodes, 1> n;
  Matrix<double, 3, kNodes> d;
  shape(xi, n, d);
  N = n;
  dN = d;
}
}  // namespace

void shape_functions(ElementType type, const Eigen::Vector3d& xi, Eigen::VectorXd& N,
                     Eigen::Matrix3Xd& dN) {
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
    case ElementType::kC3D8R:
      return evaluate_shape<8>(shape_hex8, xi, N, dN);
    case ElementType::kC3D13:
      return evaluate_shape<13>(shape_pyr13, xi, N, dN);
    case ElementType::kC3D20:
    case ElementType::kC3D20R:
      return evaluate_shape<20>(shape_hex20, xi, N, dN);
    case ElementType::kC3D4:
      return evaluate_shape<4>(shape_tet4, xi, N, dN);
    case ElementType::kC3D10:
      return evaluate_shape<10>(shape_tet10, xi, N, dN);
    case ElementType::kC3D5:
      return evaluate_shape<5>(shape_pyr5, xi, N, dN);
    case ElementType::kC3D6:
      return evaluate_shape<6>(shape_wedge6, xi, N, dN);
    case ElementType::kC3D15:
      return evaluate_shape<15>(shape_wedge15, xi, N, dN);
  }
}

void element_strain_operators(ElementType type, const Eigen::Matrix3Xd& X,
                              const IsotropicMaterial& material, std::vector<Eigen::MatrixXd>& B) {
  switch (type) {
    case ElementType::kC3D8:
      return strain_operators_standard<8>(fixed_coordinates<8>(type, X), hex8_2(), B);
    case ElementType::kC3D8I:
      return strain_operators_hex8i(fixed_coordinates<8>(type, X), lame_lambda(material),
                                    shear_modulus(material), B);
    case ElementType::kC3D8B:
      return strain_operators_hex8b(fixed_coordinates<8>(type, X), B);
    case ElementType::kC3D8R:
      return strain_operators_hex8r(fixed_coordinates<8>(type, X), B);
    case ElementType::kC3D13:
      return strain_operators_standard<13>(fixed_coordinates<13>(type, X), pyr13_3(), B);
    case ElementType::kC3D20:
      return strain_operators_standard<20>(fixed_coordinates<20>(type, X), hex20_3(), B);
    case ElementType::kC3D20R:
      return strain_operators_standard<20>(fixed_coordinates<20>(type, X), hex20_2(), B);
    case ElementType::kC3D4:
      return strain_operators_standard<4>(fixed_coordinates<4>(type, X), tet4_1(), B);
    case ElementType::kC3D10:
      return strain_operators_standard<10>(fixed_coordinates<10>(type, X), tet10_4(), B);
    case ElementType::kC3D5:
      return strain_operators_standard<5>(fixed_coordinates<5>(type, X), pyr5_2(), B);
    case ElementType::kC3D6:
      return strain_operators_standard<6>(fixed_coordinates<6>(type, X), wedge6_k(), B);
    case ElementType::kC3D15:
      return strain_operators_standard<15>(fixed_coordinates<15>(type, X), wedge15_k(), B);
  }
}

}  // namespace stickslip

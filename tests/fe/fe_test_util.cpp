#include "fe_test_util.h"

#include <array>
#include <cmath>
#include <map>
#include <random>

#include <Eigen/Geometry>

#include "fe/element.h"

namespace stickslip::testing {

namespace {

bool is_quadratic(ElementType t) {
  return t == ElementType::kC3D20 || t == ElementType::kC3D20R || t == ElementType::kC3D10 ||
         t == ElementType::kC3D15 || t == ElementType::kC3D13;
}
bool is_hex(ElementType t) { return nodes_per_element(t) == 8 || nodes_per_element(t) == 20; }
bool is_wedge(ElementType t) { return t == ElementType::kC3D6 || t == ElementType::kC3D15; }
bool is_pyramid(ElementType t) { return t == ElementType::kC3D5 || t == ElementType::kC3D13; }

// (mid node, end a, end b) local indices of the edges of quadratic elements.
std::vector<std::array<int, 3>> mid_edges(ElementType t) {
  if (t == ElementType::kC3D10) {
    return {{4, 0, 1}, {5, 1, 2}, {6, 2, 0}, {7, 0, 3}, {8, 1, 3}, {9, 2, 3}};
  }
  if (t == ElementType::kC3D15) {
    return {{6, 0, 1},  {7, 1, 2},   {8, 2, 0},   {9, 3, 4},  {10, 4, 5},
            {11, 5, 3}, {12, 0, 3}, {13, 1, 4}, {14, 2, 5}};
  }
  if (t == ElementType::kC3D13) {
    return {{5, 0, 1}, {6, 1, 2},  {7, 2, 3},  {8, 3, 0},
            {9, 0, 4}, {10, 1, 4}, {11, 2, 4}, {12, 3, 4}};
  }
  if (t == ElementType::kC3D20 || t == ElementType::kC3D20R) {
    return {{8, 0, 1},  {9, 1, 2},  {10, 2, 3}, {11, 3, 0}, {12, 4, 5}, {13, 5, 6},
            {14, 6, 7}, {15, 7, 4}, {16, 0, 4}, {17, 1, 5}, {18, 2, 6}, {19, 3, 7}};
  }
  return {};
}

}  // namespace

Mesh box_mesh(ElementType type, int nx, int ny, int nz, const Eigen::Vector3d& size) {
  Mesh mesh;
  const bool quad = is_quadratic(type);
  // Lattice points per cell edge: the C3D13's lateral mid-edge nodes lie a quarter cell in.
  const int r = type == ElementType::kC3D13 ? 4 : (quad || is_pyramid(type) ? 2 : 1);
  const int Nx = r * nx + 1, Ny = r * ny + 1, Nz = r * nz + 1;
  std::vector<int> lattice(static_cast<size_t>(Nx) * Ny * Nz, -1);
  auto lid = [&](int i, int j, int k) { return (static_cast<size_t>(k) * Ny + j) * Nx + i; };
  auto node = [&](int i, int j, int k) {
    int& n = lattice[lid(i, j, k)];
    if (n < 0) {
      const Eigen::Vector3d x(size(0) * i / (Nx - 1), size(1) * j / (Ny - 1),
                              size(2) * k / (Nz - 1));
      n = mesh.add_node(mesh.num_nodes() + 1, x);
    }
    return n;
  };
  const Eigen::Matrix3Xd ref = natural_node_coordinates(type);
  int eid = 1;
  for (int ck = 0; ck < nz; ++ck) {
    for (int cj = 0; cj < ny; ++cj) {
      for (int ci = 0; ci < nx; ++ci) {
        if (is_hex(type)) {
          std::vector<int> nodes;
          for (int a = 0; a < ref.cols(); ++a) {
            // natural -1, 0, 1 -> lattice offset 0, r/2, r
            const int di = static_cast<int>((ref(0, a) + 1) * r / 2);
            const int dj = static_cast<int>((ref(1, a) + 1) * r / 2);
            const int dk = static_cast<int>((ref(2, a) + 1) * r / 2);
            nodes.push_back(node(r * ci + di, r * cj + dj, r * ck + dk));
          }
          mesh.add_element(eid++, type, nodes);
        } else if (is_pyramid(type)) {
          // Six pyramids per cell: each face of the cell is a base (corners ordered so that
          // their right-hand normal points into the cell), the cell's centre the apex.
          static const int kBases[6][4][3] = {
              {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}},
              {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}},
              {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}};
          for (const auto& base : kBases) {
            std::vector<std::array<int, 3>> at;  // lattice points of the corners
            for (const auto& c : base)
              at.push_back({r * (ci + c[0]), r * (cj + c[1]), r * (ck + c[2])});
            at.push_back({r * ci + r / 2, r * cj + r / 2, r * ck + r / 2});
            if (quad) {
              for (const auto& me : mid_edges(type)) {
                const auto& p = at[static_cast<size_t>(me[1])];
                const auto& q = at[static_cast<size_t>(me[2])];
                at.push_back({(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2});
              }
            }
            std::vector<int> nodes;
            for (const auto& p : at) nodes.push_back(node(p[0], p[1], p[2]));
            mesh.add_element(eid++, type, nodes);
          }
        } else if (is_wedge(type)) {
          // Two wedges per cell: the x-y square split along its (0,0)-(1,1) diagonal, extruded
          // in z; the natural triangle (L2 = xi, L3 = eta) is mapped onto each half.
          static const int kHalves[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
          for (const auto& h : kHalves) {
            std::vector<int> nodes;
            for (int a = 0; a < ref.cols(); ++a) {
              // Lattice point of natural (xi, eta, zeta): barycentric blend of the half's corners.
              const double l[3] = {1.0 - ref(0, a) - ref(1, a), ref(0, a), ref(1, a)};
              double x = 0, y = 0;
              for (int c = 0; c < 3; ++c) x += l[c] * h[c][0], y += l[c] * h[c][1];
              const int di = static_cast<int>(std::lround(x * r));
              const int dj = static_cast<int>(std::lround(y * r));
              const int dk = static_cast<int>(std::lround((ref(2, a) + 1) * r / 2));
              nodes.push_back(node(r * ci + di, r * cj + dj, r * ck + dk));
            }
            mesh.add_element(eid++, type, nodes);
          }
        } else {
          // Kuhn subdivision along the diagonal v0 -> v7, v = i + 2j + 4k.
          static const int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                          {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
          for (const auto& t : kTets) {
            std::array<std::array<int, 3>, 4> c;
            for (int a = 0; a < 4; ++a) {
              c[a] = {r * (ci + (t[a] & 1)), r * (cj + ((t[a] >> 1) & 1)),
                      r * (ck + ((t[a] >> 2) & 1))};
            }
            Eigen::Matrix3d E;
            for (int a = 0; a < 3; ++a) {
              for (int d = 0; d < 3; ++d) E(d, a) = c[a + 1][d] - c[0][d];
            }
            if (E.determinant() < 0) std::swap(c[1], c[2]);
            std::vector<int> nodes;
            for (int a = 0; a < 4; ++a) nodes.push_back(node(c[a][0], c[a][1], c[a][2]));
            if (quad) {
              for (const auto& me : mid_edges(ElementType::kC3D10)) {
                const auto& p = c[me[1]];
                const auto& q = c[me[2]];
                nodes.push_back(node((p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2));
              }
            }
            mesh.add_element(eid++, type, nodes);
          }
        }
      }
    }
  }
  return mesh;
}

std::vector<int> boundary_nodes(const Mesh& mesh, const Eigen::Vector3d& size) {
  const double tol = 1e-9 * size.norm();
  std::vector<int> out;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    bool on = false;
    for (int d = 0; d < 3; ++d) {
      const double x = mesh.coordinates(d, n);
      on = on || std::abs(x) < tol || std::abs(x - size(d)) < tol;
    }
    if (on) out.push_back(n);
  }
  return out;
}

void perturb_nodes(Mesh& mesh, const Eigen::Vector3d& size, double amplitude, unsigned seed,
                   bool keep_boundary) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  std::vector<char> fixed(mesh.num_nodes(), 0);
  if (keep_boundary) {
    for (int n : boundary_nodes(mesh, size)) fixed[n] = 1;
  }
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    const Eigen::Vector3d d(u(rng), u(rng), u(rng));
    if (!fixed[n]) mesh.coordinates.col(n) += d;
  }
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto nodes = mesh.element_nodes(e);
    for (const auto& me : mid_edges(mesh.element_types[e])) {
      mesh.coordinates.col(nodes[me[0]]) =
          0.5 * (mesh.coordinates.col(nodes[me[1]]) + mesh.coordinates.col(nodes[me[2]]));
    }
  }
}

Eigen::Matrix3Xd element_coordinates(const Mesh& mesh, int e) {
  const auto nodes = mesh.element_nodes(e);
  Eigen::Matrix3Xd X(3, nodes.size());
  for (size_t a = 0; a < nodes.size(); ++a) X.col(a) = mesh.coordinates.col(nodes[a]);
  return X;
}

Eigen::Matrix3Xd distorted_element(ElementType type, unsigned seed, double corner_amplitude,
                                   double curved_amplitude) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // Random rotation and stretch: A = Q diag(s), plus translation.
  const Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  const Eigen::Matrix3d Q = q.normalized().toRotationMatrix();
  const Eigen::Vector3d s(0.7 + 0.2 * u(rng), 1.0 + 0.2 * u(rng), 0.4 + 0.1 * u(rng));
  const Eigen::Vector3d t(u(rng), u(rng), u(rng));
  const Eigen::Matrix3Xd ref = natural_node_coordinates(type);
  const int nc = is_hex(type) ? 8 : (is_wedge(type) ? 6 : (is_pyramid(type) ? 5 : 4));
  Eigen::Matrix3Xd X(3, ref.cols());
  for (int a = 0; a < ref.cols(); ++a) {
    Eigen::Vector3d p = ref.col(a);
    if (a < nc) p += corner_amplitude * Eigen::Vector3d(u(rng), u(rng), u(rng));
    X.col(a) = Q * s.asDiagonal() * p + t;
  }
  for (const auto& me : mid_edges(type)) {
    X.col(me[0]) = 0.5 * (X.col(me[1]) + X.col(me[2]));
    X.col(me[0]) += curved_amplitude * Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  return X;
}

namespace {
// V = 1/3 ∫ x·n dS over the bilinear quadrilateral f (outward, counter-clockwise seen from
// outside), with 2x2 Gauss points (exact for a bilinear face).
double bilinear_face_flux(const Eigen::Matrix3Xd& X, const std::array<int, 4>& f) {
  const double g = 1.0 / std::sqrt(3.0);
  double v = 0.0;
  for (double s : {-g, g}) {
    for (double t : {-g, g}) {
      const Eigen::Vector3d x =
          0.25 * ((1 - s) * (1 - t) * X.col(f[0]) + (1 + s) * (1 - t) * X.col(f[1]) +
                  (1 + s) * (1 + t) * X.col(f[2]) + (1 - s) * (1 + t) * X.col(f[3]));
      const Eigen::Vector3d xs = 0.25 * (-(1 - t) * X.col(f[0]) + (1 - t) * X.col(f[1]) +
                                         (1 + t) * X.col(f[2]) - (1 + t) * X.col(f[3]));
      const Eigen::Vector3d xt = 0.25 * (-(1 - s) * X.col(f[0]) - (1 + s) * X.col(f[1]) +
                                         (1 + s) * X.col(f[2]) + (1 - s) * X.col(f[3]));
      v += x.dot(xs.cross(xt));
    }
  }
  return v / 3.0;
}
}  // namespace

double independent_volume(ElementType type, const Eigen::Matrix3Xd& X) {
  if (is_pyramid(type)) {
    // Divergence theorem: the bilinear base (outward: 0 3 2 1) and four flat triangles.
    double v = bilinear_face_flux(X, {0, 3, 2, 1});
    for (const auto& t : {std::array<int, 3>{0, 1, 4}, std::array<int, 3>{1, 2, 4},
                          std::array<int, 3>{2, 3, 4}, std::array<int, 3>{3, 0, 4}}) {
      const Eigen::Vector3d a = X.col(t[0]), b = X.col(t[1]), c = X.col(t[2]);
      v += ((a + b + c) / 3.0).dot(0.5 * (b - a).cross(c - a)) / 3.0;
    }
    return v;
  }
  if (is_wedge(type)) {
    // Divergence theorem: V = 1/3 Σ_faces ∫ x·n dS; flat triangles exactly (centroid · area
    // vector), bilinear quadrilaterals with 2x2 Gauss points (exact for them). Outward faces.
    const auto corner = [&](int a) { return Eigen::Vector3d(X.col(a)); };
    double v = 0.0;
    for (const auto& t : {std::array<int, 3>{0, 2, 1}, std::array<int, 3>{3, 4, 5}}) {
      const Eigen::Vector3d c = (corner(t[0]) + corner(t[1]) + corner(t[2])) / 3.0;
      v += c.dot(0.5 * (corner(t[1]) - corner(t[0])).cross(corner(t[2]) - corner(t[0])));
    }
    const double g = 1.0 / std::sqrt(3.0);
    for (const auto& f : {std::array<int, 4>{0, 1, 4, 3}, std::array<int, 4>{1, 2, 5, 4},
                          std::array<int, 4>{2, 0, 3, 5}}) {
      for (double s : {-g, g}) {
        for (double t : {-g, g}) {
          const Eigen::Vector3d x =
              0.25 * ((1 - s) * (1 - t) * corner(f[0]) + (1 + s) * (1 - t) * corner(f[1]) +
                      (1 + s) * (1 + t) * corner(f[2]) + (1 - s) * (1 + t) * corner(f[3]));
          const Eigen::Vector3d xs = 0.25 * (-(1 - t) * corner(f[0]) + (1 - t) * corner(f[1]) +
                                             (1 + t) * corner(f[2]) - (1 + t) * corner(f[3]));
          const Eigen::Vector3d xt = 0.25 * (-(1 - s) * corner(f[0]) - (1 + s) * corner(f[1]) +
                                             (1 + s) * corner(f[2]) + (1 - s) * corner(f[3]));
          v += x.dot(xs.cross(xt));
        }
      }
    }
    return v / 3.0;
  }
  if (!is_hex(type)) {
    Eigen::Matrix3d E;
    for (int a = 0; a < 3; ++a) E.col(a) = X.col(a + 1) - X.col(0);
    return E.determinant() / 6.0;
  }
  // Faces with outward orientation (counter-clockwise seen from outside).
  static const int kFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                   {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const double g = 1.0 / std::sqrt(3.0);
  double v = 0.0;
  for (const auto& f : kFaces) {
    for (double s : {-g, g}) {
      for (double t : {-g, g}) {
        const double n0 = 0.25 * (1 - s) * (1 - t), n1 = 0.25 * (1 + s) * (1 - t),
                     n2 = 0.25 * (1 + s) * (1 + t), n3 = 0.25 * (1 - s) * (1 + t);
        const Eigen::Vector3d x =
            n0 * X.col(f[0]) + n1 * X.col(f[1]) + n2 * X.col(f[2]) + n3 * X.col(f[3]);
        const Eigen::Vector3d xs = 0.25 * (-(1 - t) * X.col(f[0]) + (1 - t) * X.col(f[1]) +
                                           (1 + t) * X.col(f[2]) - (1 + t) * X.col(f[3]));
        const Eigen::Vector3d xt = 0.25 * (-(1 - s) * X.col(f[0]) - (1 + s) * X.col(f[1]) +
                                           (1 + s) * X.col(f[2]) + (1 - s) * X.col(f[3]));
        v += x.dot(xs.cross(xt));  // 2x2 Gauss weights are 1
      }
    }
  }
  return v / 3.0;
}

Eigen::MatrixXd rigid_body_modes(const Eigen::Matrix3Xd& X) {
  const int n = static_cast<int>(X.cols());
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(3 * n, 6);
  for (int a = 0; a < n; ++a) {
    for (int d = 0; d < 3; ++d) R(3 * a + d, d) = 1.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d w = Eigen::Vector3d::Unit(k).cross(X.col(a));
      R.block<3, 1>(3 * a, 3 + k) = w;
    }
  }
  return R;
}

}  // namespace stickslip::testing

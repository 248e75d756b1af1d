#include "mesh/surface_area.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/errors.h"

namespace stickslip {
namespace {

// Corner cycles of the faces (CalculiX face numbering) and the mid-edge node of each edge.
constexpr int kHexFaces[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                                 {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
constexpr int kHexEdges[12][3] = {{0, 1, 8},  {1, 2, 9},  {2, 3, 10}, {0, 3, 11},
                                  {4, 5, 12}, {5, 6, 13}, {6, 7, 14}, {4, 7, 15},
                                  {0, 4, 16}, {1, 5, 17}, {2, 6, 18}, {3, 7, 19}};
constexpr int kTetFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
constexpr int kTetEdges[6][3] = {{0, 1, 4}, {1, 2, 5}, {0, 2, 6}, {0, 3, 7}, {1, 3, 8}, {2, 3, 9}};
// Wedges (C3D6, C3D15): two triangles and three quadrilaterals, ordered as the hexahedron's.
constexpr int kWedgeTriangles[2][3] = {{0, 1, 2}, {3, 5, 4}};
constexpr int kWedgeQuads[3][4] = {{0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}};
// Pyramid (C3D5): the base and four triangles, the brick's faces with nodes 5-8 collapsed to 4.
constexpr int kPyramidQuad[4] = {0, 1, 2, 3};
constexpr int kPyramidTriangles[4][3] = {{0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
// C3D13's mid-edge nodes: base edges 5-8, lateral edges 9-12.
constexpr int kPyramidEdges[8][3] = {{0, 1, 5}, {1, 2, 6},  {2, 3, 7},  {0, 3, 8},
                                     {0, 4, 9}, {1, 4, 10}, {2, 4, 11}, {3, 4, 12}};
constexpr int kWedgeEdges[9][3] = {{0, 1, 6},  {1, 2, 7},  {0, 2, 8},  {3, 4, 9}, {4, 5, 10},
                                   {3, 5, 11}, {0, 3, 12}, {1, 4, 13}, {2, 5, 14}};

template <size_t N>
int midside(const int (&edges)[N][3], int a, int b) {
  if (a > b) std::swap(a, b);
  for (const auto& e : edges) {
    if (e[0] == a && e[1] == b) return e[2];
  }
  return -1;
}

// Local node numbers of every face of an element type (corners, then mid-edge nodes).
std::vector<std::vector<int>> local_faces(ElementType type) {
  std::vector<std::vector<int>> faces;
  const bool quadratic = type == ElementType::kC3D20 || type == ElementType::kC3D20R ||
                         type == ElementType::kC3D10 || type == ElementType::kC3D15 ||
                         type == ElementType::kC3D13;
  const bool wedge = type == ElementType::kC3D6 || type == ElementType::kC3D15;
  const bool pyramid = type == ElementType::kC3D5 || type == ElementType::kC3D13;
  const bool hex = type == ElementType::kC3D8 || type == ElementType::kC3D8I ||
                   type == ElementType::kC3D8B || type == ElementType::kC3D8R ||
                   type == ElementType::kC3D20 || type == ElementType::kC3D20R;
  const auto add = [&](const int* corners, int n) {
    std::vector<int> f(corners, corners + n);
    if (quadratic) {
      for (int k = 0; k < n; ++k) {
        const int a = corners[k], b = corners[(k + 1) % n];
        f.push_back(hex       ? midside(kHexEdges, a, b)
                    : wedge   ? midside(kWedgeEdges, a, b)
                    : pyramid ? midside(kPyramidEdges, a, b)
                              : midside(kTetEdges, a, b));
      }
    }
    faces.push_back(std::move(f));
  };
  if (hex) {
    for (const auto& c : kHexFaces) add(c, 4);
  } else if (pyramid) {
    add(kPyramidQuad, 4);
    for (const auto& c : kPyramidTriangles) add(c, 3);
  } else if (wedge) {
    for (const auto& c : kWedgeTriangles) add(c, 3);
    for (const auto& c : kWedgeQuads) add(c, 4);
  } else {
    for (const auto& c : kTetFaces) add(c, 3);
  }
  return faces;
}

// ∫ N_i dA and ∫ N_i² dA over one face, and its area.
struct FaceIntegrals {
  Eigen::VectorXd n, n2;
  double area = 0.0;
};

FaceIntegrals integrate_face(const Mesh& mesh, const ElementFace& face) {
  const int n = static_cast<int>(face.nodes.size());
  Eigen::Matrix3Xd X(3, n);
  for (int a = 0; a < n; ++a) X.col(a) = mesh.coordinates.col(face.nodes[a]);
  FaceIntegrals r;
  r.n = Eigen::VectorXd::Zero(n);
  r.n2 = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd N;
  Eigen::Matrix2Xd dN;
  for (const FacePoint& p : face_rule(n)) {
    face_shape(n, p.xi, p.eta, N, dN);
    const Eigen::Vector3d gx = X * dN.row(0).transpose(), gy = X * dN.row(1).transpose();
    const double dA = gx.cross(gy).norm() * p.w;
    r.n += N * dA;
    r.n2 += N.cwiseProduct(N) * dA;
    r.area += dA;
  }
  return r;
}

}  // namespace

void face_shape(int n, double xi, double eta, Eigen::VectorXd& N, Eigen::Matrix2Xd& dN) {
  N.resize(n);
  dN.resize(2, n);
  if (n == 4 || n == 8) {
    constexpr double kCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int a = 0; a < 4; ++a) {
      const double xa = kCorner[a][0], ya = kCorner[a][1];
      const double fx = 1 + xi * xa, fy = 1 + eta * ya;
      if (n == 4) {
        N(a) = 0.25 * fx * fy;
        dN(0, a) = 0.25 * xa * fy;
        dN(1, a) = 0.25 * fx * ya;
      } else {
        const double s = xi * xa + eta * ya - 1;
        N(a) = 0.25 * fx * fy * s;
        dN(0, a) = 0.25 * xa * fy * s + 0.25 * fx * fy * xa;
        dN(1, a) = 0.25 * fx * ya * s + 0.25 * fx * fy * ya;
      }
    }
    if (n == 8) {
      constexpr double kMid[4][2] = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
      for (int m = 0; m < 4; ++m) {
        const int a = 4 + m;
        const double xa = kMid[m][0], ya = kMid[m][1];
        if (xa == 0) {
          N(a) = 0.5 * (1 - xi * xi) * (1 + eta * ya);
          dN(0, a) = -xi * (1 + eta * ya);
          dN(1, a) = 0.5 * (1 - xi * xi) * ya;
        } else {
          N(a) = 0.5 * (1 + xi * xa) * (1 - eta * eta);
          dN(0, a) = 0.5 * xa * (1 - eta * eta);
          dN(1, a) = -eta * (1 + xi * xa);
        }
      }
    }
    return;
  }
  // Triangles: barycentric L = (1 − ξ − η, ξ, η).
  const double L[3] = {1 - xi - eta, xi, eta};
  const double dL[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
  for (int a = 0; a < 3; ++a) {
    if (n == 3) {
      N(a) = L[a];
      dN(0, a) = dL[a][0];
      dN(1, a) = dL[a][1];
    } else {
      N(a) = L[a] * (2 * L[a] - 1);
      dN(0, a) = (4 * L[a] - 1) * dL[a][0];
      dN(1, a) = (4 * L[a] - 1) * dL[a][1];
    }
  }
  if (n == 6) {
    for (int e = 0; e < 3; ++e) {
      const int i = e, j = (e + 1) % 3;
      N(3 + e) = 4 * L[i] * L[j];
      dN(0, 3 + e) = 4 * (L[i] * dL[j][0] + L[j] * dL[i][0]);
      dN(1, 3 + e) = 4 * (L[i] * dL[j][1] + L[j] * dL[i][1]);
    }
  }
}

const std::vector<FacePoint>& face_rule(int n) {
  static const std::vector<FacePoint> quad = [] {
    const double s[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    const double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    std::vector<FacePoint> r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) r.push_back({s[i], s[j], w[i] * w[j]});
    }
    return r;
  }();
  static const std::vector<FacePoint> tri = [] {
    const double a = 0.445948490915965, wa = 0.223381589678011;
    const double b = 0.091576213509771, wb = 0.109951743655322;
    std::vector<FacePoint> r;
    for (const auto& [p, w] : {std::pair{a, wa}, std::pair{b, wb}}) {
      r.push_back({p, p, 0.5 * w});
      r.push_back({1 - 2 * p, p, 0.5 * w});
      r.push_back({p, 1 - 2 * p, 0.5 * w});
    }
    return r;
  }();
  return n == 4 || n == 8 ? quad : tri;
}

namespace {

// ∫ N_i n dA over one face, n = ∂x/∂ξ × ∂x/∂η / |…| as the face's node order gives it (3 x n).
Eigen::Matrix3Xd integrate_face_normal(const Mesh& mesh, const ElementFace& face) {
  const int n = static_cast<int>(face.nodes.size());
  Eigen::Matrix3Xd X(3, n);
  for (int a = 0; a < n; ++a) X.col(a) = mesh.coordinates.col(face.nodes[a]);
  Eigen::Matrix3Xd r = Eigen::Matrix3Xd::Zero(3, n);
  Eigen::VectorXd N;
  Eigen::Matrix2Xd dN;
  for (const FacePoint& p : face_rule(n)) {
    face_shape(n, p.xi, p.eta, N, dN);
    const Eigen::Vector3d gx = X * dN.row(0).transpose(), gy = X * dN.row(1).transpose();
    const Eigen::Vector3d ndA = gx.cross(gy) * p.w;  // unit normal times dA
    r += ndA * N.transpose();
  }
  return r;
}

}  // namespace

std::pair<int, int> interior_face(const Mesh& mesh, std::span<const int> nodes) {
  // Every face of every element within the set, to find faces shared by two elements.
  const std::unordered_set<int> in(nodes.begin(), nodes.end());
  std::map<std::vector<int>, std::vector<int>> elements_of_face;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const std::span<const int> element = mesh.element_nodes(e);
    for (const std::vector<int>& local : local_faces(mesh.element_types[e])) {
      std::vector<int> key;
      for (int l : local) key.push_back(element[static_cast<size_t>(l)]);
      if (!std::all_of(key.begin(), key.end(), [&](int v) { return in.count(v) > 0; })) continue;
      std::sort(key.begin(), key.end());
      elements_of_face[key].push_back(e);
    }
  }
  for (const auto& [key, elements] : elements_of_face) {
    if (elements.size() > 1) return {elements[0], elements[1]};
  }
  return {-1, -1};
}

std::vector<Eigen::Vector3d> pressure_nodal_forces(const Mesh& mesh, std::span<const int> nodes,
                                                   double pressure) {
  if (const auto [e1, e2] = interior_face(mesh, nodes); e1 >= 0) {
    throw InvalidInput("the pressure's nodes hold a face shared by elements " +
                       std::to_string(mesh.element_ids[e1]) + " and " +
                       std::to_string(mesh.element_ids[e2]) +
                       " (inside the body): a pressure acts on the body's boundary faces only");
  }
  const std::vector<ElementFace> faces = faces_within(mesh, nodes);
  if (faces.empty()) {
    throw InvalidInput("the pressure's nodes hold no element face (select whole faces, mid-edge "
                       "nodes included for quadratic elements)");
  }
  std::unordered_map<int, Eigen::Vector3d> by_node;
  for (const ElementFace& face : faces) {
    Eigen::Matrix3Xd nN = integrate_face_normal(mesh, face);
    // Orientation: out of the element, away from its centroid.
    const std::span<const int> element = mesh.element_nodes(face.element);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero(), face_centre = Eigen::Vector3d::Zero();
    for (int v : element) centre += mesh.coordinates.col(v);
    centre /= static_cast<double>(element.size());
    for (int v : face.nodes) face_centre += mesh.coordinates.col(v);
    face_centre /= static_cast<double>(face.nodes.size());
    if (nN.rowwise().sum().dot(face_centre - centre) < 0) nN = -nN;
    for (size_t k = 0; k < face.nodes.size(); ++k) {
      auto [it, inserted] = by_node.try_emplace(face.nodes[k], Eigen::Vector3d::Zero());
      it->second -= pressure * nN.col(static_cast<Eigen::Index>(k));
    }
  }
  std::vector<Eigen::Vector3d> out;
  out.reserve(nodes.size());
  for (int node : nodes) {
    const auto it = by_node.find(node);
    out.push_back(it == by_node.end() ? Eigen::Vector3d::Zero() : it->second);
  }
  return out;
}

std::vector<ElementFace> faces_within(const Mesh& mesh, std::span<const int> nodes) {
  const std::unordered_set<int> in(nodes.begin(), nodes.end());
  std::vector<ElementFace> faces;
  std::set<std::vector<int>> seen;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const std::span<const int> element = mesh.element_nodes(e);
    for (const std::vector<int>& local : local_faces(mesh.element_types[e])) {
      ElementFace face{e, {}};
      bool inside = true;
      for (int l : local) {
        const int node = element[static_cast<size_t>(l)];
        if (!in.count(node)) {
          inside = false;
          break;
        }
        face.nodes.push_back(node);
      }
      if (!inside) continue;
      std::vector<int> key = face.nodes;
      std::sort(key.begin(), key.end());
      if (seen.insert(key).second) faces.push_back(std::move(face));
    }
  }
  return faces;
}

double face_area(const Mesh& mesh, const ElementFace& face) {
  return integrate_face(mesh, face).area;
}

std::vector<double> nodal_areas(const Mesh& mesh, std::span<const int> nodes, NodalAreaRule rule) {
  std::unordered_map<int, double> by_node;
  for (const ElementFace& face : faces_within(mesh, nodes)) {
    const FaceIntegrals f = integrate_face(mesh, face);
    const int n = static_cast<int>(face.nodes.size());
    const bool quadratic = n == 6 || n == 8;
    const bool scaled =
        rule == NodalAreaRule::kDiagonalScaled || (rule == NodalAreaRule::kAutomatic && quadratic);
    const Eigen::VectorXd a = scaled ? Eigen::VectorXd(f.n2 * (f.area / f.n2.sum())) : f.n;
    for (int k = 0; k < n; ++k) by_node[face.nodes[k]] += a(k);
  }
  std::vector<double> out;
  out.reserve(nodes.size());
  for (int node : nodes) {
    const auto it = by_node.find(node);
    out.push_back(it == by_node.end() ? 0.0 : it->second);
  }
  return out;
}

}  // namespace stickslip

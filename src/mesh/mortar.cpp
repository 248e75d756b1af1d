#include "mesh/mortar.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>

#include <Eigen/Dense>

#include "core/errors.h"

namespace stickslip {
namespace {

// A face whose normal (a cross product of two edges or diagonals) is at or below 1e-12 of its
// size squared has no direction: collapsed nodes, not a face.
constexpr double kDegenerateFace = 1e-12;
// Newton's inverse map of a bilinear quadrilateral stops at 1e-15 of the face's size: a few eps,
// the round-off of the point itself.
constexpr double kInverseMapTolerance = 1e-15;
// A clipped overlap of two faces below 1e-12 of the clip face's area is a touching edge or a
// corner, not a shared surface: no coupling from it.
constexpr double kSliverOverlap = 1e-12;
// Partner weights |Φ_ik| = |M_ik| / D_i below 1e-14 are the round-off of integrals that vanish
// (ψ_i against the shape function of a B node whose support only touches the point's: on
// conforming faces every partner but the coincident node): dropped, so that such a node is not
// made a master of B for nothing. The weights' sum moves by less than that per dropped node.
constexpr double kNegligiblePartner = 1e-14;

// Quadratic faces (6-node triangles, 8-node quadrilaterals): their corner integrals ∫ N_c dA are
// zero or negative, so the dual basis is built on the transformed basis Ñ_c = N_c + α Σ N_m (the
// mid-edge functions of the corner's two edges), Ñ_m = (1 − 2α) N_m, which keeps Σ Ñ = 1 and
// makes every ∫ Ñ_i dA positive for α > 1/8 (8-node) or α > 0 (6-node); α = 1/5 is the value of
// Popp, Wohlmuth, Gee and Wall (SIAM J. Sci. Comput. 34, 2012): corners A/20, mid-edges A/5 on an
// 8-node rectangle of area A, corners A/15 and mid-edges 4A/15 on a 6-node triangle.
constexpr double kQuadraticBasisShift = 0.2;

using Vec2 = Eigen::Vector2d;
using Polygon = std::vector<Vec2>;

// A face seen from its own plane.
struct Face {
  int n = 0;                   // nodes: 3, 4 (linear), 6, 8 (quadratic)
  int corners = 0;             // 3 or 4
  Eigen::Matrix3Xd X;          // nodes, 3 x n (corners first, ElementFace order)
  Eigen::Vector3d centroid, normal;  // normal: unit, out of the face's element
  Eigen::AlignedBox3d box;
};

Face make_face(const Mesh& mesh, const ElementFace& f, const char* side, int index) {
  const int n = static_cast<int>(f.nodes.size());
  if (n != 3 && n != 4 && n != 6 && n != 8) {
    throw InvalidInput(
        "mortar coupling: face " + std::to_string(index) + " of surface " + side + " (element " +
        std::to_string(mesh.element_ids[static_cast<size_t>(f.element)]) + ") has " +
        std::to_string(n) +
        " nodes: only 3- and 6-node triangles and 4- and 8-node quadrilaterals can be coupled");
  }
  Face face;
  face.n = n;
  face.corners = n == 3 || n == 6 ? 3 : 4;
  face.X.resize(3, n);
  for (int a = 0; a < n; ++a) face.X.col(a) = mesh.coordinates.col(f.nodes[a]);
  face.centroid = face.X.leftCols(face.corners).rowwise().mean();
  Eigen::Vector3d normal = face.corners == 4 ? Eigen::Vector3d((face.X.col(2) - face.X.col(0))
                                                        .cross(face.X.col(3) - face.X.col(1)))
                                  : Eigen::Vector3d((face.X.col(1) - face.X.col(0))
                                                        .cross(face.X.col(2) - face.X.col(0)));
  const double size = (face.X.colwise() - face.centroid).colwise().norm().maxCoeff();
  if (!(normal.norm() > kDegenerateFace * size * size)) {
    throw InvalidInput("mortar coupling: face " + std::to_string(index) + " of surface " + side +
                       " (element " +
                       std::to_string(mesh.element_ids[static_cast<size_t>(f.element)]) +
                       ") has no area");
  }
  normal.normalize();
  // Out of the element: away from the centroid of its nodes.
  Eigen::Vector3d element_centroid = Eigen::Vector3d::Zero();
  const std::span<const int> nodes = mesh.element_nodes(f.element);
  for (int node : nodes) element_centroid += mesh.coordinates.col(node);
  element_centroid /= static_cast<double>(nodes.size());
  if (normal.dot(face.centroid - element_centroid) < 0) normal = -normal;
  face.normal = normal;
  for (int a = 0; a < n; ++a) face.box.extend(Eigen::Vector3d(face.X.col(a)));
  return face;
}

// Signed area of a polygon (counter-clockwise > 0).
double signed_area(const Polygon& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}

// Sutherland–Hodgman: `subject` clipped by the convex counter-clockwise polygon `clip`.
Polygon clip_polygon(const Polygon& subject, const Polygon& clip) {
  Polygon out = subject;
  for (size_t e = 0; e < clip.size() && !out.empty(); ++e) {
    const Vec2 a = clip[e], b = clip[(e + 1) % clip.size()];
    const Vec2 edge = b - a;
    auto side = [&](const Vec2& p) { return edge.x() * (p.y() - a.y()) - edge.y() * (p.x() - a.x()); };
    Polygon in = std::move(out);
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const Vec2& p = in[i];
      const Vec2& q = in[(i + 1) % in.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) out.push_back(p + (sp / (sp - sq)) * (q - p));
    }
  }
  return out;
}

// Natural coordinates of the 2D point p in the face whose nodes (in the plane) are `P` (2 x n):
// exact for 3-node triangles, Newton on the isoparametric map otherwise (from the corners' affine
// map for 6-node triangles: one step when their edges are straight).
Vec2 natural_coordinates(const Eigen::Matrix2Xd& P, const Vec2& p) {
  const int n = static_cast<int>(P.cols());
  if (n == 3 || n == 6) {
    Eigen::Matrix2d J;
    J << P(0, 1) - P(0, 0), P(0, 2) - P(0, 0), P(1, 1) - P(1, 0), P(1, 2) - P(1, 0);
    const Vec2 linear = J.inverse() * (p - P.col(0));
    if (n == 3) return linear;
  }
  Vec2 xi = n == 6 ? Vec2(1.0 / 3, 1.0 / 3) : Vec2(0, 0);
  Eigen::VectorXd N;
  Eigen::Matrix2Xd dN;
  const double scale = (P.colwise() - P.rowwise().mean()).norm();
  for (int it = 0; it < 50; ++it) {
    face_shape(n, xi.x(), xi.y(), N, dN);
    const Vec2 r = P * N - p;
    if (r.norm() <= kInverseMapTolerance * scale) break;
    const Eigen::Matrix2d J = P * dN.transpose();
    xi -= J.inverse() * r;
  }
  return xi;
}

// The 7-point degree-5 rule on a triangle (Radon): barycentric points and weights summing to 1.
struct TrianglePoint {
  double l0, l1, l2, w;
};
const std::array<TrianglePoint, 7>& triangle_rule() {
  static const std::array<TrianglePoint, 7> rule = [] {
    const double s = std::sqrt(15.0);
    const double a = (6 - s) / 21, b = (6 + s) / 21;
    const double wa = (155 - s) / 1200, wb = (155 + s) / 1200;
    return std::array<TrianglePoint, 7>{{{1.0 / 3, 1.0 / 3, 1.0 / 3, 9.0 / 40},
                                         {a, a, 1 - 2 * a, wa},
                                         {a, 1 - 2 * a, a, wa},
                                         {1 - 2 * a, a, a, wa},
                                         {b, b, 1 - 2 * b, wb},
                                         {b, 1 - 2 * b, b, wb},
                                         {1 - 2 * b, b, b, wb}}};
  }();
  return rule;
}

// The collapsed (Duffy) 4 x 4 Gauss–Legendre rule on a triangle: (u, v) in [0, 1]² to
// barycentric (1 − u, u (1 − v), u v), weight w_u w_v u (the map's Jacobian over the area 1/2).
// Exact for polynomials of total degree 6 (x^a y^b becomes degree a + b + 1 ≤ 7 in u and b ≤ 6 in
// v, and 4 Gauss points integrate degree 7): the products of quadratic faces' shape functions
// (degree ≤ 3 each on parallelograms: 8-node serendipity) with one another.
const std::array<TrianglePoint, 16>& collapsed_triangle_rule() {
  static const std::array<TrianglePoint, 16> rule = [] {
    const double a = std::sqrt(3.0 / 7 - 2.0 / 7 * std::sqrt(6.0 / 5));
    const double b = std::sqrt(3.0 / 7 + 2.0 / 7 * std::sqrt(6.0 / 5));
    const double wa = (18 + std::sqrt(30.0)) / 36, wb = (18 - std::sqrt(30.0)) / 36;
    const double x[4] = {-b, -a, a, b}, w[4] = {wb, wa, wa, wb};  // on [−1, 1]
    std::array<TrianglePoint, 16> r{};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const double u = 0.5 * (1 + x[i]), v = 0.5 * (1 + x[j]);
        // ∫_T f dA / |T| = 2 ∫∫ f u du dv; the Gauss weights on [0, 1] are w/2 each.
        r[static_cast<size_t>(4 * i + j)] = {1 - u, u * (1 - v), u * v, 2 * u * 0.25 * w[i] * w[j]};
      }
    return r;
  }();
  return rule;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Uniform grid of B faces by bounding box.
class FaceGrid {
 public:
  FaceGrid(const std::vector<Face>& faces, double pad) : faces_(faces) {
    double extent = 0;
    for (const Face& f : faces) extent = std::max(extent, f.box.sizes().maxCoeff());
    cell_ = std::max(extent + 2 * pad, 1e-300);
    for (size_t i = 0; i < faces.size(); ++i) cells_[key(faces[i].centroid)].push_back(static_cast<int>(i));
  }
  // Faces whose centroid lies within `box` grown by one cell.
  std::vector<int> near(const Eigen::AlignedBox3d& box) const {
    const Eigen::Array3i lo = cell_of(box.min()) - 1, hi = cell_of(box.max()) + 1;
    std::vector<int> out;
    const long cells = static_cast<long>(hi.x() - lo.x() + 1) * (hi.y() - lo.y() + 1) * (hi.z() - lo.z() + 1);
    if (cells > static_cast<long>(cells_.size())) {  // a face larger than the grid: scan the map
      for (const auto& [k, list] : cells_) {
        const Eigen::Array3i c = unkey(k);
        if ((c >= lo).all() && (c <= hi).all()) out.insert(out.end(), list.begin(), list.end());
      }
    } else {
      for (int x = lo.x(); x <= hi.x(); ++x)
        for (int y = lo.y(); y <= hi.y(); ++y)
          for (int z = lo.z(); z <= hi.z(); ++z) {
            const auto it = cells_.find(pack(x, y, z));
            if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
          }
    }
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  Eigen::Array3i cell_of(const Eigen::Vector3d& x) const {
    return (x.array() / cell_).floor().cast<int>();
  }
  static long long pack(int x, int y, int z) {
    const auto u = [](int v) { return static_cast<long long>(v + (1 << 20)) & 0x1FFFFF; };
    return (u(x) << 42) | (u(y) << 21) | u(z);
  }
  static Eigen::Array3i unkey(long long k) {
    return Eigen::Array3i(static_cast<int>((k >> 42) & 0x1FFFFF) - (1 << 20),
                          static_cast<int>((k >> 21) & 0x1FFFFF) - (1 << 20),
                          static_cast<int>(k & 0x1FFFFF) - (1 << 20));
  }
  long long key(const Eigen::Vector3d& x) const {
    const Eigen::Array3i c = cell_of(x);
    return pack(c.x(), c.y(), c.z());
  }
  const std::vector<Face>& faces_;
  double cell_ = 1;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace

MortarCoupling mortar_coupling(const Mesh& mesh_a, std::span<const ElementFace> faces_a,
                               const Mesh& mesh_b, std::span<const ElementFace> faces_b,
                               const MortarOptions& options) {
  if (faces_a.empty() || faces_b.empty()) {
    throw InvalidInput(std::string("mortar coupling: surface ") + (faces_a.empty() ? "A" : "B") +
                       " has no faces (no element face has all its nodes in the surface's set)");
  }
  std::vector<Face> A, B;
  for (size_t i = 0; i < faces_a.size(); ++i) A.push_back(make_face(mesh_a, faces_a[i], "A", static_cast<int>(i)));
  for (size_t i = 0; i < faces_b.size(); ++i) B.push_back(make_face(mesh_b, faces_b[i], "B", static_cast<int>(i)));

  MortarCoupling out;
  double search = options.search_distance;
  if (!(search > 0)) {
    std::vector<double> edges;
    for (const Face& f : A) {
      for (int a = 0; a < f.n; ++a) edges.push_back((f.X.col((a + 1) % f.n) - f.X.col(a)).norm());
    }
    search = 0.5 * median(edges);
  }
  out.search_distance = search;
  const FaceGrid grid(B, search);

  // Per A node: D_i, the D-weighted normal, M_ik, the B faces it meets, and (quadratic faces)
  // ∫ ψ_i N_j dA over A's own faces.
  std::map<int, double> D;
  std::map<int, Eigen::Vector3d> normal;
  std::map<int, std::map<int, double>> M, MA;
  std::map<int, std::set<int>> met;
  std::map<int, double> covered;  // ∫_{A∩B} Ñ_i dA

  Eigen::VectorXd N, NB;
  Eigen::Matrix2Xd dN;
  for (size_t fa = 0; fa < A.size(); ++fa) {
    const Face& a = A[fa];
    const std::vector<int>& a_nodes = faces_a[fa].nodes;
    // The face's plane: origin at its centroid, axes e1, e2 with e1 × e2 = n.
    const Eigen::Vector3d e1 = (a.X.col(1) - a.X.col(0) - a.normal.dot(a.X.col(1) - a.X.col(0)) * a.normal).normalized();
    const Eigen::Vector3d e2 = a.normal.cross(e1);
    auto to_plane = [&](const Eigen::Vector3d& x) {
      const Eigen::Vector3d d = x - a.centroid;
      return Vec2(d.dot(e1), d.dot(e2));
    };
    Eigen::Matrix2Xd PA(2, a.n);
    for (int k = 0; k < a.n; ++k) PA.col(k) = to_plane(a.X.col(k));

    // The basis the dual functions are built on, Ñ = T N (T = I on linear faces; quadratic
    // faces: kQuadraticBasisShift), and the dual basis ψ = A_e Ñ, A_e = D_e M_e⁻¹ from its own
    // integrals (in its plane), D_e = diag(∫ Ñ), M_e = ∫ Ñ Ñᵀ.
    const bool quadratic = a.n > a.corners;
    Eigen::MatrixXd T = Eigen::MatrixXd::Identity(a.n, a.n);
    if (quadratic) {
      for (int k = 0; k < a.corners; ++k) {
        const int m = a.corners + k;  // on the edge from corner k to corner k + 1
        T(k, m) += kQuadraticBasisShift;
        T((k + 1) % a.corners, m) += kQuadraticBasisShift;
        T(m, m) = 1 - 2 * kQuadraticBasisShift;
      }
    }
    Eigen::MatrixXd Me = Eigen::MatrixXd::Zero(a.n, a.n);
    Eigen::VectorXd De = Eigen::VectorXd::Zero(a.n);
    for (const FacePoint& q : face_rule(a.n)) {
      face_shape(a.n, q.xi, q.eta, N, dN);
      const double dA = std::abs((PA * dN.transpose()).determinant()) * q.w;
      const Eigen::VectorXd Nt = T * N;
      Me += Nt * Nt.transpose() * dA;
      De += Nt * dA;
    }
    const Eigen::MatrixXd Ae = De.asDiagonal() * Me.inverse() * T;  // ψ = Ae N
    for (int k = 0; k < a.n; ++k) {
      D[a_nodes[k]] += De(k);
      normal.try_emplace(a_nodes[k], Eigen::Vector3d::Zero()).first->second += De(k) * a.normal;
    }
    if (quadratic) {
      // ∫_e ψ_i N_j dA = (T⁻¹)_ji D_e,i (biorthogonality: ∫_e ψ_i Ñ_l = δ_il D_e,i, N = T⁻¹ Ñ).
      const Eigen::MatrixXd Tinv = T.inverse();
      for (int i = 0; i < a.n; ++i)
        for (int j = 0; j < a.n; ++j)
          if (Tinv(j, i) != 0.0) MA[a_nodes[i]][a_nodes[j]] += Tinv(j, i) * De(i);
    }

    Polygon clip(static_cast<size_t>(a.corners));
    for (int k = 0; k < a.corners; ++k) clip[k] = PA.col(k);
    if (signed_area(clip) < 0) std::reverse(clip.begin(), clip.end());

    Eigen::AlignedBox3d box = a.box;
    box.extend(Eigen::Vector3d(a.box.min().array() - search));
    box.extend(Eigen::Vector3d(a.box.max().array() + search));
    for (int fb : grid.near(box)) {
      const Face& b = B[static_cast<size_t>(fb)];
      if (!(a.normal.dot(b.normal) < 0)) continue;  // not facing A
      if (!b.box.intersects(box)) continue;
      bool close = true;
      for (int k = 0; k < b.n && close; ++k) close = std::abs(a.normal.dot(b.X.col(k) - a.centroid)) <= search;
      if (!close) continue;
      Eigen::Matrix2Xd PB(2, b.n);
      for (int k = 0; k < b.n; ++k) PB.col(k) = to_plane(b.X.col(k));
      Polygon subject(static_cast<size_t>(b.corners));
      for (int k = 0; k < b.corners; ++k) subject[k] = PB.col(k);
      if (signed_area(subject) < 0) std::reverse(subject.begin(), subject.end());
      const Polygon overlap = clip_polygon(subject, clip);
      if (overlap.size() < 3) continue;
      const double area = signed_area(overlap);
      if (!(area > kSliverOverlap * std::abs(signed_area(clip)))) continue;
      const std::vector<int>& b_nodes = faces_b[static_cast<size_t>(fb)].nodes;
      for (int k = 0; k < a.n; ++k) met[a_nodes[k]].insert(fb);
      // Fan triangulation of the convex overlap; 7 points per triangle between linear faces,
      // 16 where a face is quadratic (the integrands' degrees: 4 and 6 on parallelograms).
      const std::span<const TrianglePoint> rule =
          quadratic || b.n > b.corners ? std::span<const TrianglePoint>(collapsed_triangle_rule())
                                       : std::span<const TrianglePoint>(triangle_rule());
      for (size_t t = 1; t + 1 < overlap.size(); ++t) {
        const Vec2 &p0 = overlap[0], &p1 = overlap[t], &p2 = overlap[t + 1];
        const double tri = 0.5 * std::abs((p1 - p0).x() * (p2 - p0).y() - (p2 - p0).x() * (p1 - p0).y());
        for (const TrianglePoint& q : rule) {
          const Vec2 p = q.l0 * p0 + q.l1 * p1 + q.l2 * p2;
          const Vec2 xa = natural_coordinates(PA, p), xb = natural_coordinates(PB, p);
          face_shape(a.n, xa.x(), xa.y(), N, dN);
          const Eigen::VectorXd psi = Ae * N, Nt = T * N;
          face_shape(b.n, xb.x(), xb.y(), NB, dN);
          const double w = q.w * tri;
          for (int i = 0; i < a.n; ++i) {
            covered[a_nodes[i]] += w * Nt(i);
            std::map<int, double>& row = M[a_nodes[i]];
            for (int k = 0; k < b.n; ++k) row[b_nodes[k]] += w * psi(i) * NB(k);
          }
        }
      }
    }
  }

  for (const auto& [node, d] : D) {
    MortarPoint p;
    p.node_a = node;
    p.area = d;
    p.normal = normal[node].normalized();
    Eigen::Vector3d xa = mesh_a.coordinates.col(node);
    if (const auto it = MA.find(node); it != MA.end()) {
      xa.setZero();
      for (const auto& [j, m] : it->second) {
        p.nodes_a.push_back(j);
        p.weights_a.push_back(m / d);
        xa += (m / d) * mesh_a.coordinates.col(j);
      }
    }
    Eigen::Vector3d xb = Eigen::Vector3d::Zero();
    double sum = 0;  // Σ_k Φ_ik
    if (const auto it = M.find(node); it != M.end()) {
      for (const auto& [k, m] : it->second) {
        if (std::abs(m) < kNegligiblePartner * d) continue;
        p.nodes_b.push_back(k);
        p.weights_b.push_back(m / d);
        sum += m / d;
        xb += (m / d) * mesh_b.coordinates.col(k);
      }
    }
    p.coverage = covered.count(node) ? covered[node] / d : 0.0;
    p.gap = std::abs(sum) > 1e-3 ? p.normal.dot(xb / sum - xa)
                                 : std::numeric_limits<double>::quiet_NaN();
    if (const auto it = met.find(node); it != met.end()) p.faces_b.assign(it->second.begin(), it->second.end());
    if (!(p.coverage >= options.full_coverage)) out.partial.push_back(node);
    out.points.push_back(std::move(p));
  }
  return out;
}

MortarCoupling node_to_surface_coupling(const Mesh& mesh_a, std::span<const ElementFace> faces_a,
                                        const Mesh& mesh_b, std::span<const ElementFace> faces_b,
                                        const MortarOptions& options) {
  // The points' areas and normals (and the checks of both surfaces) are mortar's.
  MortarCoupling out = mortar_coupling(mesh_a, faces_a, mesh_b, faces_b, options);
  out.partial.clear();
  std::vector<Face> B;
  for (size_t i = 0; i < faces_b.size(); ++i)
    B.push_back(make_face(mesh_b, faces_b[i], "B", static_cast<int>(i)));
  const double search = out.search_distance;
  const FaceGrid grid(B, search);
  // A projection inside a face within this much of its natural extent (round-off on its edges).
  constexpr double kInside = 1e-9;
  // Weights below this are round-off of a node that lies on B's edge or node: dropped.
  constexpr double kNegligibleWeight = 1e-12;
  Eigen::VectorXd N;
  Eigen::Matrix2Xd dN;
  for (MortarPoint& p : out.points) {
    const Eigen::Vector3d x = mesh_a.coordinates.col(p.node_a);
    const Eigen::Vector3d& n = p.normal;
    Eigen::AlignedBox3d box(x);
    box.extend(Eigen::Vector3d(x.array() - search));
    box.extend(Eigen::Vector3d(x.array() + search));
    int best = -1;
    double best_gap = 0;
    Vec2 best_xi(0, 0);
    for (int fb : grid.near(box)) {
      const Face& b = B[static_cast<size_t>(fb)];
      if (!(n.dot(b.normal) < 0)) continue;  // not facing A
      if (!b.box.intersects(box)) continue;
      // x + g n = X_B N(ξ): Newton in (ξ, η, g) from the face's centre.
      Vec2 xi = b.corners == 3 ? Vec2(1.0 / 3, 1.0 / 3) : Vec2(0, 0);
      double g = n.dot(b.centroid - x);
      const double size = b.box.sizes().maxCoeff();
      bool solved = false;
      for (int it = 0; it < 50; ++it) {
        face_shape(b.n, xi.x(), xi.y(), N, dN);
        const Eigen::Vector3d r = b.X * N - x - g * n;
        if (r.norm() <= kInverseMapTolerance * 10 * size) {
          solved = true;
          break;
        }
        Eigen::Matrix3d J;
        J.leftCols<2>() = b.X * dN.transpose();
        J.col(2) = -n;
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(J);
        if (!lu.isInvertible()) break;
        const Eigen::Vector3d step = lu.solve(r);
        xi -= step.head<2>();
        g -= step(2);
        if (!xi.allFinite() || xi.cwiseAbs().maxCoeff() > 1e3) break;
      }
      if (!solved || !(std::abs(g) <= search)) continue;
      const bool inside = b.corners == 3 ? xi.x() >= -kInside && xi.y() >= -kInside &&
                                               xi.x() + xi.y() <= 1 + kInside
                                         : xi.cwiseAbs().maxCoeff() <= 1 + kInside;
      if (!inside) continue;
      if (best < 0 || std::abs(g) < std::abs(best_gap) - kInside * size) {
        best = fb;
        best_gap = g;
        best_xi = xi;
      }
    }
    p.nodes_a.clear();  // the point is the node itself
    p.weights_a.clear();
    p.nodes_b.clear();
    p.weights_b.clear();
    p.faces_b.clear();
    if (best < 0) {
      p.coverage = 0;
      p.gap = std::numeric_limits<double>::quiet_NaN();
      out.partial.push_back(p.node_a);
      continue;
    }
    const Face& b = B[static_cast<size_t>(best)];
    face_shape(b.n, best_xi.x(), best_xi.y(), N, dN);
    std::map<int, double> weights;
    for (int k = 0; k < b.n; ++k)
      if (std::abs(N(k)) >= kNegligibleWeight) weights[faces_b[static_cast<size_t>(best)].nodes[k]] += N(k);
    for (const auto& [node, w] : weights) {
      p.nodes_b.push_back(node);
      p.weights_b.push_back(w);
    }
    p.coverage = 1;
    p.gap = best_gap;
    p.faces_b.push_back(best);
  }
  return out;
}

}  // namespace stickslip

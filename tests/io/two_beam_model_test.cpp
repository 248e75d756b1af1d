#include "io/two_beam_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include <Eigen/Geometry>

#include "core/errors.h"
#include "io/inp_writer.h"

namespace stickslip {
namespace {

// Coordinates come from Gmsh's transfinite interpolation: exact to a few ulps of 0.35 m.
constexpr double kPositionTolerance = 1e-12;
// Volumes and areas are sums of ~1e3 element terms of ~1e-7 m^3 each, rounding ~1e-16 relative.
constexpr double kRelativeSumTolerance = 1e-12;

using Arrangement = TwoBeamOptions::Arrangement;

Eigen::Vector3d x_of(const Mesh& m, int n) { return m.coordinates.col(n); }

double tet_volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                  const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

// Signed volume of a hexahedron with planar faces from its 8 corners (CalculiX order), by six
// tetrahedra around the diagonal 0-6: exact for the boxes of a structured grid.
double hex_volume(const Mesh& m, int e) {
  auto x = [&](int i) { return x_of(m, m.element_nodes(e)[i]); };
  return tet_volume(x(0), x(1), x(2), x(6)) + tet_volume(x(0), x(2), x(3), x(6)) +
         tet_volume(x(0), x(3), x(7), x(6)) + tet_volume(x(0), x(7), x(4), x(6)) +
         tet_volume(x(0), x(4), x(5), x(6)) + tet_volume(x(0), x(5), x(1), x(6));
}

// The six faces of a hexahedron (corner local numbers, CalculiX).
constexpr int kHexFaces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

struct FaceCount {
  int shared = 0;            // faces used by exactly two elements
  int over_shared = 0;       // faces used by more than two (must be 0)
  double boundary_area = 0;  // total area of faces used by one element
};

// Counts the corner-node faces of the elements of `elements`. A conforming mesh of a solid has
// every interior face shared by exactly two elements with the same 4 nodes, so the faces used
// once make up exactly the outer surface; a hanging interface adds its area twice.
FaceCount count_faces(const Mesh& m, const std::vector<int>& elements) {
  std::map<std::array<int, 4>, std::pair<int, std::array<int, 4>>> faces;
  for (int e : elements) {
    const auto nodes = m.element_nodes(e);
    for (const auto& f : kHexFaces) {
      std::array<int, 4> ordered = {nodes[f[0]], nodes[f[1]], nodes[f[2]], nodes[f[3]]};
      std::array<int, 4> key = ordered;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      ++entry.first;
      entry.second = ordered;
    }
  }
  FaceCount c;
  for (const auto& [key, entry] : faces) {
    if (entry.first == 2) ++c.shared;
    if (entry.first > 2) ++c.over_shared;
    if (entry.first == 1) {
      const auto& q = entry.second;
      // Planar quadrilateral: half the norm of the cross product of its diagonals.
      c.boundary_area +=
          0.5 * (x_of(m, q[2]) - x_of(m, q[0])).cross(x_of(m, q[3]) - x_of(m, q[1])).norm();
    }
  }
  return c;
}

struct Dimensions {
  double L, W, T, e;
};
Dimensions dims(const TwoBeamOptions& o) {
  return {o.beam_length, o.width, o.thickness, o.end_length};
}
double beam_volume(const Dimensions& d) { return d.L * d.W * d.T + d.e * d.W * d.T / 2; }
// Surface of the union of the large box and the end block (they share a W x T/2 face).
double beam_area(const Dimensions& d) {
  return 2 * (d.L * d.W + d.L * d.T + d.W * d.T) + 2 * (d.e * d.W + d.e * d.T / 2 + d.W * d.T / 2) -
         2 * (d.W * d.T / 2);
}

// Checks shared by every variant: ids, sets, volumes, contact pairs, forced nodes.
void check_model(const TwoBeamModel& model, const TwoBeamOptions& o, int nodes_per_beam,
                 int elements_per_beam, int pairs, bool conforming) {
  const Mesh& m = model.mesh;
  const Dimensions d = dims(o);
  const bool butt = o.arrangement == Arrangement::kButt;
  SCOPED_TRACE(butt ? "butt" : "lap");
  ASSERT_NO_THROW(check_mesh(m));
  ASSERT_EQ(m.num_nodes(), 2 * nodes_per_beam);
  ASSERT_EQ(m.num_elements(), 2 * elements_per_beam);
  for (int i = 0; i < m.num_nodes(); ++i) ASSERT_EQ(m.node_ids[i], i + 1);
  for (int e = 0; e < m.num_elements(); ++e) ASSERT_EQ(m.element_ids[e], e + 1);
  for (ElementType t : m.element_types) ASSERT_EQ(t, o.element_type);

  const auto& beam1 = m.element_sets.at("BEAM1");
  const auto& beam2 = m.element_sets.at("BEAM2");
  ASSERT_EQ(static_cast<int>(beam1.size()), elements_per_beam);
  ASSERT_EQ(static_cast<int>(beam2.size()), elements_per_beam);
  EXPECT_EQ(beam1.front(), 0);
  EXPECT_EQ(beam2.front(), elements_per_beam);
  EXPECT_EQ(static_cast<int>(m.node_sets.at("BEAM1").size()), nodes_per_beam);
  EXPECT_EQ(m.node_sets.at("BEAM2").front(), nodes_per_beam);
  // Elements of each beam use only that beam's nodes.
  for (int e = 0; e < m.num_elements(); ++e) {
    const bool second = e >= elements_per_beam;
    for (int n : m.element_nodes(e)) ASSERT_EQ(n >= nodes_per_beam, second);
  }

  // Volumes: every element positive, each beam's total = the analytic volume.
  for (const auto* set : {&beam1, &beam2}) {
    double volume = 0.0;
    for (int e : *set) {
      const double v = hex_volume(m, e);
      ASSERT_GT(v, 0.0) << "inverted element " << m.element_ids[e];
      volume += v;
    }
    EXPECT_NEAR(volume, beam_volume(d), kRelativeSumTolerance * beam_volume(d));
  }

  // Face counting: conforming = boundary faces cover exactly the outer surface.
  for (const auto* set : {&beam1, &beam2}) {
    const FaceCount c = count_faces(m, *set);
    EXPECT_EQ(c.over_shared, 0);
    const double expected =
        beam_area(d) + (conforming ? 0.0 : 2 * (d.W * d.T / 2));  // hanging interface twice
    EXPECT_NEAR(c.boundary_area, expected, kRelativeSumTolerance * expected);
  }

  // Clamps: the faces x = 0 and the far end of beam 2, complete.
  const double x_far = butt ? 2 * d.L + 2 * d.e : 2 * d.L + d.e;
  int on_x0 = 0, on_far = 0;
  for (int n = 0; n < m.num_nodes(); ++n) {
    if (std::abs(m.coordinates(0, n)) < kPositionTolerance) ++on_x0;
    if (std::abs(m.coordinates(0, n) - x_far) < kPositionTolerance) ++on_far;
  }
  const auto& clamp1 = m.node_sets.at("CLAMP1");
  const auto& clamp2 = m.node_sets.at("CLAMP2");
  EXPECT_EQ(static_cast<int>(clamp1.size()), on_x0);
  EXPECT_EQ(static_cast<int>(clamp2.size()), on_far);
  EXPECT_GT(on_x0, 3);
  for (int n : clamp1) EXPECT_NEAR(m.coordinates(0, n), 0.0, kPositionTolerance);
  for (int n : clamp2) EXPECT_NEAR(m.coordinates(0, n), x_far, kPositionTolerance);
  EXPECT_LT(clamp1.back(), nodes_per_beam);
  EXPECT_GE(clamp2.front(), nodes_per_beam);

  // Contact: pairs coincident, on the contact face of the right beams, covering both sets.
  ASSERT_EQ(static_cast<int>(model.contact_pairs.size()), pairs);
  const Eigen::Vector3d normal = butt ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ();
  EXPECT_EQ(model.contact_normal, normal);
  std::vector<int> side1, side2;
  for (const auto& [a, b] : model.contact_pairs) {
    EXPECT_LT(a, nodes_per_beam);
    EXPECT_GE(b, nodes_per_beam);
    EXPECT_LT((x_of(m, a) - x_of(m, b)).norm(), kPositionTolerance);
    const Eigen::Vector3d x = x_of(m, a);
    if (butt) {
      EXPECT_NEAR(x.x(), d.L + d.e, kPositionTolerance);
      EXPECT_LE(x.z(), d.T / 2 + kPositionTolerance);
    } else {
      EXPECT_NEAR(x.z(), d.T / 2, kPositionTolerance);
      EXPECT_GE(x.x(), d.L - kPositionTolerance);
      EXPECT_LE(x.x(), d.L + d.e + kPositionTolerance);
    }
    side1.push_back(a);
    side2.push_back(b);
  }
  std::sort(side1.begin(), side1.end());
  std::sort(side2.begin(), side2.end());
  EXPECT_EQ(side1, m.node_sets.at("CONTACT1"));
  EXPECT_EQ(side2, m.node_sets.at("CONTACT2"));
  EXPECT_TRUE(std::adjacent_find(side2.begin(), side2.end()) == side2.end());
  // The normal points out of beam 1: an element of beam 1 with a whole face on the contact face
  // lies on the −n side of it (and one of beam 2 on the +n side).
  for (const auto& [set, sign, side] : {std::tuple{&beam1, -1.0, &side1}, {&beam2, 1.0, &side2}}) {
    int touching = 0;
    for (int e : *set) {
      const auto nodes = m.element_nodes(e);
      for (const auto& f : kHexFaces) {
        bool on_face = true;
        for (int k : f)
          on_face = on_face && std::binary_search(side->begin(), side->end(), nodes[k]);
        if (!on_face) continue;
        ++touching;
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (int k : nodes) centroid += x_of(m, k);
        centroid /= static_cast<double>(nodes.size());
        EXPECT_GT(sign * normal.dot(centroid - x_of(m, nodes[f[0]])), 0.0);
      }
    }
    EXPECT_GT(touching, 0);
  }

  // Forced nodes: (L, 0, T) on beam 1 and its mirror on beam 2.
  const Eigen::Vector3d f2 =
      butt ? Eigen::Vector3d(d.L + 2 * d.e, 0, d.T) : Eigen::Vector3d(d.L + d.e, 0, 0);
  EXPECT_LT((x_of(m, model.force_node_1) - Eigen::Vector3d(d.L, 0, d.T)).norm(),
            kPositionTolerance);
  EXPECT_LT((x_of(m, model.force_node_2) - f2).norm(), kPositionTolerance);
  EXPECT_LT(model.force_node_1, nodes_per_beam);
  EXPECT_GE(model.force_node_2, nodes_per_beam);
  EXPECT_EQ(m.node_sets.at("FORCE1"), std::vector<int>{model.force_node_1});
  EXPECT_EQ(m.node_sets.at("FORCE2"), std::vector<int>{model.force_node_2});
  EXPECT_FALSE(std::binary_search(side1.begin(), side1.end(), model.force_node_1));
}

int linear_nodes(const TwoBeamOptions& o) {
  const auto& b = o.box;
  const auto& e = o.end_block;
  return (b.x + 1) * (b.y + 1) * (b.z + 1) + e.x * (b.y + 1) * (e.z + 1);
}
int elements(const TwoBeamOptions& o) {
  return o.box.x * o.box.y * o.box.z + o.end_block.x * o.box.y * o.end_block.z;
}

TEST(TwoBeamModel, ButtDefaultIsConformingWithThirtyContactPairs) {
  const TwoBeamOptions o;
  const TwoBeamModel model = make_two_beam_model(o);
  check_model(model, o, linear_nodes(o), elements(o), (o.box.y + 1) * (o.end_block.z + 1), true);
  EXPECT_EQ(model.contact_pairs.size(), 30u);  // 6 x 5, as in the thesis
}

TEST(TwoBeamModel, LapDefaultTouchesOnTheOverlapFace) {
  TwoBeamOptions o;
  o.arrangement = Arrangement::kLap;
  const TwoBeamModel model = make_two_beam_model(o);
  check_model(model, o, linear_nodes(o), elements(o), (o.end_block.x + 1) * (o.box.y + 1), true);
  // The beams do not interpenetrate: no element centroid of beam 2 inside beam 1's solid.
  const Mesh& m = model.mesh;
  const Dimensions d = dims(o);
  for (int e : m.element_sets.at("BEAM2")) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int n : m.element_nodes(e)) c += x_of(m, n);
    c /= 8.0;
    const bool in_box = c.x() < d.L;
    const bool in_end = c.x() < d.L + d.e && c.z() < d.T / 2;
    EXPECT_FALSE(in_box || in_end);
  }
}

TEST(TwoBeamModel, NonDefaultCountsFollowTheClosedForms) {
  TwoBeamOptions o;
  o.beam_length = 0.3;
  o.width = 0.04;
  o.thickness = 0.02;
  o.end_length = 0.03;
  o.box = {9, 3, 5};  // 2 layers below mid-thickness, 3 above
  o.end_block = {4, 3, 2};
  o.element_type = ElementType::kC3D8;
  for (Arrangement a : {Arrangement::kButt, Arrangement::kLap}) {
    o.arrangement = a;
    const int pairs = a == Arrangement::kButt ? (o.box.y + 1) * (o.end_block.z + 1)
                                              : (o.end_block.x + 1) * (o.box.y + 1);
    check_model(make_two_beam_model(o), o, linear_nodes(o), elements(o), pairs, true);
  }
}

// Beam 2 with its own divisions (a non-matching joint): each beam's counts are the closed forms of
// its own divisions, beam 2's contact face has (by + 1)(ez + 1) nodes of its own, and no node
// pairs are made.
TEST(TwoBeamModel, BeamTwoMeshedFinerHasItsOwnCountsAndNoPairs) {
  TwoBeamOptions o;
  o.element_type = ElementType::kC3D8;
  o.box = {8, 2, 4};
  o.end_block = {2, 2, 2};
  TwoBeamOptions o2 = o;
  o2.box = {12, 3, 6};
  o2.end_block = {3, 3, 3};
  o.beam2_box = o2.box;
  o.beam2_end_block = o2.end_block;
  const TwoBeamModel model = make_two_beam_model(o);
  const Mesh& m = model.mesh;
  EXPECT_EQ(m.node_sets.at("BEAM1").size(), static_cast<size_t>(linear_nodes(o)));
  EXPECT_EQ(m.node_sets.at("BEAM2").size(), static_cast<size_t>(linear_nodes(o2)));
  EXPECT_EQ(m.element_sets.at("BEAM2").size(), static_cast<size_t>(elements(o2)));
  EXPECT_EQ(m.node_sets.at("CONTACT1").size(), 3u * 3u);
  EXPECT_EQ(m.node_sets.at("CONTACT2").size(), 4u * 4u);
  for (int n : m.node_sets.at("CONTACT2")) EXPECT_NEAR(x_of(m, n).x(), 0.3, 1e-12);
  EXPECT_TRUE(model.contact_pairs.empty());
  // Beam 2's rules are checked as beam 1's, under its own names.
  o.beam2_end_block = BlockDivisions{3, 2, 3};
  try {
    validate(o);
    ADD_FAILURE() << "beam2_end_block.y = 2 accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("beam2_end_block.y = 2"), std::string::npos) << e.what();
  }
}

TEST(TwoBeamModel, ThesisCoarseHas240NodesAnd115ElementsPerBeam) {
  TwoBeamOptions o;
  o.thesis_coarse = true;
  for (Arrangement a : {Arrangement::kButt, Arrangement::kLap}) {
    o.arrangement = a;
    // 7x5x1 box (8*6*2 = 96 nodes) + 4x5x4 block (5*6*5 = 150) − 6 shared edge nodes.
    check_model(make_two_beam_model(o), o, 240, 115, 30, /*conforming=*/false);
  }
}

TEST(TwoBeamModel, QuadraticHexahedraHaveMidNodesOnTheirEdges) {
  TwoBeamOptions o;
  o.box = {6, 2, 4};
  o.end_block = {2, 2, 2};
  o.element_type = ElementType::kC3D20R;
  const TwoBeamModel model = make_two_beam_model(o);
  // Serendipity nodes: grid vertices + one per grid edge, box and block sharing a 2 x 2 face.
  auto grid = [](int a, int b, int c) {
    return (a + 1) * (b + 1) * (c + 1) + a * (b + 1) * (c + 1) + (a + 1) * b * (c + 1) +
           (a + 1) * (b + 1) * c;
  };
  const int face = (o.box.y + 1) * (o.end_block.z + 1) + o.box.y * (o.end_block.z + 1) +
                   (o.box.y + 1) * o.end_block.z;
  const int nodes =
      grid(o.box.x, o.box.y, o.box.z) + grid(o.end_block.x, o.box.y, o.end_block.z) - face;
  // Butt contact face: the 2 x 2 face of the block, serendipity: 9 − 1 (no centre) nodes.
  check_model(model, o, nodes, elements(o), face, true);
  const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                            {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const Mesh& m = model.mesh;
  for (int e = 0; e < m.num_elements(); ++e) {
    const auto n = m.element_nodes(e);
    for (int k = 0; k < 12; ++k) {
      const Eigen::Vector3d mid = 0.5 * (x_of(m, n[edges[k][0]]) + x_of(m, n[edges[k][1]]));
      ASSERT_LT((x_of(m, n[8 + k]) - mid).norm(), kPositionTolerance);
    }
  }
}

// CalculiX prints volumes with 7 significant digits.
constexpr double kCalculixPrintTolerance = 5e-7;

// CalculiX (an external program) reads the deck written by write_inp for the generated model,
// runs a static step (both beams clamped, the thesis's forces on FORCE1/FORCE2) and prints the
// total volume of each beam from its own element formulation: it must equal the analytic
// volume, which fails if the node order, the continuation lines or the sets were wrong
// (CalculiX stops on a negative Jacobian).
TEST(TwoBeamModel, CalculixReadsTheWrittenDeckAndFindsTheAnalyticVolume) {
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("stickslip_two_beam_ccx_" + std::to_string(::getpid())))
                              .string();
  std::filesystem::create_directories(dir);
  for (ElementType type : {ElementType::kC3D8I, ElementType::kC3D20R}) {
    for (Arrangement arrangement : {Arrangement::kButt, Arrangement::kLap}) {
      TwoBeamOptions o;
      o.box = {6, 2, 4};
      o.end_block = {2, 2, 2};
      o.element_type = type;
      o.arrangement = arrangement;
      const TwoBeamModel model = make_two_beam_model(o);
      {
        std::ofstream deck(dir + "/beams.inp");
        write_inp(deck, model.mesh);
        deck << "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n*DENSITY\n7800\n"
             << "*SOLID SECTION, ELSET=BEAM1, MATERIAL=STEEL\n"
             << "*SOLID SECTION, ELSET=BEAM2, MATERIAL=STEEL\n"
             << "*BOUNDARY\nCLAMP1, 1, 3\nCLAMP2, 1, 3\n"
             << "*STEP\n*STATIC\n*CLOAD\nFORCE1, 3, 50.\nFORCE2, 3, -50.\n"
             << "*EL PRINT, ELSET=BEAM1, TOTALS=ONLY\nEVOL\n"
             << "*EL PRINT, ELSET=BEAM2, TOTALS=ONLY\nEVOL\n*END STEP\n";
      }
      std::filesystem::remove(dir + "/beams.dat");
      const std::string command =
          "cd " + dir + " && OMP_NUM_THREADS=1 ccx -i beams > beams.log 2>&1";
      ASSERT_EQ(std::system(command.c_str()), 0) << "ccx failed, see " << dir << "/beams.log";
      std::ifstream dat(dir + "/beams.dat");
      std::stringstream text;
      text << dat.rdbuf();
      const std::string s = text.str();
      // "total volume for set BEAM1 and time  0.1000000E+01\n\n        4.125000E-04"
      int found = 0;
      const double expected = beam_volume(dims(o));
      for (const std::string set : {"BEAM1", "BEAM2"}) {
        const std::string key = "total volume for set " + set + " and time";
        const size_t at = s.find(key);
        if (at == std::string::npos) continue;
        std::istringstream numbers(s.substr(at + key.size()));
        double time = 0.0, volume = 0.0;
        numbers >> time >> volume;
        EXPECT_NEAR(volume, expected, kCalculixPrintTolerance * expected)
            << element_type_name(type) << " " << set;
        ++found;
      }
      EXPECT_EQ(found, 2) << s.substr(0, 400);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(TwoBeamModel, ValidateNamesTheFieldAndTheRule) {
  auto message = [](const TwoBeamOptions& o) {
    try {
      validate(o);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  TwoBeamOptions o;
  EXPECT_EQ(message(o), "");
  o.end_block.y = 4;
  EXPECT_NE(message(o).find("end_block.y = 4"), std::string::npos) << message(o);
  o = {};
  o.end_block.z = 8;
  EXPECT_NE(message(o).find("end_block.z = 8"), std::string::npos);
  o = {};
  o.thickness = -0.03;
  EXPECT_NE(message(o).find("thickness = -0.03"), std::string::npos);
  o = {};
  o.box.x = 0;
  EXPECT_NE(message(o).find("box.x = 0"), std::string::npos);
  o = {};
  o.element_type = ElementType::kC3D10;
  EXPECT_NE(message(o).find("element_type = C3D10"), std::string::npos);
  EXPECT_THROW(make_two_beam_model(o), InvalidInput);
}

}  // namespace
}  // namespace stickslip

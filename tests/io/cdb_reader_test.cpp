// The ANSYS CDB reader on files ANSYS wrote (tests/data/ansys, see its README) and on small
// hand-made variants for each rule. Expected values are read off the files' text by eye (node
// coordinates, component ranges, element node lists) or are geometric facts (mid-side nodes at
// edge midpoints), not the reader's output.
#include "io/cdb_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "core/errors.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/ansys/";

std::vector<std::string> file_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string l;
  while (std::getline(in, l)) lines.push_back(l);
  return lines;
}

// The file with lines [first, last] (1-based) removed, as a stream.
std::istringstream without_lines(const std::string& path, std::vector<std::pair<int, int>> cut) {
  const std::vector<std::string> lines = file_lines(path);
  std::string text;
  for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
    bool drop = false;
    for (const auto& [a, b] : cut) drop = drop || (i + 1 >= a && i + 1 <= b);
    if (!drop) text += lines[i] + "\n";
  }
  return std::istringstream(text);
}

std::vector<int> ids_of(const Mesh& m, const std::vector<int>& nodes) {
  std::vector<int> ids;
  for (int n : nodes) ids.push_back(m.node_ids[n]);
  std::sort(ids.begin(), ids.end());
  return ids;
}

// The InvalidInput a read throws, for checking its line and message.
template <typename F>
InvalidInput error_of(F&& read) {
  try {
    read();
  } catch (const InvalidInput& e) {
    return e;
  }
  ADD_FAILURE() << "no InvalidInput thrown";
  return InvalidInput("none");
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CdbReader, ReadsHexBeamNodesElementsComponentsAndMaterial) {
  std::vector<std::string> warnings;
  std::map<int, DeckMaterial> materials;
  const Mesh m = read_cdb(kDir + "HexBeam.cdb", &warnings, &materials);
  ASSERT_EQ(m.num_nodes(), 321);
  ASSERT_EQ(m.num_elements(), 40);
  for (ElementType t : m.element_types) EXPECT_EQ(t, ElementType::kC3D20R);  // no KEYOPT(2)
  const auto index = node_index_by_id(m);
  EXPECT_EQ(m.coordinates.col(index.at(1)), Eigen::Vector3d(0, 0, 0));  // short line
  EXPECT_EQ(m.coordinates.col(index.at(6)), Eigen::Vector3d(1, 1, 0));  // z left out
  EXPECT_EQ(m.coordinates.col(index.at(22)), Eigen::Vector3d(0, 0, 5));
  EXPECT_EQ(m.coordinates.col(index.at(321)), Eigen::Vector3d(0.75, 0.5, 4.5));
  // Element 1 (lines 361-362): fields 12-19 of the first line, then the 12 of the second.
  const auto nodes = m.element_nodes(0);
  EXPECT_EQ(m.element_ids[0], 1);
  const std::vector<int> expected{1,  4,  19, 15,  63,  91,  286, 240, 3,   18,
                                  17, 16, 81, 276, 267, 258, 62,  90,  285, 239};
  ASSERT_EQ(nodes.size(), expected.size());
  for (size_t a = 0; a < nodes.size(); ++a) EXPECT_EQ(m.node_ids[nodes[a]], expected[a]) << a;
  // Components with ranges: ECOMP1 = 17..18, 21..40; NCOMP2 starts 1..21, 43..47, ..., 230, ...
  std::vector<int> ecomp1;
  for (int e : m.element_sets.at("ECOMP1")) ecomp1.push_back(m.element_ids[e]);
  std::sort(ecomp1.begin(), ecomp1.end());
  std::vector<int> expected_ecomp1{17, 18};
  for (int i = 21; i <= 40; ++i) expected_ecomp1.push_back(i);
  EXPECT_EQ(ecomp1, expected_ecomp1);
  const std::vector<int> ncomp2 = ids_of(m, m.node_sets.at("NCOMP2"));
  for (int id : {1, 21, 43, 47, 230, 313, 316}) {
    EXPECT_TRUE(std::binary_search(ncomp2.begin(), ncomp2.end(), id)) << id;
  }
  for (int id : {22, 42, 48, 229, 231, 317}) {
    EXPECT_FALSE(std::binary_search(ncomp2.begin(), ncomp2.end(), id)) << id;
  }
  EXPECT_EQ(m.node_sets.count("NODE_SELECTION"), 1u);
  EXPECT_EQ(m.element_sets.at("ECOMP2").size(), 22u);  // 1..20, 23..24
  ASSERT_EQ(materials.count(1), 1u);
  EXPECT_EQ(materials.at(1).youngs_modulus, 7e10);
  EXPECT_EQ(materials.at(1).poisson_ratio, 0.35);
  EXPECT_EQ(materials.at(1).density, 2700.0);
  EXPECT_TRUE(contains(materials.at(1).origin, "HexBeam.cdb:465"));
  // Unused commands are named with their line, grouped by reason.
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(contains(all, "ANTYPE (line 5)")) << all;
  EXPECT_TRUE(contains(all, "ACEL (line 475)")) << all;
  EXPECT_TRUE(contains(all, "analyses come from the case file")) << all;
}

TEST(CdbReader, MapsTheTetrahedralWedgeAndPyramidSolid186) {
  const std::string path = kDir + "all_solid_cells.cdb";
  // Records: hexahedron 2170 (lines 62-63), wedge 4488 (64-65), pyramid 4643 (66-67),
  // tetrahedron 4644 (68-69).
  std::vector<std::string> warnings;
  const Mesh all = read_cdb(path, &warnings);
  ASSERT_EQ(all.num_elements(), 4);
  ASSERT_EQ(all.element_types[2], ElementType::kC3D13);
  // "941 939 919 921 13984 x4 | 940 934 920 935 13984 x4 14040 14003 14371 14038": corners
  // I J K L M, base mid-side nodes Q R S T, lateral Y Z A B (U V W X = M).
  const std::vector<int> pyramid_ids{941, 939, 919,   921,   13984, 940,  934,
                                     920, 935, 14040, 14003, 14371, 14038};
  const auto pyramid = all.element_nodes(2);
  for (size_t a = 0; a < 13; ++a) EXPECT_EQ(all.node_ids[pyramid[a]], pyramid_ids[a]) << a;
  // C3D13's mid-side nodes 6..13 near the midpoints of 1-2, 2-3, 3-4, 4-1, 1-5, 2-5, 3-5, 4-5 (the
  // file's elements lie on a curved surface: within 2 % of the edge length, as the wedge's).
  const int pyramid_edges[8][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 4}, {1, 4}, {2, 4}, {3, 4}};
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d p = all.coordinates.col(pyramid[pyramid_edges[k][0]]);
    const Eigen::Vector3d q = all.coordinates.col(pyramid[pyramid_edges[k][1]]);
    EXPECT_LT((all.coordinates.col(pyramid[5 + k]) - 0.5 * (p + q)).norm(), 0.02 * (p - q).norm())
        << "mid-side node " << 6 + k;
  }
  std::string all_warnings;
  for (const std::string& w : warnings) all_warnings += w + "\n";
  EXPECT_TRUE(contains(all_warnings, "pyramid shape (first on line 66) read as C3D13"))
      << all_warnings;
  // A pyramid whose top mid-side nodes U V W X are not all its apex is no ANSYS shape.
  std::vector<std::string> lines = file_lines(path);
  const size_t at = lines[66].find("13984");
  ASSERT_NE(at, std::string::npos);
  lines[66].replace(at, 5, "13983");
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  std::istringstream bad(text);
  const InvalidInput e = error_of([&] { read_cdb(bad, "cells.cdb"); });
  EXPECT_EQ(e.where().line, 66);
  EXPECT_TRUE(contains(e.message(), "element 4643")) << e.message();
  EXPECT_TRUE(contains(e.message(), "U V W X")) << e.message();

  std::istringstream no_pyramid = without_lines(path, {{66, 67}});
  const Mesh w = read_cdb(no_pyramid, "cells.cdb");
  ASSERT_EQ(w.num_elements(), 3);
  ASSERT_EQ(w.element_types[1], ElementType::kC3D15);
  const auto wedge = w.element_nodes(1);
  // "5692 5649 5697 5697 13153 13148 13154 13154": corners I J K, M N O (K = L, O = P).
  const std::vector<int> corners{5692, 5649, 5697, 13153, 13148, 13154};
  for (size_t a = 0; a < 6; ++a) EXPECT_EQ(w.node_ids[wedge[a]], corners[a]) << a;
  // C3D15's mid-side nodes 7..15 near the midpoints of 1-2, 2-3, 3-1, 4-5, 5-6, 6-4, 1-4, 2-5,
  // 3-6: the file's wedge lies on a curved surface, its bottom mid-side nodes off the chord
  // midpoints by up to 0.7 % of the edge length (the midpoint of any other edge is > 40 % away).
  const int wedge_edges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5},
                                 {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  for (int k = 0; k < 9; ++k) {
    const Eigen::Vector3d mid = 0.5 * (w.coordinates.col(wedge[wedge_edges[k][0]]) +
                                       w.coordinates.col(wedge[wedge_edges[k][1]]));
    const double length = (w.coordinates.col(wedge[wedge_edges[k][0]]) -
                           w.coordinates.col(wedge[wedge_edges[k][1]]))
                              .norm();
    EXPECT_LT((w.coordinates.col(wedge[6 + k]) - mid).norm(), 0.02 * length)
        << "mid-side node " << 7 + k;
  }

  std::istringstream hex_and_tet = without_lines(path, {{64, 67}});
  const Mesh m = read_cdb(hex_and_tet, "cells.cdb");
  ASSERT_EQ(m.num_elements(), 2);
  EXPECT_EQ(m.element_types[0], ElementType::kC3D20R);
  ASSERT_EQ(m.element_types[1], ElementType::kC3D10);
  const auto tet = m.element_nodes(1);
  // Corners I J K M of "13983 921 919 919 13984 13984 13984 13984".
  EXPECT_EQ(m.node_ids[tet[0]], 13983);
  EXPECT_EQ(m.node_ids[tet[1]], 921);
  EXPECT_EQ(m.node_ids[tet[2]], 919);
  EXPECT_EQ(m.node_ids[tet[3]], 13984);
  // C3D10's mid-side nodes 5..10 lie at the midpoints of edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.
  const int edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector3d mid =
        0.5 * (m.coordinates.col(tet[edges[k][0]]) + m.coordinates.col(tet[edges[k][1]]));
    EXPECT_LT((m.coordinates.col(tet[4 + k]) - mid).norm(), 1e-9) << "mid-side node " << 5 + k;
  }
}

TEST(CdbReader, RefusesSolid187WithoutItsMidSideNodes) {
  const InvalidInput e = error_of([&] { read_cdb(kDir + "TetBeam.cdb"); });
  EXPECT_EQ(e.where().line, 1081);
  EXPECT_TRUE(contains(e.message(), "element 1 ")) << e.message();
  EXPECT_TRUE(contains(e.message(), "SOLID187")) << e.message();
}

TEST(CdbReader, ReadsTheDegenerateSolid185WedgesOfARealSectorAsC3D6) {
  // sector.cdb: 105 SOLID185 of which 4 have "K = L, O = P" (elements 246, 247, ... on their
  // EBLOCK lines): the 4 records whose 3rd and 4th, 7th and 8th nodes repeat.
  std::vector<std::string> warnings;
  const Mesh m = read_cdb(kDir + "sector.cdb", &warnings);
  ASSERT_EQ(m.num_elements(), 105);
  int wedges = 0;
  for (int e = 0; e < m.num_elements(); ++e) {
    const ElementType t = m.element_types[e];
    ASSERT_TRUE(t == ElementType::kC3D8B || t == ElementType::kC3D6) << element_type_name(t);
    if (t != ElementType::kC3D6) continue;
    ++wedges;
    // Six distinct corners that span a volume (the reader checked det J > 0 already).
    const auto n = m.element_nodes(e);
    EXPECT_EQ(std::set<int>(n.begin(), n.end()).size(), 6u);
  }
  EXPECT_EQ(wedges, 4);
  // Element 246: "112 114 174 174 610 606 677 677" -> C3D6 112 114 174 610 606 677.
  const auto it = std::find(m.element_ids.begin(), m.element_ids.end(), 246);
  ASSERT_NE(it, m.element_ids.end());
  const auto n246 = m.element_nodes(static_cast<int>(it - m.element_ids.begin()));
  EXPECT_EQ(ids_of(m, std::vector<int>(n246.begin(), n246.end())),
            (std::vector<int>{112, 114, 174, 606, 610, 677}));
  std::string all;
  for (const std::string& x : warnings) all += x + "\n";
  EXPECT_TRUE(contains(all, "4 degenerate SOLID185/186 element(s) of wedge shape")) << all;
}

TEST(CdbReader, Solid185IsBbarAndEveryDLineIsADofLevelSupport) {
  const std::string path = kDir + "one_solid185_point_load.cdb";
  // D on nodes 1-4 in UX, UY, UZ (lines 66-77), on nodes 5-8 in UY, UZ only (lines 78-85).
  const Mesh full = read_cdb(path);
  ASSERT_EQ(full.boundaries.size(), 20u);
  EXPECT_EQ(ids_of(full, full.node_sets.at("D_ALL")), (std::vector<int>{1, 2, 3, 4}));
  for (size_t k = 0; k < full.boundaries.size(); ++k) {
    const MeshBoundary& b = full.boundaries[k];
    const int line = 66 + static_cast<int>(k);
    EXPECT_EQ(b.origin, path + ":" + std::to_string(line));
    ASSERT_EQ(b.nodes.size(), 1u);
    EXPECT_TRUE(b.unsupported.empty());
    // Lines 66-77: node (k / 3) + 1, UX UY UZ in turn; 78-85: node 5 + (k - 12) / 2, UY UZ.
    const int node = k < 12 ? static_cast<int>(k / 3) + 1 : 5 + static_cast<int>(k - 12) / 2;
    const int dof = k < 12 ? static_cast<int>(k % 3) : 1 + static_cast<int>(k % 2);
    EXPECT_EQ(full.node_ids[b.nodes[0]], node) << "line " << line;
    EXPECT_EQ(b.first, dof) << "line " << line;
    EXPECT_EQ(b.last, dof) << "line " << line;
  }

  std::istringstream clamped_only = without_lines(path, {{78, 85}});
  std::vector<std::string> warnings;
  std::map<int, DeckMaterial> materials;
  const Mesh m = read_cdb(clamped_only, "one.cdb", &warnings, &materials);
  ASSERT_EQ(m.num_elements(), 1);
  EXPECT_EQ(m.element_types[0], ElementType::kC3D8B);
  const std::vector<int> order{2, 1, 3, 4, 7, 8, 6, 5};
  const auto nodes = m.element_nodes(0);
  for (size_t a = 0; a < 8; ++a) EXPECT_EQ(m.node_ids[nodes[a]], order[a]);
  EXPECT_EQ(ids_of(m, m.node_sets.at("D_ALL")), (std::vector<int>{1, 2, 3, 4}));
  // MPDATA in the UNBL form.
  EXPECT_EQ(materials.at(1).youngs_modulus, 2.1e11);
  EXPECT_EQ(materials.at(1).poisson_ratio, 0.3);
  EXPECT_EQ(materials.at(1).density, 7800.0);
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(contains(all, "MPDATA ALPD (line 39)")) << all;
  EXPECT_TRUE(contains(all, "F (line")) << all;
  EXPECT_TRUE(contains(all, "D_ALL")) << all;
}

TEST(CdbReader, SkipsLoadBlocksItDoesNotRead) {
  // The pressure file: an SFEBLOCK with its own format and data lines, then "SFE,end,...".
  std::vector<std::string> warnings;
  const std::string path = kDir + "one_solid185_pressure.cdb";
  std::istringstream clamped_only = without_lines(path, {{76, 79}});  // SFEBLOCK: 80 -> 76
  const Mesh m = read_cdb(clamped_only, "pressure.cdb", &warnings);
  EXPECT_EQ(m.num_elements(), 1);
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(contains(all, "SFEBLOCK (line 76)")) << all;
}

// A small hand-made file in CDWRITE's layout: one SOLID185 or SOLID186 cube.
std::string cube_file(const std::string& et_lines, const std::string& extra = "") {
  std::string s =
      "/PREP7\n" + et_lines +
      "NBLOCK,6,SOLID,8,8\n(3i9,6e21.13e3)\n"
      "        1        0        0 0.0000000000000E+000\n"
      "        2        0        0 1.0000000000000E+000\n"
      "        3        0        0 1.0000000000000E+000 1.0000000000000E+000\n"
      "        4        0        0 0.0000000000000E+000 1.0000000000000E+000\n"
      "        5        0        0 0.0000000000000E+000 0.0000000000000E+000 "
      "1.0000000000000E+000\n"
      "        6        0        0 1.0000000000000E+000 0.0000000000000E+000 "
      "1.0000000000000E+000\n"
      "        7        0        0 1.0000000000000E+000 1.0000000000000E+000 "
      "1.0000000000000E+000\n"
      "        8        0        0 0.0000000000000E+000 1.0000000000000E+000 "
      "1.0000000000000E+000\n"
      "N,R5.3,LOC,       -1,\n"
      "EBLOCK,19,SOLID,1,1\n(19i9)\n"
      "        1        1        1        1        0        0        0        0        8"
      "        0        7        1        2        3        4        5        6        7"
      "        8\n"
      "       -1\n" +
      extra;
  return s;
}

Mesh read_text(const std::string& text, std::vector<std::string>* warnings = nullptr) {
  std::istringstream in(text);
  return read_cdb(in, "cube.cdb", warnings);
}

TEST(CdbReader, KeyoptTwoOfSolid185ChoosesOrRefuses) {
  EXPECT_EQ(read_text(cube_file("ET,1,185\n")).element_types[0], ElementType::kC3D8B);
  EXPECT_EQ(read_text(cube_file("ET,1,SOLID185\nKEYOPT,1,2,0\n")).element_types[0],
            ElementType::kC3D8B);
  // KEYOPT(2) = 3, simplified enhanced strain (9 modes against shear locking): C3D8I.
  EXPECT_EQ(read_text(cube_file("ET,1,185\nKEYOPT,1,2,3\n")).element_types[0],
            ElementType::kC3D8I);
  for (int k2 : {1, 2}) {
    const InvalidInput e = error_of(
        [&] { read_text(cube_file("ET,1,185\nKEYOPT,1,2," + std::to_string(k2) + "\n")); });
    EXPECT_TRUE(contains(e.message(), "element 7")) << e.message();
    EXPECT_TRUE(contains(e.message(), "SOLID185")) << e.message();
    EXPECT_TRUE(contains(e.message(), "KEYOPT(2) = " + std::to_string(k2))) << e.message();
    EXPECT_EQ(e.where().line, 17);  // the element record
  }
  // KEYOPT also from the ET command's KOP fields: ET,1,185,,1 is KEYOPT(2) = 1.
  EXPECT_TRUE(
      contains(error_of([&] { read_text(cube_file("ET,1,185,,1\n")); }).message(), "hourglass"));
  EXPECT_TRUE(contains(
      error_of([&] { read_text(cube_file("ET,1,185\nKEYOPT,1,6,1\n")); }).message(), "mixed u-P"));
  EXPECT_TRUE(
      contains(error_of([&] { read_text(cube_file("ET,1,45\n")); }).message(), "not supported"));
  EXPECT_TRUE(contains(error_of([&] { read_text(cube_file("")); }).message(), "no ET"));
}

TEST(CdbReader, Solid185PyramidShapeIsC3D5WithAWarning) {
  const std::string cube = cube_file("ET,1,185\n");
  const std::string hexahedron = "        5        6        7        8\n";
  const size_t at = cube.find(hexahedron);
  ASSERT_NE(at, std::string::npos);
  const std::string text = cube.substr(0, at) + "        5        5        5        5\n" +
                           cube.substr(at + hexahedron.size());
  std::vector<std::string> warnings;
  const Mesh m = read_text(text, &warnings);
  ASSERT_EQ(m.num_elements(), 1);
  EXPECT_EQ(m.element_types[0], ElementType::kC3D5);
  const auto nodes = m.element_nodes(0);
  for (int a = 0; a < 5; ++a) EXPECT_EQ(m.node_ids[nodes[a]], a + 1);  // I J K L M
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  EXPECT_TRUE(contains(all, "pyramid shape (first on line 16) read as C3D5")) << all;
}

TEST(CdbReader, RulesOnConstraintsMaterialsAndBlocks) {
  const std::string et = "ET,1,185\n";
  // Nodes held in all directions (ALL, and a range) form D_ALL.
  const Mesh m =
      read_text(cube_file(et, "D,1,ALL,0\nD,2,UX,0,,4,2\nD,2,UY,0.0,,4,2\nD,2,UZ,0,,4,2\n"));
  EXPECT_EQ(ids_of(m, m.node_sets.at("D_ALL")), (std::vector<int>{1, 2, 4}));
  auto message = [&](const std::string& extra) {
    return error_of([&] { read_text(cube_file(et, extra)); }).message();
  };
  EXPECT_TRUE(contains(message("D,1,UX,0.001\n"), "non-zero prescribed displacement"));
  EXPECT_TRUE(contains(message("D,ALL,ALL,0\n"), "only node numbers"));
  EXPECT_TRUE(contains(message("CE,1,0.5,1,UX,1.0,2,UX,-1.0\n"), "non-zero constant"));
  EXPECT_TRUE(contains(message("CE,1,0,1,ROTX,1.0,2,UX,-1.0\n"), "'ROTX'"));
  EXPECT_TRUE(contains(message("CE,R5.0,DEFI,3,1,0\nCE,R5.0,NODE,1,UX,1.0,2,UX,-1.0\n"),
                       "1 term(s) missing"));
  EXPECT_TRUE(contains(message("CE,R5.0,NODE,1,UX,1.0,2,UX,-1.0\n"), "without a CE,R5.0,DEFI"));
  EXPECT_TRUE(contains(message("CP,1,ROTX,1,2\n"), "'ROTX'"));
  EXPECT_TRUE(contains(message("CP,1,UX,ALL\n"), "NODE1 = ALL"));
  EXPECT_TRUE(contains(message("CP,1,,1,2\n"), "no label"));
  EXPECT_TRUE(contains(message("CP,1,UX,1,2\nCP,1,UY,3\n"), "a different label"));
  EXPECT_TRUE(contains(message("CP,1,UX,1,9\n"), "unknown node 9"));
  EXPECT_TRUE(contains(message("CP,R5.0,1,UX,1,2\n"), "blocked form"));
  EXPECT_TRUE(contains(message("MPTEMP,R5.0,2,1,0,100\nMPDATA,R5.0,2,EX,1,1,2e11,1.9e11,\n"),
                       "temperature-dependent"));
  EXPECT_TRUE(contains(message("MPDATA,R5.0,1,EY,1,1,2e11,\n"), "anisotropic"));
  EXPECT_TRUE(
      contains(message("CMBLOCK,SIDE,NODE,2\n(8i10)\n         1         9\n"), "unknown node 9"));
  EXPECT_TRUE(contains(message("CMBLOCK,SIDE,NODE,2\n(8i10)\n        -3         4\n"),
                       "neither an id nor the end of a range"));
  // CE in CDWRITE's blocked form (two terms a line) and in the plain form: Mesh::equations,
  // first term dependent, as *EQUATION.
  const Mesh ce = read_text(cube_file(et,
                                      "CE,R5.0,DEFI,       3,       1,  0.00000000    \n"
                                      "CE,R5.0,NODE,         7,UZ  ,  1.00000000    ,         8,"
                                      "UX  , -0.500000000    \n"
                                      "CE,R5.0,NODE,         6,UY  ,  2.50000000    \n"
                                      "CE,2,0,3,UX,1.0,4,UX,-1.0\n"));
  ASSERT_EQ(ce.equations.size(), 2u);
  const auto dof = [&](int id, int d) {
    return 3 * static_cast<int>(std::find(ce.node_ids.begin(), ce.node_ids.end(), id) -
                                ce.node_ids.begin()) +
           d;
  };
  EXPECT_EQ(ce.equations[0].dofs, (std::vector<int>{dof(7, 2), dof(8, 0), dof(6, 1)}));
  EXPECT_EQ(ce.equations[0].coefficients, (std::vector<double>{1.0, -0.5, 2.5}));
  EXPECT_EQ(ce.equations[0].origin, "cube.cdb:18");
  EXPECT_EQ(ce.equations[1].dofs, (std::vector<int>{dof(3, 0), dof(4, 0)}));
  EXPECT_EQ(ce.equations[1].coefficients, (std::vector<double>{1.0, -1.0}));
  // Plain MPDATA form and PRXY.
  std::map<int, DeckMaterial> materials;
  std::istringstream in(cube_file(et, "MPDATA,EX,1,,2e11\nMPDATA,PRXY,1,,0.29\n"));
  read_cdb(in, "cube.cdb", nullptr, &materials);
  EXPECT_EQ(materials.at(1).youngs_modulus, 2e11);
  EXPECT_EQ(materials.at(1).poisson_ratio, 0.29);
  EXPECT_TRUE(std::isnan(materials.at(1).density));
  // A component with a range ending in a negative number.
  const Mesh c =
      read_text(cube_file(et, "CMBLOCK,SIDE,NODE,3\n(8i10)\n         1        -3         8\n"));
  EXPECT_EQ(ids_of(c, c.node_sets.at("SIDE")), (std::vector<int>{1, 2, 3, 8}));
}

// CP (coupled DOF sets, ANSYS's CP command): u(node) = u(primary) in the set's direction for
// every node after the first, the node's DOF dependent, as *EQUATION "node, d, 1, primary, d, -1".
TEST(CdbReader, CoupledSetsBecomeEquationsOnTheirPrimaryNode) {
  const Mesh m = read_text(cube_file("ET,1,185\n",
                                     "CP,1,UX,1,2,3\n"     // set 1: UX of 2 and 3 = UX of 1
                                     "CP,1,,4,-3,2\n"      // adds 4, takes 3 out, 2 again ignored
                                     "CP,NEXT,UZ,5,6\n"    // set 2
                                     "CP,HIGH,,7\n"        // adds 7 to set 2
                                     "CP,10,ALL,8,1\n"));  // sets 10, 11, 12: UX, UY, UZ
  const auto dof = [&](int id, int d) {
    return 3 * static_cast<int>(std::find(m.node_ids.begin(), m.node_ids.end(), id) -
                                m.node_ids.begin()) +
           d;
  };
  const std::vector<std::vector<int>> expected = {
      {dof(2, 0), dof(1, 0)}, {dof(4, 0), dof(1, 0)}, {dof(6, 2), dof(5, 2)},
      {dof(7, 2), dof(5, 2)}, {dof(1, 0), dof(8, 0)}, {dof(1, 1), dof(8, 1)},
      {dof(1, 2), dof(8, 2)}};
  ASSERT_EQ(m.equations.size(), expected.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(m.equations[k].dofs, expected[k]) << k;
    EXPECT_EQ(m.equations[k].coefficients, (std::vector<double>{1.0, -1.0})) << k;
  }
  EXPECT_EQ(m.equations[0].origin, "cube.cdb:18");
  EXPECT_EQ(m.equations[1].origin, "cube.cdb:19");
  EXPECT_EQ(m.equations[3].origin, "cube.cdb:21");
}

TEST(CdbReader, Solid186FullIntegrationAndBrokenBlocks) {
  // A 20-node element continues on a second line; KEYOPT(2)=1 is full integration.
  std::string nodes = "NBLOCK,6,SOLID\n(3i9,6e21.13e3)\n";
  // Corners and mid-edge nodes of the unit cube in C3D20 order (natural coordinates mapped to
  // [0,1]^3).
  const double xi[20][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1},
                            {1, -1, 1},   {1, 1, 1},   {-1, 1, 1}, {0, -1, -1}, {1, 0, -1},
                            {0, 1, -1},   {-1, 0, -1}, {0, -1, 1}, {1, 0, 1},   {0, 1, 1},
                            {-1, 0, 1},   {-1, -1, 0}, {1, -1, 0}, {1, 1, 0},   {-1, 1, 0}};
  for (int a = 0; a < 20; ++a) {
    char line[128];
    std::snprintf(line, sizeof line, "%9d%9d%9d%21.13E%21.13E%21.13E\n", a + 1, 0, 0,
                  0.5 * (xi[a][0] + 1), 0.5 * (xi[a][1] + 1), 0.5 * (xi[a][2] + 1));
    nodes += line;
  }
  nodes += "N,R5.3,LOC,       -1,\n";
  std::string record = "EBLOCK,19,SOLID\n(19i9)\n";
  char buf[512];
  std::snprintf(buf, sizeof buf, "%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d%9d", 1, 1, 1, 1, 0, 0, 0, 0, 20, 0,
                5);
  record += buf;
  for (int a = 0; a < 8; ++a) record += (std::snprintf(buf, sizeof buf, "%9d", a + 1), buf);
  record += "\n";
  for (int a = 8; a < 20; ++a) record += (std::snprintf(buf, sizeof buf, "%9d", a + 1), buf);
  record += "\n";
  const Mesh full = read_text("ET,1,186\nKEYOPT,1,2,1\n" + nodes + record + "       -1\n");
  ASSERT_EQ(full.num_elements(), 1);
  EXPECT_EQ(full.element_types[0], ElementType::kC3D20);
  EXPECT_EQ(read_text("ET,1,186\n" + nodes + record + "-1\n").element_types[0],
            ElementType::kC3D20R);
  // The block must end.
  EXPECT_TRUE(contains(error_of([&] { read_text("ET,1,186\n" + nodes + record); }).message(),
                       "does not end"));
  // A node line longer than its format.
  EXPECT_TRUE(contains(error_of([&] {
                         read_text(
                             "NBLOCK,6,SOLID\n(3i9,3e21.13)\n"
                             "        1        0        0 0.0000000000000E+000 "
                             "0.0000000000000E+000 0.0000000000000E+000 1.0E+000\n-1\n");
                       }).message(),
                       "longer than its format"));
}

}  // namespace
}  // namespace stickslip

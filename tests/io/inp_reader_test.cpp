#include "io/inp_reader.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "core/errors.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/mesh/";

std::vector<int> ids_of(const Mesh& m, const std::vector<int>& nodes) {
  std::vector<int> ids;
  for (int n : nodes) ids.push_back(m.node_ids[n]);
  std::sort(ids.begin(), ids.end());
  return ids;
}
std::vector<int> element_ids_of(const Mesh& m, const std::vector<int>& elements) {
  std::vector<int> ids;
  for (int e : elements) ids.push_back(m.element_ids[e]);
  std::sort(ids.begin(), ids.end());
  return ids;
}
std::vector<int> range(int first, int last, int step = 1) {
  std::vector<int> v;
  for (int i = first; i <= last; i += step) v.push_back(i);
  return v;
}

TEST(InpReader, ReadsTheHandWrittenSampleWithAllFeatures) {
  const Mesh m = read_inp(kDir + "sample_all_features.inp");
  ASSERT_EQ(m.num_nodes(), 39);
  ASSERT_EQ(m.num_elements(), 4);
  const auto index = node_index_by_id(m);
  EXPECT_EQ(m.coordinates.col(index.at(300)), Eigen::Vector3d(-1, 0, 0));   // missing y, z = 0
  EXPECT_EQ(m.coordinates.col(index.at(202)), Eigen::Vector3d(1.5, 0, 5));  // 1.5D0
  EXPECT_EQ(m.coordinates.col(index.at(7)), Eigen::Vector3d(1, 1, 1));

  // Elements in file order, types and connectivity (by id), continuation lines included.
  EXPECT_EQ(m.element_ids, (std::vector<int>{1, 2, 4, 3}));
  EXPECT_EQ(m.element_types, (std::vector<ElementType>{ElementType::kC3D8I, ElementType::kC3D20R,
                                                       ElementType::kC3D10, ElementType::kC3D4}));
  auto element_node_ids = [&](int e) {
    std::vector<int> ids;
    for (int n : m.element_nodes(e)) ids.push_back(m.node_ids[n]);
    return ids;
  };
  EXPECT_EQ(element_node_ids(0), range(1, 8));
  EXPECT_EQ(element_node_ids(1), range(101, 120));
  EXPECT_EQ(element_node_ids(2), range(201, 210));
  EXPECT_EQ(element_node_ids(3), (std::vector<int>{1, 2, 4, 5}));

  // Sets: names upper-cased, GENERATE, references resolved in file order (UNION sees BOTTOM
  // before node 5 is added to it), repeated definitions add.
  EXPECT_EQ(ids_of(m, m.node_sets.at("CUBE NODES")), range(1, 8));
  EXPECT_EQ(ids_of(m, m.node_sets.at("BOTTOM")), range(1, 5));
  EXPECT_EQ(ids_of(m, m.node_sets.at("MID")), range(109, 120));
  EXPECT_EQ(ids_of(m, m.node_sets.at("EVERY_OTHER")), range(201, 209, 2));
  std::vector<int> expected_union = range(1, 4);
  for (int id : range(109, 120)) expected_union.push_back(id);
  expected_union.push_back(300);
  EXPECT_EQ(ids_of(m, m.node_sets.at("UNION")), expected_union);
  EXPECT_EQ(m.node_sets.size(), 5u);
  EXPECT_EQ(element_ids_of(m, m.element_sets.at("HEXA")), (std::vector<int>{1, 2}));
  EXPECT_EQ(element_ids_of(m, m.element_sets.at("TETS")), (std::vector<int>{3, 4}));
  EXPECT_EQ(element_ids_of(m, m.element_sets.at("ALL")), range(1, 4));
  EXPECT_EQ(element_ids_of(m, m.element_sets.at("GEN")), range(1, 3));
  EXPECT_EQ(m.element_sets.size(), 4u);
}

TEST(InpReader, SampleMidEdgeNodesLieAtTheMidpointsOfTheCalculixEdges) {
  // Independent check that the sample (and so the reader's node order) follows CalculiX's
  // convention: C3D20 edges (0,1)(1,2)(2,3)(3,0)(4,5)(5,6)(6,7)(7,4)(0,4)(1,5)(2,6)(3,7),
  // C3D10 edges (0,1)(1,2)(2,0)(0,3)(1,3)(2,3) (CalculiX User's Manual, element types).
  const Mesh m = read_inp(kDir + "sample_all_features.inp");
  const int hex_edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const int tet_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  auto x = [&](int e, int local) {
    return Eigen::Vector3d(m.coordinates.col(m.element_nodes(e)[local]));
  };
  for (int k = 0; k < 12; ++k) {
    EXPECT_LT((x(1, 8 + k) - 0.5 * (x(1, hex_edges[k][0]) + x(1, hex_edges[k][1]))).norm(), 1e-15);
  }
  for (int k = 0; k < 6; ++k) {
    EXPECT_LT((x(2, 4 + k) - 0.5 * (x(2, tet_edges[k][0]) + x(2, tet_edges[k][1]))).norm(), 1e-15);
  }
}

struct BadFile {
  const char* file;
  int line;
  const char* message;  // substring of the message
};

class InpReaderErrors : public ::testing::TestWithParam<BadFile> {};

TEST_P(InpReaderErrors, NameTheFileTheLineAndTheProblem) {
  const BadFile& bad = GetParam();
  const std::string path = kDir + bad.file;
  try {
    read_inp(path);
    FAIL() << bad.file << " was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path);
    EXPECT_EQ(e.where().line, bad.line) << e.what();
    EXPECT_NE(e.message().find(bad.message), std::string::npos)
        << "message: " << e.message() << "\nexpected to contain: " << bad.message;
    EXPECT_NE(std::string(e.what()).find(path + ":" + std::to_string(bad.line)), std::string::npos);
  }
}

INSTANTIATE_TEST_SUITE_P(
    MalformedSamples, InpReaderErrors,
    ::testing::Values(
        BadFile{"bad_number.inp", 4, "'1.0x' is not a valid coordinate"},
        BadFile{"bad_node_id.inp", 6, "'5.5' is not a valid node id"},
        BadFile{"unknown_node.inp", 11, "element 1 refers to unknown node 99"},
        BadFile{"duplicate_node.inp", 9, "duplicate node id 3 (first defined on line 4)"},
        BadFile{"duplicate_element.inp", 12, "duplicate element id 1 (first defined on line 11)"},
        BadFile{"missing_set.inp", 15, "unknown node set FOO"},
        BadFile{"wrong_node_count.inp", 12, "element 2 of type C3D8 has 7 nodes, needs 8"},
        BadFile{"too_many_nodes.inp", 13, "element 2 of type C3D4 has more than 4 nodes"},
        BadFile{"unsupported_type.inp", 12, "unsupported element type S4R"},
        BadFile{"missing_type.inp", 12, "*ELEMENT without TYPE="},
        BadFile{"generate_reversed.inp", 13, "GENERATE: last 1 < first 8"},
        BadFile{"generate_unknown_element.inp", 13, "element set G: unknown element 2"},
        BadFile{"data_before_keyword.inp", 1, "data line before any keyword"},
        BadFile{"include.inp", 12, "*INCLUDE: cannot open"},
        BadFile{"node_too_many_values.inp", 3, "got 5 values"},
        BadFile{"unsupported_parameter.inp", 1, "*NODE: unsupported parameter SYSTEM"},
        BadFile{"repeated_node.inp", 13, "element 2 uses node 3 twice"}),
    [](const ::testing::TestParamInfo<BadFile>& info) {
      std::string name = info.param.file;
      return name.substr(0, name.find('.'));
    });

TEST(InpReader, MissingFileIsInvalidInputNamingIt) {
  try {
    read_inp(kDir + "does_not_exist.inp");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, kDir + "does_not_exist.inp");
  }
}

TEST(InpReader, StreamFormHandlesCrLfAndTrailingCommas) {
  std::istringstream in(
      "*NODE\r\n1, 0, 0, 0,\r\n2, 1, 0, 0\r\n3, 0, 1, 0\r\n4, 0, 0, 1\r\n"
      "*ELEMENT, TYPE=C3D4,\r\n7, 1, 2, 3, 4\r\n");
  const Mesh m = read_inp(in, "inline");
  EXPECT_EQ(m.num_nodes(), 4);
  EXPECT_EQ(m.element_ids, std::vector<int>{7});
}

// A one-tetrahedron deck followed by `tail`.
std::string tet_deck(const std::string& tail) {
  return "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n"
         "*ELEMENT, TYPE=C3D4\n1, 1, 2, 3, 4\n" +
         tail;
}

TEST(InpReader, EveryKeywordItDoesNotUseGivesOneWarningWithItsLines) {
  std::vector<std::string> warnings;
  read_inp(kDir + "sample_all_features.inp", &warnings);
  // In order of first appearance; lines of the sample counted by hand.
  const std::string f = kDir + "sample_all_features.inp: ";
  EXPECT_EQ(warnings,
            (std::vector<std::string>{
                f + "*HEADING ignored (not used by stickslip), line 3",
                f + "*STEP ignored (analyses and loads come from the case file), line 75",
                f + "*STATIC ignored (analyses and loads come from the case file), line 76",
                f + "*END STEP ignored (analyses and loads come from the case file), "
                    "line 77"}));
}

TEST(InpReader, RepeatedSkippedKeywordsShareOneWarningListingEveryLine) {
  std::istringstream in(tet_deck(
      "*BOUNDARY\n1, 1, 3\n*Boundary\n2, 1, 3\n*FOO, BAR=1\nx\n"
      "*BOUNDARY\n3,1\n*BOUNDARY\n*BOUNDARY\n*BOUNDARY\n*BOUNDARY\n*BOUNDARY\n*BOUNDARY\n"
      "*BOUNDARY\n*BOUNDARY\n"));
  std::vector<std::string> warnings;
  const Mesh mesh = read_inp(in, "deck", &warnings);
  EXPECT_EQ(warnings,
            (std::vector<std::string>{
                "deck: *BOUNDARY ignored (clamps come from the case file, unless a body's "
                "supports say from_mesh: true), lines 8, 10, 14, 16, 17, 18, 19, 20, 21, 22 and "
                "1 more",
                "deck: *FOO ignored (not used by stickslip), line 12"}));
  // The data lines are recorded (Mesh::boundaries) for bodies that ask for them.
  ASSERT_EQ(mesh.boundaries.size(), 3u);
  EXPECT_EQ(mesh.boundaries[0].nodes, std::vector<int>{0});
  EXPECT_EQ(mesh.boundaries[0].first, 0);
  EXPECT_EQ(mesh.boundaries[0].last, 2);
  EXPECT_EQ(mesh.boundaries[2].nodes, std::vector<int>{2});
  EXPECT_EQ(mesh.boundaries[2].last, 0);
  EXPECT_EQ(mesh.boundaries[2].origin, "deck:15");
  for (const MeshBoundary& b : mesh.boundaries) EXPECT_TRUE(b.unsupported.empty());
}

TEST(InpReader, BoundaryLinesThatAreNotZeroDisplacementsCarryWhy) {
  std::istringstream in(tet_deck(
      "*NSET, NSET=TOP\n3, 4\n*BOUNDARY\nTOP, XSYMM\n2, 1, 1, 0.5\n4, 5, 6\n1, XASYMM\n"
      "*BOUNDARY, TYPE=VELOCITY\n1, 1, 3\n"));
  const Mesh mesh = read_inp(in, "deck", nullptr);
  ASSERT_EQ(mesh.boundaries.size(), 5u);
  EXPECT_TRUE(mesh.boundaries[0].unsupported.empty());
  EXPECT_EQ(mesh.boundaries[0].nodes.size(), 2u);
  EXPECT_EQ(mesh.boundaries[0].first, 0);
  EXPECT_EQ(mesh.boundaries[0].last, 0);
  EXPECT_NE(mesh.boundaries[1].unsupported.find("non-zero"), std::string::npos);
  EXPECT_NE(mesh.boundaries[2].unsupported.find("rotational"), std::string::npos);
  EXPECT_NE(mesh.boundaries[3].unsupported.find("XASYMM"), std::string::npos);
  EXPECT_NE(mesh.boundaries[4].unsupported.find("VELOCITY"), std::string::npos);
}

TEST(InpReader, AKeywordThatWouldChangeStiffnessOrMassIsAnErrorAtItsLine) {
  for (const char* keyword : {"*TIE, NAME=T", "*COUPLING, REF NODE=1, SURFACE=S", "*KINEMATIC",
                              "*MPC", "*RIGID BODY, NSET=A, REF NODE=1", "*SHELL SECTION, ELSET=E",
                              "*BEAM SECTION", "*DASHPOT, ELSET=E", "*DISTRIBUTING COUPLING",
                              "*NGEN", "*PRE-TENSION SECTION"}) {
    std::istringstream in(tet_deck("*MATERIAL, NAME=S\n" + std::string(keyword) + "\n1\n"));
    try {
      read_inp(in, "deck");
      ADD_FAILURE() << keyword << " was accepted";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().line, 9) << keyword;
      EXPECT_NE(e.message().find("is not supported"), std::string::npos) << e.message();
      EXPECT_NE(e.message().find("would change the stiffness or mass"), std::string::npos)
          << e.message();
    }
  }
  for (const char* type : {"S4R", "B31", "DASHPOTA", "CPS4"}) {
    std::istringstream in(
        tet_deck("*ELEMENT, TYPE=" + std::string(type) + "\n2, 1, 2, 3, 4\n"));
    try {
      read_inp(in, "deck");
      ADD_FAILURE() << type << " was accepted";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().line, 8) << type;
      EXPECT_NE(e.message().find("unsupported element type"), std::string::npos) << e.message();
    }
  }
}

TEST(InpReader, MaterialsAndSolidSectionsGiveEachElementItsMaterial) {
  std::istringstream in(
      tet_deck("*ELEMENT, TYPE=C3D4, ELSET=OTHER\n2, 1, 2, 3, 4\n*ELSET, ELSET=FIRST\n1\n"
               "*MATERIAL, NAME=Steel\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n"
               "*MATERIAL, NAME=ORTHO\n*ELASTIC, TYPE=ORTHO\n1, 2, 3, 4, 5, 6, 7, 8\n9\n"
               "*SOLID SECTION, ELSET=FIRST, MATERIAL=STEEL\n*SOLID SECTION, ELSET=other, "
               "MATERIAL=ortho\n"));
  const Mesh m = read_inp(in, "deck");
  ASSERT_EQ(m.materials.size(), 2u);
  EXPECT_EQ(m.materials[0].name, "STEEL");
  EXPECT_EQ(m.materials[0].youngs_modulus, 2.1e11);
  EXPECT_EQ(m.materials[0].poisson_ratio, 0.3);
  EXPECT_EQ(m.materials[0].density, 7850.0);
  EXPECT_EQ(m.materials[0].origin, "deck:12");
  EXPECT_TRUE(m.materials[0].problem.empty());
  EXPECT_NE(m.materials[1].problem.find("TYPE=ORTHO"), std::string::npos) << m.materials[1].problem;
  EXPECT_EQ(m.element_material, (std::vector<int>{0, 1}));
  // Errors at their line.
  for (const auto& [tail, what] : std::vector<std::pair<std::string, std::string>>{
           {"*SOLID SECTION, ELSET=E, MATERIAL=NONE\n", "unknown material NONE"},
           {"*MATERIAL, NAME=A\n*SOLID SECTION, ELSET=NOPE, MATERIAL=A\n", "unknown element set"},
           {"*ELASTIC\n1, 0.3\n", "before any *MATERIAL"}}) {
    std::istringstream bad(tet_deck(tail));
    try {
      read_inp(bad, "deck");
      ADD_FAILURE() << tail;
    } catch (const InvalidInput& e) {
      EXPECT_NE(e.message().find(what), std::string::npos) << e.message();
    }
  }
}

TEST(InpReader, SpringsAndMassesTakeTheirSpringOrMassSection) {
  // SPRINGA from node 2 (1, 0, 0) to node 3 (0, 1, 0): along (-1, 1, 0)/sqrt 2.
  std::istringstream in(
      tet_deck("*ELEMENT, TYPE=SPRING1, ELSET=A\n11, 4\n*SPRING, ELSET=A\n3\n1.5e3\n"
               "*ELEMENT, TYPE=SPRING2, ELSET=B\n12, 1, 2\n*SPRING, ELSET=B\n2, 1\n2.5e3\n"
               "*ELEMENT, TYPE=SPRINGA, ELSET=C\n13, 2, 3\n*SPRING, ELSET=C\n\n3.5e3\n"
               "*ELEMENT, TYPE=MASS, ELSET=D\n14, 1\n15, 3\n*MASS, ELSET=D\n0.75\n"));
  const Mesh m = read_inp(in, "deck");
  ASSERT_EQ(m.springs.size(), 3u);
  ASSERT_EQ(m.point_masses.size(), 2u);
  EXPECT_EQ(m.springs[0].id, 11);
  EXPECT_EQ(m.node_ids[m.springs[0].node_a], 4);
  EXPECT_EQ(m.springs[0].node_b, -1);
  EXPECT_EQ(m.springs[0].direction_a, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(m.springs[0].stiffness, 1.5e3);
  EXPECT_EQ(m.node_ids[m.springs[1].node_b], 2);
  EXPECT_EQ(m.springs[1].direction_a, Eigen::Vector3d::UnitY());
  EXPECT_EQ(m.springs[1].direction_b, Eigen::Vector3d::UnitX());
  EXPECT_LT((m.springs[2].direction_a - Eigen::Vector3d(-1, 1, 0) / std::sqrt(2.0)).norm(), 1e-15);
  EXPECT_EQ(m.springs[2].direction_b, m.springs[2].direction_a);
  EXPECT_EQ(m.springs[2].stiffness, 3.5e3);
  EXPECT_EQ(m.node_ids[m.point_masses[1].node], 3);
  EXPECT_EQ(m.point_masses[1].mass, 0.75);
  EXPECT_EQ(m.springs[1].origin, "deck:14");  // its element line
}

TEST(InpReader, SpringAndMassErrorsNameTheirLine) {
  struct Bad {
    std::string tail;
    int line;
    std::string what;
  };
  const std::vector<Bad> cases{
      {"*ELEMENT, TYPE=SPRING1, ELSET=A\n11, 4\n", 9, "has no *SPRING"},
      {"*ELEMENT, TYPE=SPRING1\n11, 4\n", 8, "without ELSET"},
      {"*ELEMENT, TYPE=SPRING1, ELSET=A\n11, 4\n*SPRING, ELSET=A, NONLINEAR\n1\n", 10, "nonlinear"},
      {"*ELEMENT, TYPE=SPRING1, ELSET=A\n11, 4\n*SPRING, ELSET=A\n1.0e3\n", 10,
       "one degree of freedom"},
      {"*ELEMENT, TYPE=SPRING2, ELSET=A\n11, 4, 1\n*SPRING, ELSET=A\n1\n1.0e3\n", 10,
       "two degrees of freedom"},
      {"*ELEMENT, TYPE=SPRING1, ELSET=A\n11, 4\n*SPRING, ELSET=A\n4\n1.0e3\n", 11, "above 3"},
      {"*ELEMENT, TYPE=SPRINGA, ELSET=A\n11, 4, 4\n*SPRING, ELSET=A\n1.0e3\n", 9, "to itself"},
      {"*ELEMENT, TYPE=MASS, ELSET=M\n11, 4\n*MASS, ELSET=M\n1.0\n2.0\n", 12, "second data line"},
      {"*ELEMENT, TYPE=MASS, ELSET=M\n1, 4\n*MASS, ELSET=M\n1.0\n", 9, "duplicate element id 1"},
      {"*MASS, ELSET=M\n1.0\n", 8, "no MASS element"},
      {"*ELEMENT, TYPE=MASS, ELSET=M\n11, 9\n*MASS, ELSET=M\n1.0\n", 9, "unknown node 9"},
  };
  for (const Bad& bad : cases) {
    std::istringstream in(tet_deck(bad.tail));
    try {
      read_inp(in, "deck");
      ADD_FAILURE() << bad.tail << " was accepted";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().line, bad.line) << bad.tail << e.message();
      EXPECT_NE(e.message().find(bad.what), std::string::npos) << e.message();
    }
  }
}

TEST(InpReader, EquationsBecomeLinearConstraintsOnDofs) {
  // Terms split over lines and several per line; "2" announces the second equation.
  std::istringstream in(tet_deck(
      "*EQUATION\n3\n4, 2, 1.0, 1, 2, -0.5,\n2, 2, -5D-1\n*Equation\n2\n3,3,2.,2,1,-2.\n"));
  const Mesh m = read_inp(in, "deck");
  ASSERT_EQ(m.equations.size(), 2u);
  EXPECT_EQ(m.equations[0].dofs, (std::vector<int>{3 * 3 + 1, 0 * 3 + 1, 1 * 3 + 1}));
  EXPECT_EQ(m.equations[0].coefficients, (std::vector<double>{1.0, -0.5, -0.5}));
  EXPECT_EQ(m.equations[0].origin, "deck:9");
  EXPECT_EQ(m.equations[1].dofs, (std::vector<int>{2 * 3 + 2, 1 * 3 + 0}));
  EXPECT_EQ(m.equations[1].coefficients, (std::vector<double>{2.0, -2.0}));
  EXPECT_EQ(m.equations[1].origin, "deck:13");
}

TEST(InpReader, MalformedEquationsAreErrorsAtTheirLine) {
  struct Bad {
    const char* tail;
    int line;
    const char* message;
  };
  for (const Bad& bad : {
           Bad{"*EQUATION\n2\n4, 2, 1.0\n*STEP\n", 9, "2 terms announced, 1 given"},
           Bad{"*EQUATION\n1\n4, 2, 1.0, 1, 2, 1.0\n", 10, "more terms than the 1 announced"},
           Bad{"*EQUATION\n2\n4, 5, 1.0, 1, 2, 1.0\n", 10, "degree of freedom 5"},
           Bad{"*EQUATION\n2\n4, 1, 0.0, 1, 2, 1.0\n", 10, "must not be 0"},
           Bad{"*EQUATION\n2\nTIP, 1, 1.0, 1, 2, 1.0\n", 10, "node set TIP"},
           Bad{"*EQUATION\n2\n9, 1, 1.0, 1, 2, 1.0\n", 9, "unknown node 9"},
           Bad{"*EQUATION\n2\n4, 1, 1.0, 4, 1, 1.0\n", 9, "appears twice"},
           Bad{"*EQUATION\n2\n4, 1, 1.0, 1, 2\n", 10, "expected terms"},
           Bad{"*EQUATION, INPUT=eq.txt\n2\n", 8, "unsupported parameter INPUT"},
       }) {
    std::istringstream in(tet_deck(bad.tail));
    try {
      read_inp(in, "deck");
      ADD_FAILURE() << bad.tail << " was accepted";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(e.where().line, bad.line) << bad.tail << ": " << e.message();
      EXPECT_NE(e.message().find(bad.message), std::string::npos) << e.message();
    }
  }
}

TEST(InpReader, IncludesAreReadInPlaceRelativeToTheIncludingFile) {
  const std::string dir = kDir + "include/";
  std::vector<std::string> warnings;
  const Mesh m = read_inp(dir + "main.inp", &warnings);
  EXPECT_EQ(m.num_nodes(), 8);  // the *NODE data lines come from sub/nodes.inp
  EXPECT_EQ(m.num_elements(), 1);
  EXPECT_EQ(ids_of(m, m.node_sets.at("ALL")), range(1, 8));
  EXPECT_EQ(ids_of(m, m.node_sets.at("TOP")), range(5, 8));
  ASSERT_EQ(m.equations.size(), 1u);  // from ../equations.inp, included by sub/elements.inp
  EXPECT_EQ(m.equations[0].origin, dir + "sub/../equations.inp:2");
  // Skipped keywords are reported per file, with that file's line numbers.
  EXPECT_EQ(
      warnings,
      (std::vector<std::string>{
          dir + "sub/../equations.inp: *SURFACE INTERACTION ignored (contacts come from the case "
                "file), line 4",
          dir + "sub/elements.inp: *SURFACE INTERACTION ignored (contacts come from the case "
                "file), line 5"}));
}

TEST(InpReader, IncludeErrorsNameTheIncludedFileAndLine) {
  const std::string dir = kDir + "include/";
  try {
    read_inp(dir + "cycle_a.inp");
    FAIL() << "a cycle was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, dir + "cycle_b.inp");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_NE(e.message().find("cycle"), std::string::npos) << e.message();
  }
  try {
    read_inp(dir + "duplicate.inp");
    FAIL() << "a duplicate node was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, dir + "sub/dup.inp");
    EXPECT_EQ(e.where().line, 2);
    EXPECT_NE(e.message().find("duplicate node id 1 (first defined on line 2)"),
              std::string::npos)
        << e.message();
  }
}

}  // namespace
}  // namespace stickslip

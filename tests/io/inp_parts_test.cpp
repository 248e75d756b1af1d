// Abaqus/CAE decks with *PART, *ASSEMBLY and *INSTANCE: the mesh they define is the one written
// flat by hand (tests/abaqus_parts_decks.h: coordinates of the rotated instance worked out
// without the reader's rotation), and what the reader does not support stops at its line.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "../abaqus_parts_decks.h"
#include "core/errors.h"
#include "io/inp_reader.h"

namespace stickslip {
namespace {

// Coordinates of ~0.4 m through a rotation by 90° (cos = 6e-17) and a translation: round-off.
constexpr double kCoordinateRoundOff = 1e-15;

Mesh read_text(const std::string& text, std::vector<std::string>* warnings = nullptr) {
  std::istringstream in(text);
  return read_inp(in, "deck.inp", warnings);
}

std::vector<int> ids(const std::vector<int>& indices, const std::vector<int>& id_of) {
  std::vector<int> out;
  for (int i : indices) out.push_back(id_of[i]);
  return out;
}

TEST(InpParts, TwoPlacedInstancesOfAPartAreTheMeshWrittenFlat) {
  std::vector<std::string> warnings;
  const Mesh parts = read_text(parts_decks::part_deck(), &warnings);
  const Mesh flat = read_text(parts_decks::flat_deck());
  ASSERT_EQ(parts.num_nodes(), 32);
  ASSERT_EQ(parts.num_elements(), 6);
  EXPECT_EQ(parts.node_ids, flat.node_ids);  // instance 2 numbered after instance 1
  EXPECT_EQ(parts.element_ids, flat.element_ids);
  EXPECT_EQ(parts.connectivity, flat.connectivity);
  EXPECT_EQ(parts.element_offsets, flat.element_offsets);
  EXPECT_EQ(parts.element_types, flat.element_types);
  EXPECT_LE((parts.coordinates - flat.coordinates).cwiseAbs().maxCoeff(), kCoordinateRoundOff);
  // The rotated instance really moved: its first node went from (0, 0, 0) to (0.3, 0.1, 0).
  EXPECT_NEAR(parts.coordinates(0, 16), 0.3, kCoordinateRoundOff);
  EXPECT_NEAR(parts.coordinates(1, 16), 0.1, kCoordinateRoundOff);
  ASSERT_EQ(parts.equations.size(), flat.equations.size());
  for (size_t e = 0; e < flat.equations.size(); ++e) {
    EXPECT_EQ(parts.equations[e].dofs, flat.equations[e].dofs) << e;
    EXPECT_EQ(parts.equations[e].coefficients, flat.equations[e].coefficients) << e;
  }
  EXPECT_EQ(ids(parts.node_sets.at("FIX"), parts.node_ids),
            ids(flat.node_sets.at("FIX"), flat.node_ids));
  EXPECT_EQ(ids(parts.node_sets.at("TIP"), parts.node_ids),
            ids(flat.node_sets.at("TIP"), flat.node_ids));
  // The part's sets, named after each instance, and one element set per instance.
  EXPECT_EQ(ids(parts.node_sets.at("BLOCK-2.START"), parts.node_ids),
            (std::vector<int>{17, 21, 25, 29}));
  EXPECT_EQ(ids(parts.element_sets.at("BLOCK-1.ALL"), parts.element_ids),
            (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(ids(parts.element_sets.at("BLOCK-2"), parts.element_ids), (std::vector<int>{4, 5, 6}));
  // Each instance's elements get the part's section: the material of every element.
  ASSERT_EQ(parts.element_material.size(), 6u);
  for (int m : parts.element_material) EXPECT_EQ(m, 0);
  for (const std::string& w : warnings) EXPECT_EQ(w.find("PART"), std::string::npos) << w;
}

TEST(InpParts, AnInstanceMeshedItselfAndSpringsBetweenInstancesAreRead) {
  // An independent instance (Abaqus/CAE writes its mesh inside *INSTANCE), translated; a SPRING2
  // of the assembly between two instances; a *MASS in the part.
  const std::string deck = R"(*Part, name=P
*Node
1, 0, 0, 0
*Element, type=MASS, elset=M
1, 1
*Mass, elset=M
2.5
*End Part
*Part, name=Empty
*End Part
*Assembly, name=A
*Instance, name=I1, part=P
*End Instance
*Instance, name=I2, part=Empty
 1., 2., 3.
*Node
1, 0, 0, 0
2, 1, 0, 0
3, 0, 1, 0
4, 0, 0, 1
*Element, type=C3D4, elset=Tet
1, 1, 2, 3, 4
*End Instance
*Element, type=Spring2, elset=Springs/Dashpots-1-spring
1, I1.1, I2.4
*Spring, elset=Springs/Dashpots-1-spring
1, 3
1e6
*Elset, elset=Both
I2.Tet, I2.1
*End Assembly
)";
  const Mesh m = read_text(deck);
  ASSERT_EQ(m.num_nodes(), 5);
  EXPECT_EQ(m.node_ids, (std::vector<int>{1, 2, 3, 4, 5}));
  EXPECT_EQ(m.coordinates.col(1), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(m.coordinates.col(4), Eigen::Vector3d(1, 2, 4));
  EXPECT_EQ(m.element_ids, (std::vector<int>{2}));  // after the part's MASS element 1
  ASSERT_EQ(m.point_masses.size(), 1u);
  EXPECT_EQ(m.point_masses[0].node, 0);
  EXPECT_EQ(m.point_masses[0].mass, 2.5);
  ASSERT_EQ(m.springs.size(), 1u);
  EXPECT_EQ(m.springs[0].id, 3);  // after the instances' elements 1 and 2
  EXPECT_EQ(m.springs[0].node_a, 0);
  EXPECT_EQ(m.springs[0].node_b, 4);
  EXPECT_EQ(m.springs[0].direction_b, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(m.element_sets.at("BOTH"), (std::vector<int>{0}));
  EXPECT_EQ(m.element_sets.at("I2.TET"), (std::vector<int>{0}));
}

// The fuzzers' seed of a deck with parts (fuzz/corpus/inp), read as a whole: ids, placement
// (Tet-2: translated by (2, 0, 0), then turned 90 degrees about the vertical through (2, 0, 0)),
// qualified names in sets, equations, springs and boundaries.
TEST(InpParts, TheFuzzSeedWithPartsReadsAsWorkedOutByHand) {
  const Mesh m =
      read_inp(std::string(STICKSLIP_TEST_DATA_DIR) + "/../../fuzz/corpus/inp/parts_instances.inp");
  ASSERT_EQ(m.num_nodes(), 8);
  EXPECT_EQ(m.element_ids, (std::vector<int>{1, 3}));  // Tet-2 after Tet-1's C3D4 1 and MASS 2
  const auto at = node_index_by_id(m);
  EXPECT_LE((m.coordinates.col(at.at(6)) - Eigen::Vector3d(2, 1, 0)).norm(), kCoordinateRoundOff);
  EXPECT_LE((m.coordinates.col(at.at(7)) - Eigen::Vector3d(1, 0, 0)).norm(), kCoordinateRoundOff);
  EXPECT_LE((m.coordinates.col(at.at(8)) - Eigen::Vector3d(2, 0, 1)).norm(), kCoordinateRoundOff);
  ASSERT_EQ(m.point_masses.size(), 2u);
  EXPECT_EQ(m.point_masses[1].id, 4);
  ASSERT_EQ(m.springs.size(), 1u);
  EXPECT_EQ(m.springs[0].id, 5);  // after every element of the instances
  EXPECT_EQ(m.node_ids[m.springs[0].node_a], 3);
  EXPECT_EQ(m.node_ids[m.springs[0].node_b], 7);
  EXPECT_EQ(ids(m.node_sets.at("FIX"), m.node_ids), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(ids(m.node_sets.at("TIPS"), m.node_ids), (std::vector<int>{4, 8}));
  EXPECT_EQ(ids(m.element_sets.at("BOTH"), m.element_ids), (std::vector<int>{1, 3}));
  ASSERT_EQ(m.equations.size(), 1u);
  EXPECT_EQ(m.equations[0].dofs, (std::vector<int>{3 * at.at(5), 3 * at.at(2)}));
  ASSERT_EQ(m.boundaries.size(), 2u);
  EXPECT_EQ(ids(m.boundaries[0].nodes, m.node_ids), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(ids(m.boundaries[1].nodes, m.node_ids), (std::vector<int>{6}));
  EXPECT_EQ(m.element_material, (std::vector<int>{0, 0}));
}

TEST(InpParts, APartWithoutInstanceIsAWarning) {
  std::vector<std::string> warnings;
  read_text("*Part, name=Unused\n*Node\n1, 0, 0, 0\n*End Part\n*Part, name=P\n" +
                std::string("*Node\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n*Element, type=C3D4\n"
                            "1, 1, 2, 3, 4\n*End Part\n*Assembly, name=A\n"
                            "*Instance, name=P-1, part=P\n*End Instance\n*End Assembly\n"),
            &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("deck.inp: *PART UNUSED ignored (no *INSTANCE of it), line 1"),
            std::string::npos)
      << warnings[0];
}

struct BadDeck {
  const char* name;
  const char* text;
  int line;
  const char* message;
};

class InpPartsErrors : public ::testing::TestWithParam<BadDeck> {};

TEST_P(InpPartsErrors, NameTheLineAndTheProblem) {
  const BadDeck& bad = GetParam();
  try {
    read_text(bad.text);
    FAIL() << bad.name << " was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "deck.inp") << bad.name;
    EXPECT_EQ(e.where().line, bad.line) << bad.name << ": " << e.what();
    EXPECT_NE(e.message().find(bad.message), std::string::npos)
        << bad.name << ": " << e.message() << "\nexpected to contain: " << bad.message;
  }
}

#define TET "*Node\n1,0,0,0\n2,1,0,0\n3,0,1,0\n4,0,0,1\n*Element, type=C3D4\n1, 1, 2, 3, 4\n"

INSTANTIATE_TEST_SUITE_P(
    Decks, InpPartsErrors,
    ::testing::Values(
        BadDeck{"instance outside assembly",
                "*Part, name=P\n" TET "*End Part\n*Instance, name=I, part=P\n", 10,
                "*INSTANCE outside an *ASSEMBLY"},
        BadDeck{"unknown part", "*Assembly, name=A\n*Instance, name=I, part=Q\n", 2,
                "unknown part Q"},
        BadDeck{"end part alone", "*End Part\n", 1, "*END PART without its *PART"},
        BadDeck{"unclosed part", "**\n*Part, name=P\n" TET, 2,
                "*PART P of line 2 has no *END PART before the end of the deck"},
        BadDeck{"unclosed instance",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Instance, name=I, part=P\n", 11,
                "*INSTANCE I of line 11 has no *END INSTANCE"},
        BadDeck{"part in assembly", "*Assembly, name=A\n*Part, name=P\n", 2,
                "*PART inside the *ASSEMBLY of line 1"},
        BadDeck{"duplicate instance",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Instance, name=I, part=P\n"
                "*End Instance\n*Instance, name=i, part=P\n",
                13, "*INSTANCE I defined twice (first on line 11)"},
        BadDeck{"reference point",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Node\n1, 0, 0, 0\n", 11,
                "*NODE in the *ASSEMBLY (a reference point) is not supported"},
        BadDeck{"solid element in assembly",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Element, type=C3D4\n", 11,
                "only springs and masses"},
        BadDeck{"plain node id in assembly set",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Instance, name=I, part=P\n"
                "*End Instance\n*Nset, nset=S\n1, 2\n",
                14, "plain node ids at assembly level"},
        BadDeck{"unknown instance",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Instance, name=I, part=P\n"
                "*End Instance\n*Nset, nset=S\nJ.1\n",
                14, "unknown instance J"},
        BadDeck{"unknown set of an instance",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n*Instance, name=I, part=P\n"
                "*End Instance\n*Nset, nset=S\nI.Nope\n*End Assembly\n",
                14, "unknown node set I.NOPE"},
        BadDeck{"rotation line",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n"
                "*Instance, name=I, part=P\n0, 0, 0\n0, 0, 0, 1, 1, 1\n",
                13, "the second data line is the rotation"},
        BadDeck{"zero axis",
                "*Part, name=P\n" TET "*End Part\n*Assembly\n"
                "*Instance, name=I, part=P\n0, 0, 0\n1, 1, 1, 1, 1, 1, 30\n",
                13, "the rotation axis has zero length"},
        BadDeck{"boundary in a part", "*Part, name=P\n" TET "*Boundary\n1, 1, 3\n", 9,
                "*BOUNDARY inside *PART P is not supported"},
        BadDeck{"flat mesh then parts", TET "*Part, name=P\n", 8,
                "after nodes or elements outside any part (line 2)"},
        BadDeck{"library instance", "*Assembly\n*Instance, name=I, library=L\n", 2,
                "substructure libraries are not supported"},
        BadDeck{"qualified id inside a part", "*Part, name=P\n" TET "*Nset, nset=S\nP.1\n", 10,
                "inside *PART P of line 1"}));

}  // namespace
}  // namespace stickslip

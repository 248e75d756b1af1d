// End-to-end: meshes read from .inp and .msh files whose elements cannot be integrated (inverted,
// flat, a misplaced mid-side node, a coordinate that is not a number) or whose node ids clash stop
// in `stickslip run` with exit 2 at the mesh file's line (issues 26 and 11.5(c)). Each damaged mesh
// is one edit of a valid one-element mesh that runs (checked first).
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

// A unit cube of one hexahedron clamped at z = 0, held along x by a spring to the ground at a top
// node and forced there; the mesh file is `mesh_file`.
std::string cube_case(const std::string& mesh_file) {
  return "stickslip: 1\n"
         "materials:\n"
         "  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}\n"
         "meshes:\n"
         "  m: {file: " +
         mesh_file +
         "}\n"
         "bodies:\n"
         "  b: {mesh: m, material: steel, clamp: [1, 2, 3, 4], masters: [5, 6, 7, 8], modes: 2}\n"
         "contacts:\n"
         "  - {name: g, law: linear, bodies: [b, ground], pairs: [7], direction: x,\n"
         "     per_pair: {k: 1.0e6}}\n"
         "excitation:\n"
         "  - {body: b, node: 7, direction: x, amplitude: 1}\n"
         "analysis:\n"
         "  frequency: {start_hz: 10, stop_hz: 20, step_hz: 5}\n"
         "recovery: {points: none}\n"
         "output: {plots: false, vtu: false}\n";
}

const std::string kCubeNodes =
    "1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, "
    "1\n";

std::string cube_inp(const std::string& nodes, const std::string& element) {
  return "** one hexahedron\n*NODE\n" + nodes + "*ELEMENT, TYPE=C3D8\n" + element + "\n";
}

// MSH 2.2 ASCII; nodes "tag x y z" lines, elements "tag type 2 1 1 nodes" lines.
std::string cube_msh(const std::vector<std::string>& nodes, const std::string& element) {
  std::string s =
      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" + std::to_string(nodes.size()) + "\n";
  for (const std::string& n : nodes) s += n + "\n";
  return s + "$EndNodes\n$Elements\n1\n" + element + "\n$EndElements\n";
}

const std::vector<std::string> kMshNodes{"1 0 0 0", "2 1 0 0", "3 1 1 0", "4 0 1 0",
                                         "5 0 0 1", "6 1 0 1", "7 1 1 1", "8 0 1 1"};

struct Outcome {
  int code = -1;
  std::string log;
};

Outcome run_mesh(const fs::path& dir, const std::string& mesh_name, const std::string& mesh_text) {
  std::ofstream(dir / mesh_name) << mesh_text;
  const fs::path file = write_case(dir, "case", cube_case(mesh_name));
  Outcome o;
  o.code = run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "log.txt");
  o.log = slurp(dir / "log.txt");
  return o;
}

void expect_refused(const Outcome& o, const std::string& where, const std::string& what) {
  EXPECT_EQ(o.code, 2) << o.log;
  EXPECT_NE(o.log.find(where), std::string::npos) << where << "\n" << o.log;
  EXPECT_NE(o.log.find(what), std::string::npos) << what << "\n" << o.log;
}

TEST(NonsenseMesh, InpElementsThatCannotBeIntegratedStopAtTheirLine) {
  const fs::path dir = fresh_dir("nonsense_inp");
  const std::string inp = (dir / "cube.inp").string();
  ASSERT_EQ(run_mesh(dir, "cube.inp", cube_inp(kCubeNodes, "1, 1, 2, 3, 4, 5, 6, 7, 8")).code, 0);
  // Line 12: the element (2 header lines + 8 nodes + *ELEMENT).
  expect_refused(run_mesh(dir, "cube.inp", cube_inp(kCubeNodes, "1, 5, 6, 7, 8, 1, 2, 3, 4")),
                 inp + ":12: ",
                 "element 1 (C3D8): Jacobian determinant -0.125 at an integration "
                 "point (det J > 0 needed): the element is inverted");
  std::string flat = kCubeNodes;
  for (const char* top : {"5, 0, 0, 1", "6, 1, 0, 1", "7, 1, 1, 1", "8, 0, 1, 1"}) {
    const std::string t(top);
    flat.replace(flat.find(t), t.size(), t.substr(0, t.size() - 1) + "0");
  }
  expect_refused(run_mesh(dir, "cube.inp", cube_inp(flat, "1, 1, 2, 3, 4, 5, 6, 7, 8")),
                 inp + ":12: ",
                 "element 1 (C3D8): Jacobian determinant 0 at an integration point "
                 "(det J > 0 needed): the element is flat");
  std::string nan = kCubeNodes;
  nan.replace(nan.find("7, 1, 1, 1"), 10, "7, 1, nan, 1");
  expect_refused(run_mesh(dir, "cube.inp", cube_inp(nan, "1, 1, 2, 3, 4, 5, 6, 7, 8")),
                 inp + ":9: ", "'nan' is not a valid coordinate");
  // A 10-node tetrahedron whose mid-side node of edge 1-2 lies beyond node 2.
  const std::string tet =
      "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 0, 1, 0\n4, 0, 0, 1\n5, 1.5, 0, 0\n6, 0.5, 0.5, 0\n"
      "7, 0, 0.5, 0\n8, 0, 0, 0.5\n9, 0.5, 0, 0.5\n10, 0, 0.5, 0.5\n*ELEMENT, TYPE=C3D10\n"
      "1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10\n";
  expect_refused(run_mesh(dir, "cube.inp", tet),
                 inp + ":13: ", "element 1 (C3D10): Jacobian determinant -");
  EXPECT_NE(slurp(dir / "log.txt")
                .find("the element is distorted (det J changes sign inside it: "
                      "a misplaced mid-side node"),
            std::string::npos)
      << slurp(dir / "log.txt");
}

TEST(NonsenseMesh, MshElementsAndNodesStopAtTheirLine) {
  const fs::path dir = fresh_dir("nonsense_msh");
  const std::string msh = (dir / "cube.msh").string();
  const std::string element = "1 5 2 1 1 1 2 3 4 5 6 7 8";
  ASSERT_EQ(run_mesh(dir, "cube.msh", cube_msh(kMshNodes, element)).code, 0);
  // Two nodes with tag 3: Gmsh kept one of them without a word.
  std::vector<std::string> nodes = kMshNodes;
  nodes.push_back("3 5 5 5");
  expect_refused(run_mesh(dir, "cube.msh", cube_msh(nodes, element)),
                 msh + ":14: ", "node tag 3 is defined twice (first on line 8)");
  // Line 17: the element.
  expect_refused(run_mesh(dir, "cube.msh", cube_msh(kMshNodes, "1 5 2 1 1 5 6 7 8 1 2 3 4")),
                 msh + ":17: ",
                 "element 1 (C3D8I): Jacobian determinant -0.125 at an "
                 "integration point (det J > 0 needed): the element is inverted");
  nodes = kMshNodes;
  for (int i = 4; i < 8; ++i) nodes[i].back() = '0';
  expect_refused(run_mesh(dir, "cube.msh", cube_msh(nodes, element)),
                 msh + ":17: ", "the element is flat");
  nodes = kMshNodes;
  nodes[6] = "7 1 nan 1";
  expect_refused(run_mesh(dir, "cube.msh", cube_msh(nodes, element)),
                 msh + ":12: ", "node 7: a coordinate is not a finite number");
  // A 10-node tetrahedron (Gmsh order: corners, then edges 1-2, 2-3, 3-1, 4-1, 4-3, 4-2) whose
  // mid-side node of edge 1-2 lies beyond node 2.
  const std::vector<std::string> tet{"1 0 0 0",     "2 1 0 0",     "3 0 1 0",   "4 0 0 1",
                                     "5 1.5 0 0",   "6 0.5 0.5 0", "7 0 0.5 0", "8 0 0 0.5",
                                     "9 0 0.5 0.5", "10 0.5 0 0.5"};
  expect_refused(run_mesh(dir, "cube.msh", cube_msh(tet, "1 11 2 1 1 1 2 3 4 5 6 7 8 9 10")),
                 msh + ":19: ", "element 1 (C3D10): Jacobian determinant -");
  EXPECT_NE(slurp(dir / "log.txt").find("the element is distorted"), std::string::npos)
      << slurp(dir / "log.txt");
}

}  // namespace

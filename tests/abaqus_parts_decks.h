// Two decks of the same L-shaped steel beam for the tests of Abaqus/CAE parts and instances: one
// as Abaqus/CAE writes it (*PART, *ASSEMBLY, two *INSTANCEs of one part, the second translated
// and rotated, assembly-level sets and *EQUATIONs with qualified names), one flat (what
// CalculiX reads), written with coordinates worked out by hand.
//
// The part BLOCK: 3 x 1 x 1 C3D8 cubes of 0.1 m along x, [0, 0.3] x [0, 0.1] x [0, 0.1]; node
// (i, j, k) of the 4 x 2 x 2 grid has id 1 + i + 4 (j + 2 k), element i + 1 spans i..i+1.
// BLOCK-1 is the part in place. BLOCK-2 is translated by t = (0.05, 0.02, 0) and then rotated by
// 90° about the axis through a = (0.135, 0.185, 0) along +z: a + R(x + t − a) with
// R (x, y) = (−y, x), which works out to (x, y, z) -> (0.3 − y, 0.1 + x, z): it stands on the
// end of BLOCK-1, along +y, its x = 0 face on BLOCK-1's top face, where four pairs of coincident
// nodes are tied by equations in x, y and z. FIX: BLOCK-1's x = 0 face (the part's set START);
// TIP: BLOCK-2's node (3, 0, 1). In the flat deck BLOCK-2's ids follow BLOCK-1's (+16 nodes, +3
// elements), as the reader numbers instances.
#pragma once

#include <sstream>
#include <string>

namespace stickslip::parts_decks {

inline int block_node(int i, int j, int k) { return 1 + i + 4 * (j + 2 * k); }

// The element lines "id, n1..n8" of the block with ids from first_element, nodes from
// first_node.
inline std::string block_elements(int first_element, int first_node) {
  std::ostringstream s;
  for (int i = 0; i < 3; ++i) {
    const auto n = [&](int a, int b, int c) { return first_node - 1 + block_node(a, b, c); };
    s << first_element + i << ", " << n(i, 0, 0) << ", " << n(i + 1, 0, 0) << ", " << n(i + 1, 1, 0)
      << ", " << n(i, 1, 0) << ", " << n(i, 0, 1) << ", " << n(i + 1, 0, 1) << ", "
      << n(i + 1, 1, 1) << ", " << n(i, 1, 1) << "\n";
  }
  return s.str();
}

// The 12 equations tying BLOCK-2's x = 0 face to BLOCK-1: BLOCK-2's (0, j, k) sits on BLOCK-1's
// (3 − j, 1, k). `b1`, `b2` write a node of each instance.
template <class Name1, class Name2>
std::string tie_equations(Name1 b1, Name2 b2) {
  std::ostringstream s;
  s << "*EQUATION\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int d = 1; d <= 3; ++d) {
        s << "2\n"
          << b2(block_node(0, j, k)) << ", " << d << ", 1.\n"
          << b1(block_node(3 - j, 1, k)) << ", " << d << ", -1.\n";
      }
  return s.str();
}

inline const char* const kMaterial = "*Material, name=Steel\n*Elastic\n2e11, 0.3\n*Density\n7800\n";

// As Abaqus/CAE writes it (mixed case, blanks, generate, a section in the part).
inline std::string part_deck() {
  std::ostringstream s;
  s.precision(17);
  s << "*Heading\n** Job name: L Model name: Model-1\n** PARTS\n**\n*Part, name=Block\n*Node\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 4; ++i)
        s << "  " << block_node(i, j, k) << ", " << 0.1 * i << ", " << 0.1 * j << ", " << 0.1 * k
          << "\n";
  s << "*Element, type=C3D8\n" << block_elements(1, 1);
  s << "*Nset, nset=Start\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) s << block_node(0, j, k) << ",\n";
  s << "*Elset, elset=All, generate\n 1, 3, 1\n";
  s << "** Section: Section-1\n*Solid Section, elset=All, material=Steel\n,\n*End Part\n";
  s << "**\n** ASSEMBLY\n**\n*Assembly, name=Assembly\n**\n";
  s << "*Instance, name=Block-1, part=Block\n*End Instance\n**\n";
  s << "*Instance, name=Block-2, part=Block\n 0.05, 0.02, 0.\n"
       " 0.135, 0.185, 0., 0.135, 0.185, 2., 90.\n*End Instance\n**\n";
  s << "*Nset, nset=FIX\n Block-1.Start\n";
  s << "*Nset, nset=TIP, instance=Block-2\n " << block_node(3, 0, 1) << ",\n";
  s << tie_equations([](int n) { return "Block-1." + std::to_string(n); },
                     [](int n) { return "Block-2." + std::to_string(n); });
  s << "*End Assembly\n** MATERIALS\n" << kMaterial;
  return s.str();
}

// The same beam flat, BLOCK-2's coordinates mapped by hand: (x, y, z) -> (0.3 − y, 0.1 + x, z).
inline std::string flat_deck() {
  std::ostringstream s;
  s.precision(17);
  s << "*NODE\n";
  for (int copy = 0; copy < 2; ++copy)
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) {
          const double x = 0.1 * i, y = 0.1 * j, z = 0.1 * k;
          s << 16 * copy + block_node(i, j, k) << ", " << (copy == 0 ? x : 0.3 - y) << ", "
            << (copy == 0 ? y : 0.1 + x) << ", " << z << "\n";
        }
  s << "*ELEMENT, TYPE=C3D8, ELSET=EALL\n" << block_elements(1, 1) << block_elements(4, 17);
  s << "*NSET, NSET=FIX\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j) s << block_node(0, j, k) << ",\n";
  s << "*NSET, NSET=TIP\n" << 16 + block_node(3, 0, 1) << "\n";
  s << tie_equations([](int n) { return std::to_string(n); },
                     [](int n) { return std::to_string(16 + n); });
  return s.str();
}

}  // namespace stickslip::parts_decks

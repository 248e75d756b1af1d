// The reference model of docs/conventions.md ("the reference case"): two identical cantilever beams
// whose half-thickness free ends touch, meshed with structured hexahedra through the Gmsh API
// (built-in "geo" kernel, transfinite curves/surfaces/volumes, recombined surfaces).
//
// Geometry (m). Beam 1: large box [0, L] x [0, W] x [0, T], clamped at x = 0, with the end block
// [L, L + e] x [0, W] x [0, T/2] (half thickness, flush with the z = 0 face).
//  - kButt: beam 2 is beam 1 mirrored in the plane x = L + e: end block [L+e, L+2e] x [0,W] x
//    [0,T/2], large box [L+2e, 2L+2e] x [0,W] x [0,T], clamped at x = 2L + 2e. Contact plane
//    x = L + e (W x T/2), normal +x.
//  - kLap: beam 2 is beam 1 turned by 180 degrees about the line x = L + e/2, z = T/2 (parallel to
//    y): end block [L, L+e] x [0,W] x [T/2,T], large box [L+e, 2L+e] x [0,W] x [0,T], clamped at
//    x = 2L + e. The end blocks overlap by e and touch on the face z = T/2 (e x W), normal +z.
//  The two beams have separate nodes everywhere (coincident ones at the contact face are paired).
//  In kLap the tip of each end block also lies against the other beam's step face (x = L and
//  x = L + e, W x T/2); those coincident faces are not paired (no contact there).
//
// Mesh of one beam. Conforming (default): the large box has box.x x box.y x box.z elements, of
// which end_block.z layers lie below mid-thickness and box.z − end_block.z above (uniform when
// box.z = 2 end_block.z); the end block has end_block.x x box.y x end_block.z elements and shares
// the nodes of its interface with the large box. Nodes per beam (8-node hexahedra):
// (bx+1)(by+1)(bz+1) + ex(by+1)(ez+1); elements bx by bz + ex by ez.
// thesis_coarse: the thesis's count, 7x5x1 large box + 4x5x4 end block meshed as two separate
// transfinite volumes that share only the nodes of their common edge (x = L, z = 0): 240 nodes and
// 115 elements per beam. Non-conforming: the end block hangs on the large box by that edge only.
// 20-node types give serendipity hexahedra (Gmsh's incomplete second order) on the same grid.
// Beam 2 may have its own divisions (beam2_box, beam2_end_block; same rules): its contact face is
// then meshed differently from beam 1's (non-matching: no node pairs, a contact needs mortar
// coupling). Unset, beam 2 is beam 1's mirror image, node for node.
//
// Numbering: beam 1's nodes and elements get ids 1..n1 and 1..e1, beam 2's n1+1.. and e1+1..
// (indices = ids − 1). Sets: element sets BEAM1, BEAM2; node sets BEAM1, BEAM2, CLAMP1 (x = 0),
// CLAMP2 (the far end of beam 2), CONTACT1, CONTACT2 (the contact face of each beam), FORCE1,
// FORCE2 (one node each).
// Forced nodes: beam 1's node at (L, 0, T), the top corner (y = 0) of the free end face of its
// large box, above the step (free in both arrangements, not a contact node), and its mirror on
// beam 2 under the map above: (L + 2e, 0, T) for kButt, (L + e, 0, 0) for kLap. The thesis loads
// them with +z (beam 1) and −z (beam 2); the load itself is the case file's business. (In kLap
// each forced node coincides with a tip corner of the other beam's end block, unpaired.)
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

struct BlockDivisions {
  int x = 1, y = 1, z = 1;  // elements along each axis
};

struct TwoBeamOptions {
  enum class Arrangement { kButt, kLap };
  Arrangement arrangement = Arrangement::kButt;
  double beam_length = 0.25;          // L: x extent of the large box, m
  double width = 0.05;                // W: y extent of both boxes, m
  double thickness = 0.03;            // T: z extent of the large box (end block: T/2), m
  double end_length = 0.05;           // e: x extent of the end block (and lap overlap), m
  BlockDivisions box{25, 5, 8};       // large box; conforming: box.z > end_block.z
  BlockDivisions end_block{5, 5, 4};  // end block; conforming: y must equal box.y
  // Beam 2's divisions where they differ from beam 1's (box, end_block when unset).
  std::optional<BlockDivisions> beam2_box, beam2_end_block;
  bool thesis_coarse = false;  // 7x5x1 + 4x5x4, only the shared edge merged; ignores the above
  ElementType element_type = ElementType::kC3D8I;  // a hexahedron type
};
// Throws InvalidInput naming the field, its value and the rule.
void validate(const TwoBeamOptions& options);

struct TwoBeamModel {
  Mesh mesh;  // both beams
  // (node index on beam 1, node index on beam 2), coincident, one per node of the contact face,
  // sorted by the beam-1 index; empty when beam 2's contact face is meshed differently.
  std::vector<std::pair<int, int>> contact_pairs;
  Eigen::Vector3d contact_normal;  // unit, out of beam 1 into beam 2
  int force_node_1 = -1;           // node indices (see the header comment)
  int force_node_2 = -1;
};

// Generates the model through the Gmsh API (opens and closes its own GmshSession).
TwoBeamModel make_two_beam_model(const TwoBeamOptions& options = {});

}  // namespace stickslip

// Writer of a Mesh as an Abaqus/CalculiX .inp mesh deck that read_inp() and ccx read back:
//   *NODE (id, x, y, z: the shortest text that round-trips when it fits CalculiX's 20 characters a
//     field, else 13 or more significant digits, io/apdl_macro.h decimal_in_width),
//   *ELEMENT, TYPE=<type> blocks, one per element type present (in index order within a type;
//     at most 16 numbers per line, a 20-node element continues on a second line),
//   *NSET, NSET=<name> and *ELSET, ELSET=<name> for every set (external ids, 16 per line),
//   *EQUATION for every Mesh::equations entry (4 terms a line, coefficients as coordinates),
//   every Mesh::springs entry as a SPRING1 / SPRING2 (along global axes) or SPRINGA element in
//   an element set SS_K<id> with its *SPRING, every point mass as MASS in SS_M<id> with *MASS.
// No material, section or step: the caller adds them (the stream form writes into a deck).
// Set names must be non-empty and contain no comma, '*', quote or line break (InvalidInput).
// The file form writes atomically (io/atomic_file.h).
#pragma once

#include <ostream>
#include <string>

#include "mesh/mesh.h"

namespace stickslip {

void write_inp(const std::string& path, const Mesh& mesh);
void write_inp(std::ostream& out, const Mesh& mesh);

}  // namespace stickslip

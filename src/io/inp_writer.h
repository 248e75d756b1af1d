// Writer of a Mesh as an Abaqus/CalculiX .inp mesh deck that read_inp() and ccx read back:
//   *NODE (id, x, y, z with 17 significant digits, so coordinates round-trip exactly),
//   *ELEMENT, TYPE=<type> blocks, one per element type present (in index order within a type;
//     at most 16 numbers per line, a 20-node element continues on a second line),
//   *NSET, NSET=<name> and *ELSET, ELSET=<name> for every set (external ids, 16 per line).
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

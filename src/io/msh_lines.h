// Where each node and element of an ASCII Gmsh .msh file is written, for messages: Gmsh's own
// reader (libgmsh) keeps no line numbers, and silently keeps one of two nodes that share a tag.
//
// scan_msh_lines reads the $MeshFormat, $Nodes and $Elements sections of an ASCII MSH 2.x or 4.1
// file and returns the line of each node tag (the line holding the tag) and of each element tag.
// A node tag or an element tag that appears twice throws InvalidInput at the second line, naming
// the first. Binary files and other versions (MSH 4.0) give empty maps (`scanned` false): their
// nodes and elements are then named without a line. Anything else the scan cannot follow (a
// truncated section, a count that is not a number) is left to Gmsh's reader, which reports it.
#pragma once

#include <cstddef>
#include <string>
#include <unordered_map>

namespace stickslip {

struct MshLines {
  bool scanned = false;                          // an ASCII MSH 2.x or 4.1 file was scanned
  std::unordered_map<std::size_t, int> node;     // node tag -> 1-based line
  std::unordered_map<std::size_t, int> element;  // element tag -> 1-based line
};

MshLines scan_msh_lines(const std::string& path);

}  // namespace stickslip

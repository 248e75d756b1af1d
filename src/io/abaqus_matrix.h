// Reader of the matrices Abaqus writes with *MATRIX GENERATE (and *SUBSTRUCTURE ... *MATRIX
// OUTPUT) in its matrix input text format, FORMAT=MATRIX INPUT, files jobname_STIF1.mtx and
// jobname_MASS1.mtx (not Matrix Market, despite the extension):
//   ** comment lines (Abaqus writes a header of them)
//   row node, row DOF, column node, column DOF, value
// one entry per line, commas and/or blanks between fields. For a symmetric matrix Abaqus writes
// one triangle; an entry given in both triangles must hold the same value (1e-10 relative), and
// the matrix is the symmetric one the entries define. The DOFs are nodal: DOF 1, 2, 3 are the x,
// y, z translations (a stickslip body has no others: DOFs 4-6, rotations, and other numbers are
// refused at their line, as are node labels that are not positive integers). Entries given
// twice are refused (Abaqus writes each once), as is a value that is not finite.
//
// The body's DOFs are the (node, DOF) pairs of both files, sorted by node and DOF; every one is
// physical (ReducedDof::node_id, direction). At most kMaxReducedBodyDofs (io/ansys_mapping.h)
// distinct DOFs: a larger file is refused at the entry that brings the count over the limit,
// before anything dense is allocated.
//
// Errors: InvalidInput with the file and line.
#pragma once

#include <istream>
#include <string>

#include "reduction/reduced_body.h"

namespace stickslip {

ReducedBody read_abaqus_reduced_body(const std::string& stiffness_path,
                                     const std::string& mass_path);
// Same, from streams; the names are used in messages.
ReducedBody read_abaqus_reduced_body(std::istream& stiffness, const std::string& stiffness_name,
                                     std::istream& mass, const std::string& mass_name);

}  // namespace stickslip

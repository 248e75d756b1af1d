// Reader of the mesh part of an Abaqus/CalculiX .inp deck.
//
// Understood keywords (case-insensitive, parameters separated by commas, spaces around names
// and values ignored, '**' comment lines and blank lines skipped anywhere):
//   *NODE [, NSET=name]                  lines "id, x[, y[, z]]" (missing coordinates = 0), m
//   *ELEMENT, TYPE=t [, ELSET=name]      lines "id, n1, n2, ..."; an element continues on the
//                                        following data line(s) until it has all its nodes
//                                        (20-node elements take two lines)
//   *NSET, NSET=name [, GENERATE]        node ids and/or names of node sets defined earlier;
//   *ELSET, ELSET=name [, GENERATE]      with GENERATE, lines "first, last[, increment]"
//   *EQUATION                            per equation: a line with the number of terms n, then
//                                        n terms "node id, direction (1-3), coefficient", any
//                                        number per line: Σ c_k u_k = 0, the first term's DOF
//                                        dependent (Mesh::equations, origin "file:line")
//   *BOUNDARY                            lines "node or set, first[, last[, value]]" or "node or
//                                        set, ENCASTRE|PINNED|XSYMM|YSYMM|ZSYMM", anywhere (also in
//                                        steps): recorded in Mesh::boundaries (a line that is not a
//                                        zero displacement carries why), applied only on request;
//                                        also listed in the skipped-keyword warning
//   *INCLUDE, INPUT=path                 the file's lines in place (textually: data lines continue
//                                        the keyword before the *INCLUDE); path relative to the
//                                        including file's folder; nested; a cycle is an error
//   *PART, NAME=p ... *END PART          Abaqus/CAE's parts: the nodes, elements, sets,
//                                        equations, springs, masses and sections inside are
//                                        the part's, used only through its instances
//   *ASSEMBLY ... *END ASSEMBLY          holds the instances and what joins them
//   *INSTANCE, NAME=i, PART=p            one copy of the part (plus any mesh given inside the
//     [dx, dy, dz]                       instance block), moved by the translation, then rotated
//     [ax, ay, az, bx, by, bz, angle]    by angle degrees about the axis from a to b (right-hand
//   *END INSTANCE                        rule). Its node and element ids follow the largest ids
//                                        of the instances (and assembly springs) above it (the
//                                        first instance keeps the part's ids); its sets are
//                                        named "I.SET" and the element set "I" holds its elements
//   In the assembly and the model: "I.12" names node (or element) 12 of instance I in sets,
//   *EQUATION, *BOUNDARY and SPRING/MASS elements; "I.SET" a set of instance I; *NSET/*ELSET
//   with INSTANCE=i take plain ids and set names of that instance. Nodes outside the parts
//   (reference points), solid elements outside the parts, *BOUNDARY/*MATERIAL/*STEP inside a
//   part or instance, instances of libraries, and a deck mixing a flat mesh and parts are
//   errors at their line; a part that no instance uses is a warning.
// Supported TYPE: C3D8, C3D8I, C3D8R (CalculiX's hourglass control), C3D8B (B-bar), C3D20,
// C3D20R, C3D4, C3D10, C3D6, C3D15, C3D5 and C3D13 (pyramids: stickslip's names; node order as
// in the .inp, which is Mesh's), and the discrete SPRING1, SPRING2, SPRINGA and MASS
// (ELSET= required):
//   *SPRING, ELSET=name                  for SPRING1/SPRING2 a line of DOFs (1-3; integers), then
//                                        the spring constant (N/m, a real); SPRINGA no DOF line
//   *MASS, ELSET=name                    the mass (kg)
// They become Mesh::springs and Mesh::point_masses (the element's line is their origin).
// Any other element type is rejected.
// Nothing vanishes silently: a keyword that would change the stiffness or mass and is not
// supported (*TIE, *COUPLING, *KINEMATIC, *MPC, *RIGID BODY, shell/beam sections, *DASHPOT,
// node/element generation, ...; list in inp_reader.cpp) is an
// error at its line. Every other keyword (*MATERIAL, *BOUNDARY, *STEP, ...) is skipped with its
// data lines and gives one warning per keyword name, "<file>: *NAME ignored (<why>), lines a, b",
// appended to `warnings` (when not null).
// Set names are case-insensitive in Abaqus/CalculiX and are stored upper-cased; repeating a set
// keyword with the same name adds to the set. Elements may refer to nodes defined later; a set
// may refer only to sets defined above it.
//
// Errors: InvalidInput with SourceLocation{file, line} (the included file's name and line when
// it lies in one) and what is wrong (bad number, unknown
// node in an element, duplicate id, missing set, wrong node count, unsupported type/parameter).
#pragma once

#include <istream>
#include <string>
#include <vector>

#include "mesh/mesh.h"

namespace stickslip {

Mesh read_inp(const std::string& path, std::vector<std::string>* warnings = nullptr);
// Same, from a stream; `source_name` is used as the file name in error messages.
Mesh read_inp(std::istream& in, const std::string& source_name,
              std::vector<std::string>* warnings = nullptr);

// `path` and every file it includes, directly or not (each once), for fingerprints of what a
// mesh depends on. A best-effort scan: files that cannot be read are listed and not followed
// (read_inp reports them).
std::vector<std::string> inp_files(const std::string& path);

}  // namespace stickslip

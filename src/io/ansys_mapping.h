// ANSYS HBMAT mapping files, and reduced bodies given by Harwell–Boeing matrices plus mapping (the
// thesis's workflow, appendix A.2: `hbmat` of a CMS superelement `.sub` file writes K2.txt,
// M2.txt and, with Mapping = YES, K2.mapping / M2.mapping).
//
// Mapping file: one header line (text, e.g. "Matrix Eqn   Node   DOF"), then one row per matrix
// equation, whitespace separated:
//     <matrix equation number, 1-based>  <node number>  <DOF label>
// Labels UX, UY, UZ are nodal translations (x, y, z); ROTX, ROTY, ROTZ nodal rotations. For a CMS
// superelement the generalised (modal) coordinates follow the nodal DOFs with labels of their own;
// ANSYS's public documentation does not spell them out, so every label that is not a nodal
// displacement or rotation is read as a generalised coordinate. stickslip writes them with node
// number 0 and label GEN. A file without a header line is accepted too.
//
// Malformed files throw InvalidInput naming the file, the line and what is wrong.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "reduction/reduced_body.h"

namespace stickslip {

struct AnsysMappingEntry {
  int equation = 0;   // 1-based matrix row/column
  int node = 0;       // node number (0 for stickslip-written generalised coordinates)
  std::string label;  // UX, UY, UZ, ROTX, ..., or a generalised-coordinate label
  int line = 0;       // line of the file it was read from (0: not read from a file)
};

struct AnsysMapping {
  std::vector<AnsysMappingEntry> entries;  // sorted: entries[k].equation == k + 1
};

enum class AnsysDofKind { kTranslation, kRotation, kGeneralized };
// kTranslation: *direction = 0, 1, 2 for UX, UY, UZ. Labels are case-insensitive.
AnsysDofKind classify_ansys_label(const std::string& label, int* direction);

// Equation numbers must be exactly 1..n, each once (rows may come in any order).
AnsysMapping read_ansys_mapping(const std::string& path);
AnsysMapping read_ansys_mapping(std::istream& in, const std::string& name);
void write_ansys_mapping(const std::string& path, const AnsysMapping& mapping);
void write_ansys_mapping(std::ostream& out, const AnsysMapping& mapping);

// `path` with its extension replaced by ".mapping" (ANSYS names the file Fname.mapping).
std::string ansys_mapping_path(const std::string& matrix_path);

// A reduced body from K, M (n x n, any source; taken as given, not symmetrised) and a parsed
// mapping with n entries: nodal translations become physical DOFs (node_id = node number,
// direction), generalised coordinates modal DOFs numbered in order with frequency_hz =
// sqrt(K_jj / M_jj) / 2π (0 when either is not positive). A rotation throws InvalidInput naming
// mapping_path and its line; sizes that disagree with the mapping throw InvalidInput too.
ReducedBody reduced_body_from_mapping(Eigen::MatrixXd K, Eigen::MatrixXd M,
                                      const AnsysMapping& mapping, const std::string& mapping_path);

// A reduced body from HBMAT exports: stiffness and mass in Harwell–Boeing (RSA or symmetric RUA)
// and the mapping (default: ansys_mapping_path(stiffness_path)). Nodal translations become
// physical DOFs (node_id = node number, direction); generalised coordinates become modal DOFs
// numbered in order, with frequency_hz = sqrt(K_jj / M_jj) / 2π — the fixed-interface natural
// frequency when the modes are mass-normalised and K_r's modal block is diagonal, as in a
// Craig–Bampton superelement. Nodal rotations are rejected (stickslip bodies are solids).
ReducedBody read_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                                    const std::string& mapping_path = "");

// Writes K and M as RSA Harwell–Boeing files and, next to each, its mapping file
// (ansys_mapping_path). Physical DOFs need node_id set (external node numbers).
void write_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                              const ReducedBody& body);

}  // namespace stickslip

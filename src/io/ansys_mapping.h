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

// Equation numbers must be exactly 1..n, each once (rows may come in any order); a nodal DOF
// (node, UX..ROTZ) at most once; a label of U or ROT plus at most one character that is not one of
// the six nodal labels ("UQ") is refused as a misspelt nodal DOF. Errors name the file and line.
AnsysMapping read_ansys_mapping(const std::string& path);
AnsysMapping read_ansys_mapping(std::istream& in, const std::string& name);
void write_ansys_mapping(const std::string& path, const AnsysMapping& mapping);
void write_ansys_mapping(std::ostream& out, const AnsysMapping& mapping);

// `path` with its extension replaced by ".mapping" (ANSYS names the file Fname.mapping).
std::string ansys_mapping_path(const std::string& matrix_path);

// Largest reduced body stickslip reads or makes, in DOFs (rows of the mapping; boundary DOFs plus
// modes of a Craig–Bampton body). A CMS superelement has a few thousand DOFs at most, and K_r and
// M_r are held dense (n x n doubles): 20000 DOFs already take 3.2 GB per matrix, and the modes of
// the assembled model cost O(n³). A larger count is a wrong file (or a mesh body with far too
// many master nodes or modes) and is refused before anything of that size is allocated.
inline constexpr int kMaxReducedBodyDofs = 20000;
// "a reduced body of n DOFs needs dense K and M of <bytes> each (n² x 8 bytes): at most 20000
// DOFs (3.2 GB each) are accepted", for the InvalidInput of a body above kMaxReducedBodyDofs.
std::string reduced_body_size_message(long long n);
// Throws InvalidInput at the row of equation kMaxReducedBodyDofs + 1 of `mapping` (read from
// `mapping_path`) when it has more than kMaxReducedBodyDofs equations.
void check_reduced_body_size(const AnsysMapping& mapping, const std::string& mapping_path);

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
// The mapping is read first: more than kMaxReducedBodyDofs equations are refused (at the first
// row beyond the limit) before the matrices are read, and matrices whose NROW/NCOL (line 3) are
// not the mapping's count are refused before the dense K_r, M_r are allocated.
ReducedBody read_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                                    const std::string& mapping_path = "");

// Writes K and M as RSA Harwell–Boeing files and, next to each, its mapping file
// (ansys_mapping_path). Physical DOFs need node_id set (external node numbers).
void write_ansys_reduced_body(const std::string& stiffness_path, const std::string& mass_path,
                              const ReducedBody& body);

// Writes K and M as symmetric coordinate Matrix Market files (lower triangle, full double
// precision; what SciPy's scipy.io.mmread reads, unlike symmetric Harwell–Boeing files that
// scipy.io.hb_read refuses) and `mapping_path` with the ANSYS mapping of the DOFs (as
// write_ansys_reduced_body). Read back by `reduced: {format: matrix_market, mapping: ...}`.
// K and M must be symmetric (io/matrix_market.h's test); InvalidInput otherwise.
void write_matrix_market_reduced_body(const std::string& stiffness_path,
                                      const std::string& mass_path,
                                      const std::string& mapping_path, const ReducedBody& body);

}  // namespace stickslip

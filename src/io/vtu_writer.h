// VTK XML UnstructuredGrid (.vtu) output for ParaView, written atomically (io/atomic_file.h).
//
// Cells: C3D8/C3D8I -> VTK_HEXAHEDRON (12), C3D20/C3D20R -> VTK_QUADRATIC_HEXAHEDRON (25),
// C3D4 -> VTK_TETRA (10), C3D10 -> VTK_QUADRATIC_TETRA (24). VTK's local node orders coincide with
// CalculiX's for these four cells (VTK's quadratic hexahedron: corners, then mid-edge nodes on
// (0,1) (1,2) (2,3) (3,0) (4,5) (5,6) (6,7) (7,4) (0,4) (1,5) (2,6) (3,7); quadratic tetrahedron:
// (0,1) (1,2) (2,0) (0,3) (1,3) (2,3)), so connectivity is written as stored. (CalculiX's .frd
// result files order the 20-node hexahedron differently; that is not this file's concern.)
//
// Data: point fields have one column per node, cell fields one per element, rows = components
// (1 scalar, 3 vector; 6 = symmetric tensor in VTK/ParaView order xx, yy, zz, xy, yz, xz; any
// other count is written as is). Float64. Always written besides: point data "node_id" and cell
// data "element_id" (Int32, the external ids). Field data: named scalars (e.g. the frequency of a
// mode shape, "mode_1_frequency_hz"), Float64.
// Encoding: zlib-compressed appended raw data (the default: VTK's `compressor=
// "vtkZLibDataCompressor"`, one `<AppendedData encoding="raw">` section after the XML, per array
// a UInt64 block header and zlib blocks of 32 KiB; bit-exact, and 2-4 times smaller than base64),
// ASCII (17 significant digits) or base64 "binary" (VTK's inline binary format: per array one
// base64 stream of a UInt64 byte count followed by the raw machine-order values).
// Bad input (field size mismatch, empty or duplicate name) throws InvalidInput naming the field.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mesh/mesh.h"

namespace stickslip {

struct VtuField {
  std::string name;
  Eigen::MatrixXd values;  // components x (num_nodes or num_elements)
};

struct VtuData {
  std::vector<VtuField> point_data;
  std::vector<VtuField> cell_data;
  std::vector<std::pair<std::string, double>> field_data;
};

enum class VtuEncoding { kAscii, kBase64, kZlibAppended };

// VTK cell type number of an element type (12, 25, 10, 24).
int vtk_cell_type(ElementType type);

void write_vtu(const std::string& path, const Mesh& mesh, const VtuData& data,
               VtuEncoding encoding = VtuEncoding::kZlibAppended);

// Points without a mesh (e.g. contact points), each one VTK_VERTEX cell (element_id 1..n, in
// order); `ids` become point data "node_id". Same data rules and encodings as write_vtu.
void write_vtu_points(const std::string& path, const Eigen::Matrix3Xd& coordinates,
                      const std::vector<int>& ids, const VtuData& data,
                      VtuEncoding encoding = VtuEncoding::kZlibAppended);

// Collections of files written by write_vtu, for ParaView; `file` paths are relative to the
// collection's own folder, written as given (XML-escaped). Atomic.
// A multiblock file (.vtm): one named block per entry, in order.
struct VtmBlock {
  std::string name;
  std::string file;
};
void write_vtm(const std::string& path, const std::vector<VtmBlock>& blocks);
// A ParaView data collection (.pvd): each entry a dataset at a time value; several datasets at one
// time are told apart by `part` (ParaView shows them as blocks of one multiblock).
struct PvdEntry {
  double time = 0.0;
  int part = 0;
  std::string name;
  std::string file;
};
void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries);

}  // namespace stickslip

#include "io/vtu_writer.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <set>
#include <vector>

#include <zlib.h>

#include "core/errors.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void base64_encode(std::ostream& out, const std::vector<unsigned char>& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  size_t i = 0;
  std::string chunk;
  chunk.reserve(4 * (bytes.size() / 3 + 1));
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    chunk += kAlphabet[(v >> 18) & 63];
    chunk += kAlphabet[(v >> 12) & 63];
    chunk += kAlphabet[(v >> 6) & 63];
    chunk += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (bytes[i] << 16) | (two ? bytes[i + 1] << 8 : 0);
    chunk += kAlphabet[(v >> 18) & 63];
    chunk += kAlphabet[(v >> 12) & 63];
    chunk += two ? kAlphabet[(v >> 6) & 63] : '=';
    chunk += '=';
  }
  out << chunk;
}

template <typename T>
const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

// Bytes per zlib block of a compressed array (VTK's own default) and the compression level:
// level 1 compresses a field of doubles nearly as well as the default level 6 (rounding noise in
// the low bits does not compress at any level) at several times its speed.
constexpr std::size_t kZlibBlockBytes = 1 << 15;
constexpr int kZlibLevel = 1;

template <typename T>
void append_bytes(std::vector<unsigned char>& to, const T& value) {
  const auto* p = reinterpret_cast<const unsigned char*>(&value);
  to.insert(to.end(), p, p + sizeof(T));
}

// VTK's compressed layout of one array: UInt64 header [number of blocks, uncompressed block
// size, uncompressed size of the last block (0: a full block), compressed size of each block],
// then the blocks, each compressed by zlib on its own.
void append_compressed(std::vector<unsigned char>& to, const unsigned char* data,
                       std::size_t size) {
  const std::uint64_t blocks = (size + kZlibBlockBytes - 1) / kZlibBlockBytes;
  const std::uint64_t last = size % kZlibBlockBytes;
  std::vector<std::uint64_t> sizes;
  std::vector<unsigned char> compressed;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::size_t n = std::min(kZlibBlockBytes, size - b * kZlibBlockBytes);
    uLongf bound = compressBound(static_cast<uLong>(n));
    const std::size_t at = compressed.size();
    compressed.resize(at + bound);
    const int rc = compress2(compressed.data() + at, &bound, data + b * kZlibBlockBytes,
                             static_cast<uLong>(n), kZlibLevel);
    STICKSLIP_VERIFY(rc == Z_OK, "zlib compress2 failed");
    compressed.resize(at + bound);
    sizes.push_back(bound);
  }
  append_bytes(to, blocks);
  append_bytes(to, static_cast<std::uint64_t>(kZlibBlockBytes));
  append_bytes(to, last);
  for (std::uint64_t c : sizes) append_bytes(to, c);
  to.insert(to.end(), compressed.begin(), compressed.end());
}

class ArrayWriter {
 public:
  ArrayWriter(std::ostream& out, VtuEncoding encoding) : out_(out), encoding_(encoding) {}

  // The appended section of kZlibAppended (after the XML; offsets count from its first byte).
  const std::vector<unsigned char>& appended() const { return appended_; }

  template <typename T>
  void write(const std::string& name, int components, const std::vector<T>& values,
             const std::string& indent) {
    out_ << indent << "<DataArray type=\"" << vtk_type_name<T>() << "\"";
    if (!name.empty()) out_ << " Name=\"" << xml_escape(name) << "\"";
    if (components != 1) out_ << " NumberOfComponents=\"" << components << "\"";
    if (encoding_ == VtuEncoding::kZlibAppended) {
      out_ << " format=\"appended\" offset=\"" << appended_.size() << "\"/>\n";
      append_compressed(appended_, reinterpret_cast<const unsigned char*>(values.data()),
                        values.size() * sizeof(T));
      return;
    }
    out_ << " format=\"" << (encoding_ == VtuEncoding::kAscii ? "ascii" : "binary") << "\">\n"
         << indent << "  ";
    if (encoding_ == VtuEncoding::kAscii) {
      for (size_t i = 0; i < values.size(); ++i) {
        if constexpr (std::is_same_v<T, std::uint8_t>) {
          out_ << static_cast<int>(values[i]);
        } else {
          out_ << values[i];
        }
        out_ << ((i + 1) % 12 == 0 && i + 1 < values.size() ? "\n  " + indent : " ");
      }
    } else {
      const std::uint64_t size = values.size() * sizeof(T);
      std::vector<unsigned char> bytes(sizeof(size) + size);
      std::memcpy(bytes.data(), &size, sizeof(size));
      if (size > 0) std::memcpy(bytes.data() + sizeof(size), values.data(), size);
      base64_encode(out_, bytes);
    }
    out_ << "\n" << indent << "</DataArray>\n";
  }

 private:
  std::ostream& out_;
  VtuEncoding encoding_;
  std::vector<unsigned char> appended_;
};

void check_fields(const std::vector<VtuField>& fields, int count, const char* kind,
                  const char* reserved) {
  std::set<std::string> names{reserved};
  for (const VtuField& f : fields) {
    if (f.name.empty())
      throw InvalidInput(std::string("vtu writer: a ") + kind + " field has no name");
    if (!names.insert(f.name).second) {
      throw InvalidInput(std::string("vtu writer: ") + kind + " field name '" + f.name +
                         "' is used twice (or is reserved)");
    }
    if (f.values.cols() != count || f.values.rows() < 1) {
      throw InvalidInput(std::string("vtu writer: ") + kind + " field '" + f.name + "' is " +
                         std::to_string(f.values.rows()) + " x " + std::to_string(f.values.cols()) +
                         ", needs components x " + std::to_string(count));
    }
  }
}

std::vector<double> column_major(const Eigen::MatrixXd& m) {
  return std::vector<double>(m.data(), m.data() + m.size());
}

// Connectivity in VTK's node order. Identical to CalculiX's for every type but the wedges:
// VTK's wedge has its first triangle ordered so that its right-hand normal points away from the
// second (vtkWedge), CalculiX's towards it, so nodes 1 ↔ 2 and 4 ↔ 5 swap (and with them the
// mid-edge nodes of the quadratic wedge).
std::vector<std::int64_t> vtk_connectivity(const Mesh& mesh) {
  static constexpr int kWedge[15] = {0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13};
  std::vector<std::int64_t> c(mesh.connectivity.begin(), mesh.connectivity.end());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const ElementType t = mesh.element_types[static_cast<size_t>(e)];
    if (t != ElementType::kC3D6 && t != ElementType::kC3D15) continue;
    const std::span<const int> nodes = mesh.element_nodes(e);
    const size_t first = static_cast<size_t>(mesh.element_offsets[static_cast<size_t>(e)]);
    for (size_t a = 0; a < nodes.size(); ++a) c[first + a] = nodes[static_cast<size_t>(kWedge[a])];
  }
  return c;
}

}  // namespace

int vtk_cell_type(ElementType type) {
  switch (type) {
    case ElementType::kC3D8:
    case ElementType::kC3D8I:
    case ElementType::kC3D8B:
    case ElementType::kC3D8R:
      return 12;
    case ElementType::kC3D20:
    case ElementType::kC3D20R:
      return 25;
    case ElementType::kC3D4:
      return 10;
    case ElementType::kC3D10:
      return 24;
    case ElementType::kC3D6:  // VTK_WEDGE and VTK_QUADRATIC_WEDGE: CalculiX's node order
      return 13;
    case ElementType::kC3D15:
      return 26;
    case ElementType::kC3D5:  // VTK_PYRAMID: base 0-3 with its normal towards the apex 4, as ours
      return 14;
    case ElementType::kC3D13:  // VTK_QUADRATIC_PYRAMID: corners as C3D5, then mid-edge nodes on
      return 27;               // (0,1) (1,2) (2,3) (3,0) (0,4) (1,4) (2,4) (3,4), as ours
  }
  return 0;
}

namespace {

// The cells of an unstructured grid as VTK stores them.
struct VtkCells {
  std::vector<std::int64_t> connectivity, offsets;  // offsets: end of each cell
  std::vector<std::uint8_t> types;
  std::vector<std::int32_t> ids;  // written as cell data "element_id"
};

void write_grid(const std::string& path, const Eigen::Matrix3Xd& coordinates,
                const std::vector<int>& node_ids, const VtkCells& cells, const VtuData& data,
                VtuEncoding encoding) {
  const int num_points = static_cast<int>(coordinates.cols());
  const int num_cells = static_cast<int>(cells.types.size());
  check_fields(data.point_data, num_points, "point", "node_id");
  check_fields(data.cell_data, num_cells, "cell", "element_id");
  {
    std::set<std::string> names;
    for (const auto& [name, value] : data.field_data) {
      if (name.empty() || !names.insert(name).second) {
        throw InvalidInput("vtu writer: field data name '" + name + "' is empty or used twice");
      }
    }
  }
  write_file_atomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    ArrayWriter arrays(out, encoding);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
        << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
        << "\" header_type=\"UInt64\""
        << (encoding == VtuEncoding::kZlibAppended ? " compressor=\"vtkZLibDataCompressor\"" : "")
        << ">\n"
        << "  <UnstructuredGrid>\n";
    if (!data.field_data.empty()) {
      out << "    <FieldData>\n";
      for (const auto& [name, value] : data.field_data) {
        out << "      <DataArray type=\"Float64\" Name=\"" << xml_escape(name)
            << "\" NumberOfTuples=\"1\" format=\"ascii\">" << value << "</DataArray>\n";
      }
      out << "    </FieldData>\n";
    }
    out << "    <Piece NumberOfPoints=\"" << num_points << "\" NumberOfCells=\"" << num_cells
        << "\">\n";
    const std::string in = "        ";
    out << "      <PointData>\n";
    arrays.write("node_id", 1, std::vector<std::int32_t>(node_ids.begin(), node_ids.end()), in);
    for (const VtuField& f : data.point_data) {
      arrays.write(f.name, static_cast<int>(f.values.rows()), column_major(f.values), in);
    }
    out << "      </PointData>\n      <CellData>\n";
    arrays.write("element_id", 1, cells.ids, in);
    for (const VtuField& f : data.cell_data) {
      arrays.write(f.name, static_cast<int>(f.values.rows()), column_major(f.values), in);
    }
    out << "      </CellData>\n      <Points>\n";
    arrays.write("Points", 3, column_major(coordinates), in);
    out << "      </Points>\n      <Cells>\n";
    arrays.write("connectivity", 1, cells.connectivity, in);
    arrays.write("offsets", 1, cells.offsets, in);
    arrays.write("types", 1, cells.types, in);
    out << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
    if (encoding == VtuEncoding::kZlibAppended) {
      out << "  <AppendedData encoding=\"raw\">\n   _";
      const std::vector<unsigned char>& bytes = arrays.appended();
      out.write(reinterpret_cast<const char*>(bytes.data()),
                static_cast<std::streamsize>(bytes.size()));
      out << "\n  </AppendedData>\n";
    }
    out << "</VTKFile>\n";
  });
}

}  // namespace

void write_vtu(const std::string& path, const Mesh& mesh, const VtuData& data,
               VtuEncoding encoding) {
  check_mesh(mesh);
  VtkCells cells;
  cells.connectivity = vtk_connectivity(mesh);
  cells.offsets.assign(mesh.element_offsets.begin() + 1, mesh.element_offsets.end());
  cells.types.reserve(mesh.element_types.size());
  for (ElementType t : mesh.element_types)
    cells.types.push_back(static_cast<std::uint8_t>(vtk_cell_type(t)));
  cells.ids.assign(mesh.element_ids.begin(), mesh.element_ids.end());
  write_grid(path, mesh.coordinates, mesh.node_ids, cells, data, encoding);
}

void write_vtu_points(const std::string& path, const Eigen::Matrix3Xd& coordinates,
                      const std::vector<int>& ids, const VtuData& data, VtuEncoding encoding) {
  if (static_cast<Eigen::Index>(ids.size()) != coordinates.cols()) {
    throw InvalidInput("vtu writer: " + std::to_string(ids.size()) + " point ids for " +
                       std::to_string(coordinates.cols()) + " points");
  }
  if (!coordinates.allFinite()) throw InvalidInput("vtu writer: a point is not finite");
  constexpr std::uint8_t kVtkVertex = 1;
  VtkCells cells;
  const std::int64_t n = coordinates.cols();
  for (std::int64_t i = 0; i < n; ++i) {
    cells.connectivity.push_back(i);
    cells.offsets.push_back(i + 1);
    cells.types.push_back(kVtkVertex);
    cells.ids.push_back(static_cast<std::int32_t>(i + 1));
  }
  write_grid(path, coordinates, ids, cells, data, encoding);
}

void write_vtm(const std::string& path, const std::vector<VtmBlock>& blocks) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"vtkMultiBlockDataSet\" version=\"1.0\">\n"
        << "  <vtkMultiBlockDataSet>\n";
    for (size_t i = 0; i < blocks.size(); ++i) {
      out << "    <DataSet index=\"" << i << "\" name=\"" << xml_escape(blocks[i].name)
          << "\" file=\"" << xml_escape(blocks[i].file) << "\"/>\n";
    }
    out << "  </vtkMultiBlockDataSet>\n</VTKFile>\n";
  });
}

void write_pvd(const std::string& path, const std::vector<PvdEntry>& entries) {
  write_file_atomically(path, [&](std::ostream& out) {
    out.precision(std::numeric_limits<double>::max_digits10);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\">\n"
        << "  <Collection>\n";
    for (const PvdEntry& e : entries) {
      out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part
          << "\" name=\"" << xml_escape(e.name) << "\" file=\"" << xml_escape(e.file)
          << "\"/>\n";
    }
    out << "  </Collection>\n</VTKFile>\n";
  });
}

}  // namespace stickslip

#include "io/vtu_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/errors.h"

namespace stickslip {
namespace {

// ASCII output has 17 significant digits and binary output is bit-exact.
constexpr double kRoundTripTolerance = 0.0;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("stickslip_vtu_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// An independent reader: Python's xml.etree parses the file (so it must be well-formed XML) and
// decodes every DataArray (ASCII, or base64 with a UInt64 byte-count header as VTK reads it).
// Output, one line per array: "<section>\t<name>\t<type>\t<components>\t<count>\tv1 v2 ...".
constexpr const char* kPythonReader = R"PY(
import base64, struct, sys, zlib
import xml.etree.ElementTree as ET
data = open(sys.argv[1], 'rb').read()
cut = data.find(b'<AppendedData')
blob = b''
if cut >= 0:
    assert b'encoding="raw"' in data[cut:cut + 40]
    blob = data[data.index(b'_', cut) + 1:]
    data = data[:cut] + b'</VTKFile>'
root = ET.fromstring(data)
assert root.tag == 'VTKFile' and root.get('type') == 'UnstructuredGrid', root.tag
def appended(offset):  # VTK's zlib layout: UInt64 header [blocks, size, last, sizes...], blocks
    blocks, size, last = struct.unpack_from('<3Q', blob, offset)
    sizes = struct.unpack_from('<%dQ' % blocks, blob, offset + 24)
    at, raw = offset + 24 + 8 * blocks, b''
    for b, c in enumerate(sizes):
        chunk = zlib.decompress(blob[at:at + c])
        assert len(chunk) == (last if b == blocks - 1 and last else size), (len(chunk), b)
        raw += chunk
        at += c
    return raw
assert root.get('byte_order') == 'LittleEndian' and root.get('header_type') == 'UInt64'
fmt = {'Float64': 'd', 'Int64': 'q', 'Int32': 'i', 'UInt8': 'B'}
grid = root.find('UnstructuredGrid')
piece = grid.find('Piece')
out = open(sys.argv[2], 'w')
out.write('piece %s %s\n' % (piece.get('NumberOfPoints'), piece.get('NumberOfCells')))
def dump(section, arrays):
    for a in arrays:
        t = a.get('type'); text = (a.text or '').strip()
        if a.get('format') == 'appended':
            assert root.get('compressor') == 'vtkZLibDataCompressor'
            raw = appended(int(a.get('offset')))
            values = struct.unpack('<%d%s' % (len(raw) // struct.calcsize(fmt[t]), fmt[t]), raw)
        elif a.get('format') == 'binary':
            raw = base64.b64decode(text)
            (nbytes,) = struct.unpack('<Q', raw[:8])
            assert nbytes == len(raw) - 8, (nbytes, len(raw))
            values = struct.unpack('<%d%s' % (nbytes // struct.calcsize(fmt[t]), fmt[t]), raw[8:])
        else:
            assert a.get('format') == 'ascii'
            values = [float(v) if t == 'Float64' else int(v) for v in text.split()]
        out.write('%s\t%s\t%s\t%s\t%d\t%s\n' % (section, a.get('Name'), t,
                  a.get('NumberOfComponents', '1'), len(values), ' '.join(repr(v) for v in values)))
if grid.find('FieldData') is not None:
    dump('field', grid.find('FieldData').findall('DataArray'))
for section in ['PointData', 'CellData', 'Points', 'Cells']:
    dump(section, piece.find(section).findall('DataArray'))
)PY";

struct Array {
  std::string type;
  int components = 0;
  std::vector<double> values;
};

struct ParsedVtu {
  int points = -1, cells = -1;
  std::map<std::string, Array> arrays;  // key "<section>/<name>"
};

ParsedVtu parse_with_python(const std::string& vtu) {
  const std::string script = temp_path("reader.py");
  const std::string dump = temp_path("dump.txt");
  std::ofstream(script) << kPythonReader;
  const std::string command = "/usr/bin/python3 " + script + " " + vtu + " " + dump;
  const int status = std::system(command.c_str());
  std::filesystem::remove(script);
  EXPECT_EQ(status, 0) << "the Python XML reader rejected " << vtu;
  ParsedVtu parsed;
  std::ifstream in(dump);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string section, name, type, components, count;
    std::getline(s, section, '\t');
    if (section.rfind("piece", 0) == 0) {
      std::istringstream(section.substr(5)) >> parsed.points >> parsed.cells;
      continue;
    }
    std::getline(s, name, '\t');
    std::getline(s, type, '\t');
    std::getline(s, components, '\t');
    std::getline(s, count, '\t');
    Array a;
    a.type = type;
    a.components = std::stoi(components);
    a.values.resize(std::stoul(count));
    for (double& v : a.values) s >> v;
    EXPECT_FALSE(s.fail()) << line.substr(0, 80);
    parsed.arrays[section + "/" + name] = a;
  }
  std::filesystem::remove(dump);
  return parsed;
}

// One element of each type, on separate nodes, with straight edges: hex8 and hex20 on unit
// cubes, tet4 and tet10 on the unit corner tetrahedron, all in CalculiX order.
Mesh one_of_each() {
  Mesh m;
  const Eigen::Vector3d cube[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int hex_edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const Eigen::Vector3d tet[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int tet_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  int id = 1;
  auto add = [&](ElementType type, Eigen::Vector3d shift) {
    std::vector<int> nodes;
    const bool hex = type == ElementType::kC3D8 || type == ElementType::kC3D20;
    const int corners = hex ? 8 : 4;
    for (int i = 0; i < corners; ++i)
      nodes.push_back(m.add_node(id++, (hex ? cube[i] : tet[i]) + shift));
    if (type == ElementType::kC3D20) {
      for (const auto& e : hex_edges) {
        nodes.push_back(m.add_node(id++, 0.5 * (cube[e[0]] + cube[e[1]]) + shift));
      }
    }
    if (type == ElementType::kC3D10) {
      for (const auto& e : tet_edges) {
        nodes.push_back(m.add_node(id++, 0.5 * (tet[e[0]] + tet[e[1]]) + shift));
      }
    }
    m.add_element(10 * m.num_elements() + 7, type, nodes);
  };
  add(ElementType::kC3D8, {0, 0, 0});
  add(ElementType::kC3D20, {2, 0, 0});
  add(ElementType::kC3D4, {4, 0, 0});
  add(ElementType::kC3D10, {6, 0, 0});
  return m;
}

VtuData sample_data(const Mesh& m) {
  VtuData d;
  VtuField temperature{"temperature", Eigen::MatrixXd(1, m.num_nodes())};
  VtuField mode{"mode_1", Eigen::MatrixXd(3, m.num_nodes())};
  for (int n = 0; n < m.num_nodes(); ++n) {
    temperature.values(0, n) = 1.0 / (n + 3.0);
    mode.values.col(n) = m.coordinates.col(n) * 0.1 + Eigen::Vector3d(1e-300, -2.5, 1e10);
  }
  VtuField stress{"stress <von Mises> & co", Eigen::MatrixXd(6, m.num_elements())};
  for (int e = 0; e < m.num_elements(); ++e) {
    for (int k = 0; k < 6; ++k) stress.values(k, e) = 1e8 * (e + 1) + k / 7.0;
  }
  d.point_data = {temperature, mode};
  d.cell_data = {stress};
  d.field_data = {{"mode_1_frequency_hz", 1853.9123456789}};
  return d;
}

void check_file(const std::string& path, const Mesh& m, const VtuData& d) {
  const ParsedVtu p = parse_with_python(path);
  ASSERT_EQ(p.points, m.num_nodes());
  ASSERT_EQ(p.cells, m.num_elements());

  // Cells: VTK types, offsets and connectivity.
  const Array& types = p.arrays.at("Cells/types");
  EXPECT_EQ(types.type, "UInt8");
  EXPECT_EQ(types.values, (std::vector<double>{12, 25, 10, 24}));
  EXPECT_EQ(p.arrays.at("Cells/offsets").values, (std::vector<double>{8, 28, 32, 42}));
  const Array& connectivity = p.arrays.at("Cells/connectivity");
  ASSERT_EQ(connectivity.values.size(), m.connectivity.size());
  for (size_t i = 0; i < m.connectivity.size(); ++i) {
    EXPECT_EQ(connectivity.values[i], m.connectivity[i]);
  }
  const Array& points = p.arrays.at("Points/Points");
  ASSERT_EQ(points.components, 3);
  ASSERT_EQ(points.values.size(), static_cast<size_t>(3 * m.num_nodes()));

  // VTK's own node order (vtkQuadraticHexahedron.h, vtkQuadraticTetra.h): the mid-edge nodes of
  // the written cells must lie at the midpoints of VTK's edges.
  const int vtk_hex20_edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                      {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  const int vtk_tet10_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  auto point = [&](size_t cell_start, int local) {
    const int n = static_cast<int>(connectivity.values[cell_start + local]);
    return Eigen::Vector3d(points.values[3 * n], points.values[3 * n + 1],
                           points.values[3 * n + 2]);
  };
  for (int k = 0; k < 12; ++k) {
    EXPECT_EQ(point(8, 8 + k),
              0.5 * (point(8, vtk_hex20_edges[k][0]) + point(8, vtk_hex20_edges[k][1])));
  }
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(point(32, 4 + k),
              0.5 * (point(32, vtk_tet10_edges[k][0]) + point(32, vtk_tet10_edges[k][1])));
  }
  for (int n = 0; n < m.num_nodes(); ++n) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(points.values[3 * n + c], m.coordinates(c, n), kRoundTripTolerance);
    }
  }

  // Data arrays: ids, fields (component-interleaved), field data.
  const Array& node_id = p.arrays.at("PointData/node_id");
  EXPECT_EQ(node_id.type, "Int32");
  for (int n = 0; n < m.num_nodes(); ++n) EXPECT_EQ(node_id.values[n], m.node_ids[n]);
  const Array& element_id = p.arrays.at("CellData/element_id");
  for (int e = 0; e < m.num_elements(); ++e) EXPECT_EQ(element_id.values[e], m.element_ids[e]);
  auto check_field = [&](const std::string& key, const VtuField& f) {
    const Array& a = p.arrays.at(key);
    EXPECT_EQ(a.type, "Float64");
    EXPECT_EQ(a.components, f.values.rows());
    ASSERT_EQ(a.values.size(), static_cast<size_t>(f.values.size()));
    for (Eigen::Index j = 0; j < f.values.cols(); ++j) {
      for (Eigen::Index c = 0; c < f.values.rows(); ++c) {
        EXPECT_NEAR(a.values[j * f.values.rows() + c], f.values(c, j), kRoundTripTolerance);
      }
    }
  };
  check_field("PointData/temperature", d.point_data[0]);
  check_field("PointData/mode_1", d.point_data[1]);
  check_field("CellData/stress <von Mises> & co", d.cell_data[0]);
  EXPECT_EQ(p.arrays.at("field/mode_1_frequency_hz").values, std::vector<double>{1853.9123456789});
}

TEST(VtuWriter, AsciiFileParsesAndHoldsTheMeshAndFields) {
  const Mesh m = one_of_each();
  const VtuData d = sample_data(m);
  const std::string path = temp_path("ascii.vtu");
  write_vtu(path, m, d, VtuEncoding::kAscii);
  check_file(path, m, d);
  std::filesystem::remove(path);
}

TEST(VtuWriter, Base64FileParsesAndHoldsTheMeshAndFields) {
  const Mesh m = one_of_each();
  const VtuData d = sample_data(m);
  const std::string path = temp_path("base64.vtu");
  write_vtu(path, m, d, VtuEncoding::kBase64);
  check_file(path, m, d);
  std::filesystem::remove(path);
}

TEST(VtuWriter, ZlibAppendedFileParsesAndHoldsTheMeshAndFields) {
  const Mesh m = one_of_each();
  VtuData d = sample_data(m);
  // A field of more than one 32 KiB block, to exercise the block header.
  d.point_data.push_back({"large", Eigen::MatrixXd::Random(2000, m.num_nodes())});
  const std::string path = temp_path("zlib.vtu");
  write_vtu(path, m, d, VtuEncoding::kZlibAppended);
  check_file(path, m, d);
  std::filesystem::remove(path);
}

TEST(VtuWriter, CellTypeNumbers) {
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D8), 12);
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D8I), 12);
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D20), 25);
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D20R), 25);
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D4), 10);
  EXPECT_EQ(vtk_cell_type(ElementType::kC3D10), 24);
}

TEST(VtuWriter, RejectsBadFieldsAndLeavesNoFile) {
  const Mesh m = one_of_each();
  const std::string path = temp_path("bad.vtu");
  VtuData d;
  d.point_data = {{"short", Eigen::MatrixXd::Zero(3, m.num_nodes() - 1)}};
  EXPECT_THROW(write_vtu(path, m, d), InvalidInput);
  d.point_data = {{"node_id", Eigen::MatrixXd::Zero(1, m.num_nodes())}};  // reserved
  EXPECT_THROW(write_vtu(path, m, d), InvalidInput);
  d.point_data = {};
  d.cell_data = {{"", Eigen::MatrixXd::Zero(1, m.num_elements())}};
  EXPECT_THROW(write_vtu(path, m, d), InvalidInput);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace stickslip

// The Gmsh plugin (io/gmsh_plugin.h): every call into the Gmsh API of the program is here, built
// as libstickslip_gmsh.so and loaded on first use, so that runs that need no Gmsh never load it.
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <map>
#include <mutex>
#include <unordered_map>

#include "core/errors.h"
#include "fe/element.h"
#include "io/gmsh_plugin.h"
#include "io/msh_element_types.h"
#include "io/msh_lines.h"

namespace stickslip {
namespace {

std::mutex g_session_mutex;
int g_session_count = 0;

// Runs a Gmsh call and turns Gmsh's exceptions into InvalidInput naming `source`.
template <typename F>
void gmsh_call(const std::string& source, const std::string& what, F&& f) {
  try {
    f();
  } catch (...) {
    std::string error;
    try {
      gmsh::logger::getLastError(error);
    } catch (...) {
    }
    throw InvalidInput({source, 0, ""},
                       "Gmsh failed to " + what + (error.empty() ? "" : ": " + error));
  }
}

std::string gmsh_element_name(int type) {
  std::string name;
  int dim = 0, order = 0, num_nodes = 0, num_primary = 0;
  std::vector<double> local;
  try {
    gmsh::model::mesh::getElementProperties(type, name, dim, order, num_nodes, local, num_primary);
  } catch (...) {
    name = "unknown";
  }
  return name + " (MSH type " + std::to_string(type) + ")";
}

// Elements of dimension 0-2 that belong to no physical group are used for nothing (3D elements
// make the mesh, physical groups the sets): one warning per dimension with the count by type.
void warn_unused_lower_dimensional(const std::string& source, std::vector<std::string>* warnings) {
  for (int dim = 0; dim < 3; ++dim) {
    gmsh::vectorpair entities;
    gmsh_call(source, "get the entities", [&] { gmsh::model::getEntities(entities, dim); });
    std::vector<std::pair<int, std::size_t>> count;  // (MSH type, elements)
    for (const auto& entity : entities) {
      const int tag = entity.second;
      std::vector<int> groups;
      gmsh_call(source, "get the physical groups of an entity",
                [&] { gmsh::model::getPhysicalGroupsForEntity(dim, tag, groups); });
      if (!groups.empty()) continue;
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> tags, nodes;
      gmsh_call(source, "get the elements of an entity",
                [&] { gmsh::model::mesh::getElements(types, tags, nodes, dim, tag); });
      for (size_t t = 0; t < types.size(); ++t) {
        if (tags[t].empty()) continue;
        auto it = std::find_if(count.begin(), count.end(),
                               [&](const auto& c) { return c.first == types[t]; });
        if (it == count.end()) it = count.insert(count.end(), {types[t], 0});
        it->second += tags[t].size();
      }
    }
    if (count.empty()) continue;
    std::string what;
    for (const auto& [type, n] : count) {
      what += (what.empty() ? "" : ", ") + std::to_string(n) + " " + gmsh_element_name(type);
    }
    warnings->push_back(source + ": " + what + " (dimension " + std::to_string(dim) +
                        ") belong to no physical group and are ignored");
  }
}

int checked_id(std::size_t tag, const std::string& source, const char* what) {
  if (tag == 0 || tag > static_cast<std::size_t>(INT_MAX)) {
    throw InvalidInput({source, 0, ""}, std::string(what) + " tag " + std::to_string(tag) +
                                            " is outside the supported range 1.." +
                                            std::to_string(INT_MAX));
  }
  return static_cast<int>(tag);
}

// The line of `tag` in `lines` (0 when unknown).
int line_of(const std::unordered_map<std::size_t, int>* lines, std::size_t tag) {
  if (lines == nullptr) return 0;
  const auto it = lines->find(tag);
  return it == lines->end() ? 0 : it->second;
}

Mesh convert_gmsh_model(const std::string& source, const GmshReadOptions& options,
                        std::vector<std::string>* warnings, const MshLines* lines) {
  validate(options);
  const auto* node_lines = lines != nullptr && lines->scanned ? &lines->node : nullptr;
  const auto* element_lines = lines != nullptr && lines->scanned ? &lines->element : nullptr;
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> element_tags;
  std::vector<std::vector<std::size_t>> element_nodes;
  gmsh_call(source, "get the elements",
            [&] { gmsh::model::mesh::getElements(types, element_tags, element_nodes, 3, -1); });

  struct RawElement {
    std::size_t tag;
    ElementType type;
    const std::size_t* gmsh_nodes;
    const int* order;
  };
  std::vector<RawElement> raw;
  for (size_t t = 0; t < types.size(); ++t) {
    ElementType type;
    switch (types[t]) {
      case msh::kTet4:
        type = ElementType::kC3D4;
        break;
      case msh::kTet10:
        type = ElementType::kC3D10;
        break;
      case msh::kHex8:
        type = options.hexahedron8;
        break;
      case msh::kHex20:
        type = options.hexahedron20;
        break;
      case msh::kPrism6:
        type = ElementType::kC3D6;
        break;
      case msh::kPrism15:
        type = ElementType::kC3D15;
        break;
      case msh::kPyramid5:
        type = ElementType::kC3D5;
        break;
      case msh::kPyramid13:
        type = ElementType::kC3D13;
        break;
      default:
        throw InvalidInput({source, 0, ""},
                           "unsupported element type " + gmsh_element_name(types[t]) +
                               " (supported: 4- and 10-node tetrahedra, 6- and 15-node "
                               "prisms, 5- and 13-node pyramids, 8- and 20-node hexahedra)");
    }
    const size_t n = static_cast<size_t>(nodes_per_element(type));
    STICKSLIP_VERIFY(element_nodes[t].size() == n * element_tags[t].size(),
                     "Gmsh returned an inconsistent connectivity array");
    for (size_t e = 0; e < element_tags[t].size(); ++e) {
      raw.push_back({element_tags[t][e], type, element_nodes[t].data() + n * e,
                     gmsh_to_calculix_order(types[t])});
    }
  }
  if (raw.empty()) throw InvalidInput({source, 0, ""}, "the model has no 3D elements");
  std::sort(raw.begin(), raw.end(),
            [](const RawElement& a, const RawElement& b) { return a.tag < b.tag; });

  // Nodes used by 3D elements, sorted by tag.
  std::vector<std::size_t> used;
  for (const RawElement& e : raw) {
    used.insert(used.end(), e.gmsh_nodes, e.gmsh_nodes + nodes_per_element(e.type));
  }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());

  std::vector<std::size_t> node_tags;
  std::vector<double> coords, parametric;
  gmsh_call(source, "get the nodes", [&] {
    gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
  });
  std::unordered_map<std::size_t, size_t> position;  // tag -> position in node_tags
  position.reserve(node_tags.size());
  for (size_t i = 0; i < node_tags.size(); ++i) position.emplace(node_tags[i], i);

  Mesh mesh;
  mesh.coordinates.resize(3, static_cast<Eigen::Index>(used.size()));
  std::unordered_map<std::size_t, int> node_index;
  node_index.reserve(used.size());
  for (std::size_t tag : used) {
    const auto it = position.find(tag);
    if (it == position.end()) {
      throw InvalidInput({source, 0, ""}, "an element refers to node " + std::to_string(tag) +
                                              ", which has no coordinates");
    }
    const int index = mesh.num_nodes();
    mesh.coordinates.col(index) = Eigen::Vector3d(
        coords[3 * it->second], coords[3 * it->second + 1], coords[3 * it->second + 2]);
    if (!mesh.coordinates.col(index).allFinite()) {
      throw InvalidInput({source, line_of(node_lines, tag), ""},
                         "node " + std::to_string(tag) + ": a coordinate is not a finite number");
    }
    mesh.node_ids.push_back(checked_id(tag, source, "node"));
    node_index.emplace(tag, index);
  }
  std::unordered_map<std::size_t, int> element_index;
  element_index.reserve(raw.size());
  std::vector<int> local;
  for (const RawElement& e : raw) {
    local.clear();
    for (int i = 0; i < nodes_per_element(e.type); ++i) {
      local.push_back(node_index.at(e.gmsh_nodes[e.order[i]]));
    }
    const int index = mesh.add_element(checked_id(e.tag, source, "element"), e.type, local);
    element_index.emplace(e.tag, index);
    Eigen::Matrix3Xd X(3, static_cast<Eigen::Index>(local.size()));
    for (size_t i = 0; i < local.size(); ++i) {
      X.col(static_cast<Eigen::Index>(i)) = mesh.coordinates.col(local[i]);
    }
    const std::string problem = element_shape_problem(e.type, X);
    if (!problem.empty()) {
      throw InvalidInput(
          {source, line_of(element_lines, e.tag), ""},
          "element " + std::to_string(e.tag) + " (" + element_type_name(e.type) + "): " + problem);
    }
  }

  // Physical groups -> sets.
  gmsh::vectorpair groups;
  gmsh_call(source, "get the physical groups", [&] { gmsh::model::getPhysicalGroups(groups); });
  for (const auto& group : groups) {
    // Plain variables, not a structured binding: clang before 16 cannot capture bindings in the
    // lambdas below (the fuzz preset builds io with clang 14).
    const int dim = group.first, tag = group.second;
    std::string name;
    gmsh_call(source, "get a physical name", [&] { gmsh::model::getPhysicalName(dim, tag, name); });
    if (name.empty()) name = "PHYSICAL_" + std::to_string(dim) + "_" + std::to_string(tag);
    std::vector<std::size_t> group_nodes;
    std::vector<double> group_coords;
    gmsh_call(source, "get the nodes of physical group " + name, [&] {
      gmsh::model::mesh::getNodesForPhysicalGroup(dim, tag, group_nodes, group_coords);
    });
    std::vector<int>& node_set = mesh.node_sets[name];
    std::size_t off_solid = 0;
    for (std::size_t n : group_nodes) {
      const auto it = node_index.find(n);
      if (it != node_index.end()) {
        node_set.push_back(it->second);
      } else {
        ++off_solid;
      }
    }
    if (off_solid > 0 && warnings != nullptr) {
      warnings->push_back(source + ": physical group " + name + ": " + std::to_string(off_solid) +
                          " of its " + std::to_string(group_nodes.size()) +
                          " nodes are on no 3D element and are ignored (not in node set " + name +
                          ")");
    }
    std::sort(node_set.begin(), node_set.end());
    node_set.erase(std::unique(node_set.begin(), node_set.end()), node_set.end());
    if (dim != 3) continue;
    std::vector<int> entities;
    gmsh_call(source, "get the entities of physical group " + name,
              [&] { gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities); });
    std::vector<int>& element_set = mesh.element_sets[name];
    for (int entity : entities) {
      std::vector<int> et;
      std::vector<std::vector<std::size_t>> etags, enodes;
      gmsh_call(source, "get the elements of physical group " + name,
                [&] { gmsh::model::mesh::getElements(et, etags, enodes, 3, entity); });
      for (const auto& tags : etags) {
        for (std::size_t t : tags) element_set.push_back(element_index.at(t));
      }
    }
    std::sort(element_set.begin(), element_set.end());
    element_set.erase(std::unique(element_set.begin(), element_set.end()), element_set.end());
  }
  if (warnings != nullptr) warn_unused_lower_dimensional(source, warnings);
  check_mesh(mesh);
  return mesh;
}

// Builds axis-aligned boxes in the current Gmsh model (geo kernel) as transfinite, recombined
// hexahedral volumes. Points, lines and surfaces at the same place are shared, so boxes that
// share a face (or an edge) share its nodes; nothing else is merged.
class BoxBuilder {
 public:
  explicit BoxBuilder(double tolerance) : tolerance_(tolerance) {}

  int add(const GmshBox& box) {
    int p[2][2][2];
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) {
        for (int k = 0; k < 2; ++k) {
          p[i][j][k] = point({i ? box.upper.x() : box.lower.x(), j ? box.upper.y() : box.lower.y(),
                              k ? box.upper.z() : box.lower.z()});
        }
      }
    }
    // The 12 edges with their divisions.
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) line(p[0][j][k], p[1][j][k], box.divisions[0]);
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k) line(p[i][0][k], p[i][1][k], box.divisions[1]);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) line(p[i][j][0], p[i][j][1], box.divisions[2]);
    std::vector<int> faces;
    for (int s = 0; s < 2; ++s) {
      faces.push_back(surface({p[s][0][0], p[s][1][0], p[s][1][1], p[s][0][1]}));
      faces.push_back(surface({p[0][s][0], p[1][s][0], p[1][s][1], p[0][s][1]}));
      faces.push_back(surface({p[0][0][s], p[1][0][s], p[1][1][s], p[0][1][s]}));
    }
    const int loop = gmsh::model::geo::addSurfaceLoop(faces);
    const int volume = gmsh::model::geo::addVolume({loop});
    gmsh::model::geo::mesh::setTransfiniteVolume(volume);
    return volume;
  }

 private:
  int point(const Eigen::Vector3d& x) {
    const std::array<long long, 3> key = {std::llround(x.x() / tolerance_),
                                          std::llround(x.y() / tolerance_),
                                          std::llround(x.z() / tolerance_)};
    const auto it = points_.find(key);
    if (it != points_.end()) return it->second;
    const int tag = gmsh::model::geo::addPoint(x.x(), x.y(), x.z());
    points_.emplace(key, tag);
    return tag;
  }

  // Signed tag of the line a -> b (negative if stored as b -> a).
  int line(int a, int b, int divisions = -1) {
    const auto it = lines_.find({std::min(a, b), std::max(a, b)});
    if (it != lines_.end()) {
      STICKSLIP_VERIFY(divisions < 0 || divisions == it->second.second,
                       "shared edge with different divisions");
      return a < b ? it->second.first : -it->second.first;
    }
    STICKSLIP_VERIFY(divisions > 0, "line without divisions");
    const int tag = gmsh::model::geo::addLine(std::min(a, b), std::max(a, b));
    gmsh::model::geo::mesh::setTransfiniteCurve(tag, divisions + 1);
    lines_.emplace(std::make_pair(std::min(a, b), std::max(a, b)), std::make_pair(tag, divisions));
    return a < b ? tag : -tag;
  }

  int surface(std::array<int, 4> corners) {
    std::array<int, 4> key = corners;
    std::sort(key.begin(), key.end());
    const auto it = surfaces_.find(key);
    if (it != surfaces_.end()) return it->second;
    const int loop = gmsh::model::geo::addCurveLoop(
        {line(corners[0], corners[1]), line(corners[1], corners[2]), line(corners[2], corners[3]),
         line(corners[3], corners[0])});
    const int tag = gmsh::model::geo::addPlaneSurface({loop});
    gmsh::model::geo::mesh::setTransfiniteSurface(tag);
    gmsh::model::geo::mesh::setRecombine(2, tag);
    surfaces_.emplace(key, tag);
    return tag;
  }

  double tolerance_;
  std::map<std::array<long long, 3>, int> points_;
  std::map<std::pair<int, int>, std::pair<int, int>> lines_;  // (a, b) -> (tag, divisions)
  std::map<std::array<int, 4>, int> surfaces_;
};

void begin_session() {
  std::lock_guard<std::mutex> lock(g_session_mutex);
  if (g_session_count++ == 0) {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 2);  // errors and warnings only, into the logger
    gmsh::logger::start();
  }
}

void end_session() noexcept {
  std::lock_guard<std::mutex> lock(g_session_mutex);
  if (--g_session_count == 0) {
    try {
      gmsh::logger::stop();
      gmsh::finalize();
    } catch (...) {
    }
  }
}

Mesh read_file(const std::string& path, const GmshReadOptions& options,
               std::vector<std::string>* warnings, const MshLines* lines) {
  gmsh_call(path, "read the file", [&] {
    gmsh::clear();
    gmsh::open(path);
  });
  Mesh mesh = convert_gmsh_model(path, options, warnings, lines);
  gmsh::clear();
  return mesh;
}

Mesh convert_model(const std::string& source, const GmshReadOptions& options,
                   std::vector<std::string>* warnings) {
  return convert_gmsh_model(source, options, warnings, nullptr);
}

Mesh mesh_boxes(const std::vector<GmshBox>& boxes, bool quadratic, double tolerance,
                const std::string& name, const std::string& source, const GmshReadOptions& read) {
  try {
    gmsh::model::add(name);
    BoxBuilder builder(tolerance);
    std::vector<int> volumes;
    for (const GmshBox& b : boxes) volumes.push_back(builder.add(b));
    gmsh::model::geo::synchronize();
    const int group = gmsh::model::addPhysicalGroup(3, volumes);
    gmsh::model::setPhysicalName(3, group, name);
    gmsh::option::setNumber("Mesh.SecondOrderIncomplete", 1);
    gmsh::model::mesh::generate(3);
    if (quadratic) gmsh::model::mesh::setOrder(2);
  } catch (const InvalidInput&) {
    throw;
  } catch (...) {
    std::string error;
    gmsh::logger::getLastError(error);
    throw InvalidInput({source, 0, ""}, "Gmsh failed to mesh the beam: " + error);
  }
  Mesh mesh = convert_gmsh_model(source, read, nullptr, nullptr);
  gmsh::model::remove();
  return mesh;
}

}  // namespace
}  // namespace stickslip

extern "C" __attribute__((visibility("default"))) const stickslip::GmshPluginApi*
stickslip_gmsh_plugin_api() {
  static const stickslip::GmshPluginApi api{
      .abi = stickslip::kGmshPluginAbi,
      .begin_session = &stickslip::begin_session,
      .end_session = &stickslip::end_session,
      .read_file = &stickslip::read_file,
      .convert_model = &stickslip::convert_model,
      .mesh_boxes = &stickslip::mesh_boxes,
  };
  return &api;
}

#include "model/case_model.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <fstream>
#include <set>
#include <unordered_map>

#include <fmt/core.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "contact/contact_law.h"
#include "core/errors.h"
#include "core/format.h"
#include "core/frame.h"
#include "core/printable.h"
#include "core/types.h"
#include "io/cdb_reader.h"
#include "io/fingerprint.h"
#include "io/gmsh_mesh.h"
#include "io/inp_reader.h"
#include "io/two_beam_model.h"
#include "linalg/modal.h"
#include "mesh/mesh_tools.h"
#include "mesh/mortar.h"
#include "mesh/surface_area.h"
#include "model/body_reduction.h"
#include "model/rotation_case.h"
#include "model/cyclic_forced_response.h"
#include "model/nonlinear_mode_case.h"

namespace stickslip {

namespace {

// The continuation's curvature control (ArcLengthOptions.target_turn_angle), radians.
constexpr double kContinuationTurnAngle = 0.1;
// The warning sink (set_model_warning_sink); empty: stderr.
WarningFn& warning_sink() {
  static WarningFn sink;
  return sink;
}
}  // namespace

void set_model_warning_sink(WarningFn sink) { warning_sink() = std::move(sink); }

void model_warning(const std::string& text) {
  if (warning_sink()) {
    warning_sink()(text);
  } else {
    std::fprintf(stderr, "stickslip: warning: %s\n", printable(text).c_str());
  }
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

Eigen::Vector3d vec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

Mesh load_mesh(const CaseDefinition& def, const std::string& name, const MeshDefinition& m) {
  const SourceLocation where = def.where("meshes." + name);
  try {
    if (m.source == MeshDefinition::Source::kGenerate) {
      TwoBeamOptions o;
      const TwoBeamDefinition& t = m.two_beam;
      o.arrangement = t.arrangement;
      o.beam_length = t.beam_length;
      o.width = t.width;
      o.thickness = t.thickness;
      o.end_length = t.end_length;
      o.box = {t.box[0], t.box[1], t.box[2]};
      o.end_block = {t.end_block[0], t.end_block[1], t.end_block[2]};
      if (t.beam2_box) o.beam2_box = BlockDivisions{(*t.beam2_box)[0], (*t.beam2_box)[1], (*t.beam2_box)[2]};
      if (t.beam2_end_block)
        o.beam2_end_block =
            BlockDivisions{(*t.beam2_end_block)[0], (*t.beam2_end_block)[1], (*t.beam2_end_block)[2]};
      o.thesis_coarse = t.coarse;
      o.element_type = t.element;
      return make_two_beam_model(o).mesh;
    }
    if (m.format == MeshFileFormat::kMsh) {
      GmshReadOptions o;
      o.hexahedron8 = m.hexahedron8;
      o.hexahedron20 = m.hexahedron20;
      std::vector<std::string> warnings;
      Mesh mesh = read_gmsh(m.file, o, &warnings);
      for (const std::string& w : warnings) model_warning(w);
      return mesh;
    }
    std::vector<std::string> warnings;
    Mesh mesh = m.format == MeshFileFormat::kCdb ? read_cdb(m.file, &warnings)
                                                 : read_inp(m.file, &warnings);
    for (const std::string& w : warnings) model_warning(w);
    return mesh;
  } catch (const InvalidInput& e) {
    if (!e.where().file.empty()) throw;  // a mesh file's own error names its file and line
    throw InvalidInput(where, e.message());
  }
}

// The material of a mesh body. The case file's `material` when it names one (a warning when the
// mesh file assigns the body's elements a material with other constants: the file's is not used);
// else the mesh file's, which must be one complete, usable material for all the body's elements.
IsotropicMaterial body_material(const CaseDefinition& def, const std::string& name,
                                const BodyDefinition& bd, const Mesh& mesh) {
  std::set<int> used;
  for (int m : mesh.element_material) used.insert(m);
  if (!bd.material.empty()) {
    const MaterialDefinition& m = def.materials.at(bd.material);
    const IsotropicMaterial material{m.youngs_modulus, m.poisson_ratio, m.density};
    for (int i : used) {
      if (i < 0) continue;
      const MeshMaterial& f = mesh.materials[i];
      if (f.youngs_modulus != m.youngs_modulus || f.poisson_ratio != m.poisson_ratio ||
          f.density != m.density) {
        model_warning(fmt::format(
            "body {}: the case file's material {} (E {:g}, nu {:g}, rho {:g}) is used, not the "
            "mesh file's {} ({}: E {:g}, nu {:g}, rho {:g})",
            name, bd.material, m.youngs_modulus, m.poisson_ratio, m.density, f.name, f.origin,
            f.youngs_modulus, f.poisson_ratio, f.density));
      }
    }
    return material;
  }
  const SourceLocation where = def.where("bodies." + name);
  if (used.empty() || used.count(-1)) {
    throw InvalidInput(where, "body " + name + ": no 'material', and the mesh file assigns " +
                                  (used.empty() ? "no material"
                                                : "no material to some of its "
                                                  "elements") +
                                  " (*SOLID SECTION in .inp, the element's MPDATA in .cdb): give "
                                  "bodies." +
                                  name + ".material");
  }
  if (used.size() > 1) {
    std::string names;
    for (int i : used) names += (names.empty() ? "" : ", ") + mesh.materials[i].name;
    throw InvalidInput(where, "body " + name +
                                  ": no 'material', and its elements have several in "
                                  "the mesh file (" +
                                  names + "): give bodies." + name +
                                  ".material, or one body per element set");
  }
  const MeshMaterial& f = mesh.materials[*used.begin()];
  if (!f.problem.empty()) {
    throw InvalidInput(where, "body " + name + ": the mesh file's material " + f.name + " (" +
                                  f.origin + ") cannot be used: " + f.problem);
  }
  if (std::isnan(f.youngs_modulus) || std::isnan(f.poisson_ratio) || std::isnan(f.density)) {
    throw InvalidInput(
        where,
        "body " + name + ": the mesh file's material " + f.name + " (" + f.origin + ") lacks " +
            (std::isnan(f.youngs_modulus) || std::isnan(f.poisson_ratio) ? "its elastic constants"
                                                                         : "a density") +
            ": give bodies." + name + ".material");
  }
  const IsotropicMaterial material{f.youngs_modulus, f.poisson_ratio, f.density};
  try {
    validate(material);
  } catch (const InvalidInput& e) {
    throw InvalidInput(where, "body " + name + ": the mesh file's material " + f.name + " (" +
                                  f.origin + "): " + e.message());
  }
  return material;
}

// What loading a mesh depends on, as text (part of the reduction fingerprints: changing this text
// makes every manifest of `reduce` stale).
std::string mesh_description(const MeshDefinition& m) {
  if (m.source == MeshDefinition::Source::kGenerate) {
    const TwoBeamDefinition& t = m.two_beam;
    std::string beam2;  // only when given: the default keeps earlier fingerprints
    for (const auto& [name, c] : {std::pair{"beam2_box", t.beam2_box},
                                  std::pair{"beam2_end_block", t.beam2_end_block}})
      if (c) beam2 += fmt::format(" {} {} {} {}", name, (*c)[0], (*c)[1], (*c)[2]);
    return fmt::format(
        "generate {} arrangement {} element {} coarse {} box {} {} {} end_block {} {} {} "
        "size {:.17g} {:.17g} {:.17g} {:.17g}",
        m.generate, case_name(t.arrangement), element_type_name(t.element), t.coarse, t.box[0], t.box[1], t.box[2],
        t.end_block[0], t.end_block[1], t.end_block[2], t.beam_length, t.width, t.thickness,
        t.end_length) + beam2;
  }
  // The file by its contents, not its path (a moved project keeps its reductions), and the
  // contents of the files it includes, in the order read.
  std::string text = fmt::format("file format {} hex8 {} hex20 {} bytes {}", case_name(m.format),
                                 element_type_name(m.hexahedron8),
                                 element_type_name(m.hexahedron20), file_fingerprint_hex(m.file));
  if (m.format == MeshFileFormat::kInp) {
    const std::vector<std::string> files = inp_files(m.file);
    for (size_t i = 1; i < files.size(); ++i) {  // unreadable: read_inp names the line
      const bool readable = std::ifstream(files[i]).good();
      text += fmt::format(" include bytes {}", readable ? file_fingerprint_hex(files[i]) : "none");
    }
  }
  return text;
}

// Node indices of a selection in a body's mesh (sets first, then ids, duplicates removed while
// keeping the order).
std::vector<int> resolve_nodes(const CaseDefinition& def, const std::string& key,
                               const CaseBody& body, const NodeSelection& selection) {
  const SourceLocation where = def.where(key);
  std::vector<int> nodes;
  if (!body.from_mesh) {
    if (!selection.sets.empty()) {
      throw InvalidInput(where, "body " + body.name +
                                    " is given by reduced matrices: select its nodes by id, "
                                    "not by node set");
    }
    return selection.ids;  // node ids stand for themselves
  }
  for (const std::string& set : selection.sets) {
    const auto it = body.mesh.node_sets.find(set);
    if (it == body.mesh.node_sets.end()) {
      std::string known;
      for (const auto& [n, s] : body.mesh.node_sets) known += (known.empty() ? "" : ", ") + n;
      throw InvalidInput(where, "body " + body.name + " has no node set " + set +
                                    " (its node sets: " + known + ")");
    }
    nodes.insert(nodes.end(), it->second.begin(), it->second.end());
  }
  if (!selection.ids.empty()) {
    const auto by_id = node_index_by_id(body.mesh);
    for (int id : selection.ids) {
      const auto it = by_id.find(id);
      if (it == by_id.end()) {
        throw InvalidInput(where, "node " + std::to_string(id) + " is not in body " + body.name);
      }
      nodes.push_back(it->second);
    }
  }
  std::vector<int> unique;
  std::set<int> seen;
  for (int n : nodes) {
    if (seen.insert(n).second) unique.push_back(n);
  }
  return unique;
}

int node_id_of(const PreparedBody& body, int node) {
  return body.from_mesh ? body.mesh.node_ids[node] : node;
}

// Every node of a contact's preload_file must be the A node of one of its pairs: a preload that
// acts nowhere is a wrong file (another contact's, or the B nodes' ids).
void check_preload_nodes(const CaseDefinition& def, const ContactDefinition& cd, const CaseBody& A,
                         const CaseContact& rc) {
  if (cd.preloads.empty()) return;
  std::set<int> a_nodes;
  for (const auto& [a, b] : rc.node_pairs) a_nodes.insert(A.node_id(a));
  for (size_t k = 0; k < cd.preloads.size(); ++k) {
    const int id = cd.preloads[k].first;
    if (a_nodes.count(id) == 0) {
      throw InvalidInput(def.where(fmt::format("contacts.{}.preloads[{}]", cd.name, k)),
                         fmt::format("node {} is not the first node (body {}) of any pair of "
                                     "contact {}: preloads are given per pair, by its node on "
                                     "the first body",
                                     id, A.name, cd.name));
    }
  }
}

// Up to kListedIds ids of `nodes` (indices in `body`'s mesh), for messages: "12, 13, 17 (and 4
// more)".
constexpr size_t kListedIds = 12;
std::string listed_ids(const CaseBody& body, const std::vector<int>& nodes) {
  std::string text;
  for (size_t i = 0; i < nodes.size() && i < kListedIds; ++i)
    text += (i ? ", " : "") + std::to_string(body.node_id(nodes[i]));
  if (nodes.size() > kListedIds) text += fmt::format(" (and {} more)", nodes.size() - kListedIds);
  return text;
}

// Each mortar point acts in its own frame, whose normal is its surface's (mesh/mortar.h: out of
// A); the contact's `normal` says which side B is on. A point whose surface faces away from it
// (the angle is 90° or more: a normal given the wrong way round makes every point's angle 180°, a
// surface that wraps round more than a half-space has no one side) is refused.
constexpr double kMaxNormalAngleDeg = 90.0;

// A mortar point's geometric gap within this much of its coordinates' size (the norm of its
// position plus the square root of its area) is round-off of coincident surfaces, not a gap: a
// few hundred ulps; 1e-12 of a 0.3 m coordinate is 0.3 pm.
constexpr double kRoundOffGap = 1e-12;

// The frame of a mortar point of a contact whose frame is `contact_frame` (rows t1, t2, n): n its
// own surface normal, t1 the contact's t1 projected on its tangent plane (t2's where t1 is
// normal to it), so a point on a flat surface normal to the contact's `normal` has the contact's
// frame.
Eigen::MatrixXd mortar_point_frame(const Eigen::MatrixXd& contact_frame,
                                   const Eigen::Vector3d& normal) {
  try {
    return frame_from_normal(normal, contact_frame.row(0).transpose());
  } catch (const InvalidInput&) {
    return frame_from_normal(normal, contact_frame.row(1).transpose());
  }
}

// coupling: mortar: the surfaces of the two node selections (the faces of each body whose nodes
// all lie in its selection), one point per node of A's faces (mesh/mortar.h). Refused, naming
// ids: a selection that holds a face inside its body, a selected node on no face, points not
// wholly over B (unless unpaired: skip, which leaves them out with a warning), a point whose
// normal is not the contact's.
void resolve_mortar(const CaseDefinition& def, const ContactDefinition& cd, const CaseBody& A,
                    const std::vector<int>& nodes_a, const CaseBody& B,
                    const std::vector<int>& nodes_b, CaseContact& rc) {
  const std::string key = "contacts." + cd.name + ".between";
  // What the messages start with: the coupling asked for, or chosen (auto).
  const bool node_to_surface = cd.coupling == ContactCoupling::kNodeToSurface;
  const std::string lead = cd.coupling == ContactCoupling::kAuto
                               ? "the surfaces do not match node for node, so coupling: mortar: "
                           : node_to_surface ? "coupling: node_to_surface: "
                                             : "coupling: mortar: ";
  std::vector<ElementFace> faces[2];
  for (int side = 0; side < 2; ++side) {
    const CaseBody& body = side == 0 ? A : B;
    const std::vector<int>& nodes = side == 0 ? nodes_a : nodes_b;
    if (const auto [e1, e2] = interior_face(body.mesh, nodes); e1 >= 0) {
      throw InvalidInput(
          def.where(key + "." + body.name),
          lead + fmt::format("the nodes of body {} hold a face shared by elements {} "
                      "and {}, inside the body: a contact surface is made of boundary faces only",
                      body.name, body.mesh.element_ids[e1], body.mesh.element_ids[e2]));
    }
    faces[side] = faces_within(body.mesh, nodes);
    if (faces[side].empty()) {
      throw InvalidInput(def.where(key + "." + body.name),
                         lead + fmt::format("the nodes of body {} hold no element face "
                                     "(select whole faces of its surface)",
                                     body.name));
    }
    std::set<int> on_face;
    for (const ElementFace& f : faces[side]) on_face.insert(f.nodes.begin(), f.nodes.end());
    std::vector<int> stray;
    for (int n : nodes)
      if (!on_face.count(n)) stray.push_back(n);
    if (!stray.empty()) {
      throw InvalidInput(def.where(key + "." + body.name),
                         lead + fmt::format("node(s) {} of body {} lie on no element "
                                     "face whose nodes are all selected (select whole faces)",
                                     listed_ids(body, stray), body.name));
    }
  }
  MortarOptions options;
  options.search_distance = cd.search_distance;
  MortarCoupling coupling;
  try {
    coupling = node_to_surface
                   ? node_to_surface_coupling(A.mesh, faces[0], B.mesh, faces[1], options)
                   : mortar_coupling(A.mesh, faces[0], B.mesh, faces[1], options);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key), e.message());
  }
  for (const ElementFace& f : faces[1]) rc.mortar_faces_b.push_back(f.element);
  std::vector<int> none, partial;
  std::set<int> unpaired(coupling.partial.begin(), coupling.partial.end());
  for (const MortarPoint& point : coupling.points) {
    if (!unpaired.count(point.node_a)) continue;
    (point.coverage > 0 ? partial : none).push_back(point.node_a);
  }
  if (!none.empty() || !partial.empty()) {
    std::string what;
    if (!none.empty())
      what += node_to_surface
                  ? fmt::format("node(s) {} of body {} project onto no face of body {}'s "
                                "surface along their normal (outside it, or farther than the "
                                "search distance {} m)",
                                listed_ids(A, none), A.name, B.name,
                                format_number(coupling.search_distance))
                  : fmt::format("node(s) {} of body {} have no part of their area over body {}'s "
                                "surface (outside it, or farther than the search distance {} m)",
                                listed_ids(A, none), A.name, B.name,
                                format_number(coupling.search_distance));
    if (!partial.empty())
      what += fmt::format("{}node(s) {} of body {} lie only partly over body {}'s surface",
                          what.empty() ? "" : "; ", listed_ids(A, partial), A.name, B.name);
    if (cd.unpaired != UnpairedChoice::kSkip) {
      throw InvalidInput(def.where(key),
                         lead + what +
                             ". Select on body " + A.name +
                             " only the part of its surface that faces the other body, raise "
                             "search_distance if the surfaces are apart, or give 'unpaired: "
                             "skip' to leave those points out");
    }
    model_warning(fmt::format("contact {}: unpaired: skip: points left out: {}", cd.name, what));
  }
  const bool law_uses_frame = cd.uses_frame;  // 1D laws act along `direction`, any surface
  const Eigen::Vector3d normal =
      law_uses_frame ? vec3(cd.normal).normalized() : Eigen::Vector3d::UnitZ();
  const double min_cos = std::cos(kMaxNormalAngleDeg * kPi / 180.0);
  std::vector<int> turned;
  for (MortarPoint& point : coupling.points) {
    if (unpaired.count(point.node_a)) {
      rc.skipped.push_back(point.node_a);
      continue;
    }
    if (law_uses_frame && !(point.normal.dot(normal) > min_cos)) turned.push_back(point.node_a);
    int best = 0;
    for (size_t k = 1; k < point.weights_b.size(); ++k)
      if (point.weights_b[k] > point.weights_b[static_cast<size_t>(best)])
        best = static_cast<int>(k);
    rc.node_pairs.emplace_back(point.node_a, point.nodes_b[static_cast<size_t>(best)]);
    rc.mortar.push_back(std::move(point));
  }
  if (!turned.empty()) {
    throw InvalidInput(
        def.where("contacts." + cd.name + ".normal"),
        lead + fmt::format("the surface of body {} at node(s) {} faces {}° or more "
                    "away from the contact's normal (out of {} into {})",
                    A.name, listed_ids(A, turned), format_number(kMaxNormalAngleDeg), A.name,
                    B.name));
  }
  if (rc.mortar.empty()) {
    throw InvalidInput(def.where(key), lead + "the contact has no points");
  }
}

CaseContact resolve_contact(const CaseDefinition& def, int c, const std::vector<CaseBody>& bodies,
                            const std::map<std::string, int>& body_index) {
  const ContactDefinition& cd = def.contacts[c];
  const std::string key = "contacts." + cd.name;
  CaseContact rc;
  const auto find_body = [&](const std::string& name) {
    if (name == "ground") return -1;
    const auto it = body_index.find(name);
    if (it == body_index.end()) throw InvalidInput(def.where(key), "unknown body " + name);
    return it->second;
  };
  rc.body_a = find_body(cd.body_a);
  rc.body_b = find_body(cd.body_b);
  if (rc.body_a < 0)
    throw InvalidInput(def.where(key), "the first body of a contact cannot be ground");
  const CaseBody& A = bodies[rc.body_a];
  if (!cd.pairs.empty() || !cd.pairs_file.empty()) {
    const auto& listed = cd.pairs;  // pairs_file was read into `pairs` by the parser
    for (size_t i = 0; i < listed.size(); ++i) {
      const std::string pair_key = fmt::format("{}.pairs[{}]", key, i);
      NodeSelection sa{{}, {listed[i][0]}};
      const int a = resolve_nodes(def, pair_key, A, sa)[0];
      int b = -1;
      if (rc.body_b >= 0) {
        NodeSelection sb{{}, {listed[i][1]}};
        b = resolve_nodes(def, pair_key, bodies[rc.body_b], sb)[0];
      }
      rc.node_pairs.emplace_back(a, b);
    }
    check_preload_nodes(def, cd, A, rc);
    return rc;
  }
  const std::vector<int> nodes_a = resolve_nodes(def, key + ".between", A, cd.nodes_a);
  if (rc.body_b < 0) {
    for (int a : nodes_a) rc.node_pairs.emplace_back(a, -1);
    return rc;
  }
  const CaseBody& B = bodies[rc.body_b];
  if (!A.from_mesh || !B.from_mesh) {
    throw InvalidInput(def.where(key + ".between"),
                       "pairs between bodies given by matrices must be listed (pairs or "
                       "pairs_file): there are no coordinates to match");
  }
  const std::vector<int> nodes_b = resolve_nodes(def, key + ".between", B, cd.nodes_b);
  // auto: node-to-node only where the two selections coincide node for node (every node of
  // either has one partner in the other); anything else is a non-matching interface, for which
  // node pairs would leave B's other nodes untied and node-to-surface fails the patch test
  // (docs/case-file.md, "Non-matching surfaces").
  bool mortar =
      cd.coupling == ContactCoupling::kMortar || cd.coupling == ContactCoupling::kNodeToSurface;
  if (cd.coupling == ContactCoupling::kAuto) {
    try {
      rc.node_pairs = match_coincident_nodes(A.mesh, nodes_a, B.mesh, nodes_b, cd.tolerance);
      mortar = rc.node_pairs.size() != nodes_b.size();
    } catch (const InvalidInput&) {
      mortar = true;
    }
    if (mortar) rc.node_pairs.clear();
  }
  if (mortar) {
    resolve_mortar(def, cd, A, nodes_a, B, nodes_b, rc);
    check_preload_nodes(def, cd, A, rc);
    return rc;
  }
  try {
    if (rc.node_pairs.empty())
      rc.node_pairs = match_coincident_nodes(A.mesh, nodes_a, B.mesh, nodes_b, cd.tolerance);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key + ".between"),
                       "contact nodes are not coincident within tolerance " +
                           fmt::format("{:g}", cd.tolerance) + " m: " + e.message() +
                           " (surfaces meshed differently: leave 'coupling' out or give "
                           "'coupling: mortar')");
  }
  if (rc.node_pairs.empty()) {
    throw InvalidInput(def.where(key + ".between"), "the contact has no node pairs");
  }
  check_preload_nodes(def, cd, A, rc);
  return rc;
}

// Parameters of a pair that carries `share` of the contact's totals, or (per_area) of its
// values per unit area: share = the pair's area (per_pair: as given; the law's keys that are not
// `split`, mu, and the gap are never split).
ContactParametersDefinition pair_parameters(const ContactDefinition& cd, double share) {
  ContactParametersDefinition p = cd.parameters;
  if (cd.parameters_given != ContactDefinition::Parameters::kPerPair) {
    for (const LawParameter& key : contact_law(cd.law, cd.uses_frame).parameters) {
      if (key.split) *p.field(key.key) *= share;
    }
  }
  return p;
}

// The values the law's functions receive (contact/contact_law.h): its keys, `preload` the pair's
// N0, `gap` the contact's g0.
LawValues law_values(const ContactLaw& law, const ContactParametersDefinition& p, double preload,
                     double gap) {
  LawValues values;
  for (const std::string& key : law.parameter_keys()) values[key] = p.value(key);
  if (law.has_preload) values["preload"] = preload;
  if (law.has_gap) values["gap"] = gap;
  return values;
}

// The fraction of the contact's totals each pair carries: 1/n (equal), or its tributary area over
// the contact face's area (split: area; `areas` receives the areas, m²). per_pair: all 1.
std::vector<double> pair_shares(const CaseDefinition& def, const ContactDefinition& cd,
                                const CaseContact& rc, const std::vector<PreparedBody>& bodies,
                                std::vector<double>* areas) {
  const size_t np = rc.node_pairs.size();
  areas->assign(np, 0.0);
  using Parameters = ContactDefinition::Parameters;
  const bool by_area = cd.parameters_given == Parameters::kPerArea ||
                       (cd.parameters_given == Parameters::kTotal && cd.split == PreloadSplit::kArea);
  if (!rc.mortar.empty()) {  // a mortar point's area is its own
    double total = 0.0;
    for (size_t i = 0; i < np; ++i) total += (*areas)[i] = rc.mortar[i].area;
    if (cd.parameters_given == Parameters::kPerArea) return *areas;
    if (cd.parameters_given == Parameters::kPerPair) return std::vector<double>(np, 1.0);
    if (!by_area) return std::vector<double>(np, 1.0 / static_cast<double>(np));
    std::vector<double> shares(np);
    for (size_t i = 0; i < np; ++i) shares[i] = (*areas)[i] / total;
    return shares;
  }
  if (cd.parameters_given == Parameters::kPerPair) return std::vector<double>(np, 1.0);
  if (!by_area) return std::vector<double>(np, 1.0 / static_cast<double>(np));
  const std::string key =
      "contacts." + cd.name +
      (cd.parameters_given == Parameters::kPerArea ? ".per_area" : ".total.split");
  // The mesh of a body (bodies given by matrices have none).
  const auto mesh_of = [&](int b) -> const Mesh* {
    if (b < 0 || !bodies[b].from_mesh) return nullptr;
    return &bodies[b].mesh;
  };
  // The face of A, or of B when A has no mesh.
  const bool use_a = mesh_of(rc.body_a) != nullptr;
  const Mesh* mesh = use_a ? mesh_of(rc.body_a) : mesh_of(rc.body_b);
  if (mesh == nullptr) {
    throw InvalidInput(def.where(key),
                       "parameters by area need the geometry of the contact face, but "
                       "the bodies of contact " +
                           cd.name + " are given by matrices (no mesh); use per_pair or split: equal");
  }
  const PreparedBody& body = bodies[use_a ? rc.body_a : rc.body_b];
  std::unordered_map<int, int> index_of_id;  // bodies given by matrices name nodes by id
  if (!body.from_mesh) index_of_id = node_index_by_id(*mesh);
  const auto mesh_node = [&](const std::pair<int, int>& pair) {
    const int n = use_a ? pair.first : pair.second;
    if (body.from_mesh) return n;
    const auto it = index_of_id.find(n);
    if (it == index_of_id.end()) {
      throw InvalidInput(def.where(key),
                         fmt::format("node {} of body {} is not in its mesh", n, body.name));
    }
    return it->second;
  };
  std::vector<int> nodes;
  std::map<int, int> uses;  // node -> number of pairs it belongs to
  for (const auto& pair : rc.node_pairs) {
    const int n = mesh_node(pair);
    if (uses[n]++ == 0) nodes.push_back(n);
  }
  const std::vector<double> node_area = nodal_areas(*mesh, nodes);
  std::map<int, double> area_of;
  double total = 0.0;
  for (size_t k = 0; k < nodes.size(); ++k) {
    if (!(node_area[k] > 0.0)) {
      throw InvalidInput(
          def.where(key),
          fmt::format("parameters by area: node {} of body {} lies on no element face whose "
                      "nodes are all nodes of contact {}, so it has no tributary area (select "
                      "whole faces, mid-edge nodes included for quadratic elements, or use "
                      "per_pair or split: equal)",
                      mesh->node_ids[nodes[k]], body.name, cd.name));
    }
    area_of[nodes[k]] = node_area[k];
    total += node_area[k];
  }
  std::vector<double> shares(np);
  for (size_t i = 0; i < np; ++i) {
    const int n = mesh_node(rc.node_pairs[i]);
    (*areas)[i] = area_of.at(n) / uses.at(n);  // a node in several pairs shares its area
    shares[i] = cd.parameters_given == Parameters::kPerArea ? (*areas)[i] : (*areas)[i] / total;
  }
  return shares;
}

// bodies.B.cyclic on the body's mesh: its boundaries matched (the library's message, naming the
// unmatched node, its image and the nearest high node with its distance, at the key's line).
void resolve_cyclic(const CaseDefinition& def, const std::string& name, const CyclicDefinition& cd,
                    CaseBody& body) {
  const std::string key = "bodies." + name + ".cyclic";
  CyclicSymmetry symmetry;
  symmetry.sectors = cd.sectors;
  symmetry.axis_point = vec3(cd.axis_point);
  symmetry.axis_direction = vec3(cd.axis_direction);
  if (cd.low.empty()) {  // a body of the sector that crosses no boundary (a damper)
    body.cyclic = symmetry;
    return;
  }
  const std::vector<int> low = resolve_nodes(def, key + ".low", body, cd.low);
  const std::vector<int> high = resolve_nodes(def, key + ".high", body, cd.high);
  for (int n : low) {
    if (std::find(high.begin(), high.end(), n) != high.end()) {
      throw InvalidInput(def.where(key + ".high"),
                         fmt::format("node {} of body {} is on both the low and the high boundary",
                                     body.mesh.node_ids[n], name));
    }
  }
  try {
    body.cyclic_pairs = match_cyclic_boundaries(body.mesh, low, high, symmetry, cd.tolerance);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key), "body " + name + ": " + e.message());
  }
  body.cyclic = symmetry;
}

}  // namespace

DofMap body_constraints(const CaseBody& body, const Mesh& mesh) {
  return DofMap::from_supports(mesh.num_nodes(), body.clamp, body.supports, mesh.equations);
}

ModelCache::Body& ModelCache::body(const std::string& name, const std::string& fingerprint) {
  Body& entry = bodies[name];
  if (entry.fingerprint != fingerprint) {
    entry = Body{};
    entry.fingerprint = fingerprint;
  }
  return entry;
}

int PreparedBody::global_dof(int node_id, int direction) const {
  const auto it = master_dof.find({node_id, direction});
  return it == master_dof.end() ? -1 : it->second;
}

int PreparedModel::body_index(const std::string& name) const {
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string mesh_fingerprint(const CaseDefinition& def, const std::string& name) {
  return fingerprint_hex(mesh_description(def.meshes.at(name)));
}

std::vector<std::string> reduction_fingerprints(const CaseDefinition& def,
                                                const CaseBodies& bodies) {
  std::map<std::string, std::string> mesh_text;  // each mesh file is hashed once
  std::vector<std::string> out;
  for (const CaseBody& body : bodies.bodies) {
    out.emplace_back();
    if (!body.from_mesh) continue;
    const BodyDefinition& bd = def.bodies.at(body.name);
    auto [it, inserted] = mesh_text.try_emplace(bd.mesh);
    if (inserted) it->second = mesh_description(def.meshes.at(bd.mesh));
    std::string text = "stickslip reduce 1\n";
    text += it->second + "\n";
    text += "element_set " + bd.element_set + "\n";
    text += fmt::format("material {:.17g} {:.17g} {:.17g}\n", body.material.youngs_modulus,
                        body.material.poisson_ratio, body.material.density);
    text += "clamp";
    for (int n : body.clamp) text += fmt::format(" {}", body.node_id(n));
    for (const NodeSupport& support : body.supports) {
      text += fmt::format("\nsupport {}", body.node_id(support.node));
      for (const Eigen::Vector3d& d : support.directions)
        text += fmt::format(" {:.17g} {:.17g} {:.17g}", d.x(), d.y(), d.z());
    }
    text += "\nmasters";
    for (int n : body.masters) text += fmt::format(" {}", body.node_id(n));
    text += fmt::format("\nmodes {}\n", bd.modes);
    if (bd.mass_rule != MassIntegration::kExact) text += "mass_rule calculix\n";
    if (def.rotation && def.rotation->speed_rpm != 0.0 &&
        (def.rotation->stress_stiffening || def.rotation->spin_softening)) {
      // The body is reduced with its stiffness at that speed (model/rotation_case.h).
      const RotationAxis axis = case_rotation_axis(def);
      text += fmt::format("rotation {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {} {}\n",
                          def.rotation->speed_rpm, axis.point.x(), axis.point.y(), axis.point.z(),
                          axis.direction.x(), axis.direction.y(), axis.direction.z(),
                          int{def.rotation->stress_stiffening}, int{def.rotation->spin_softening});
    }
    out.back() = fingerprint_hex(text);
  }
  return out;
}

// Every recovery.nodes id must be a node of a body given by a mesh (the bodies recovered). The
// parser refuses recovery.nodes in a case without such bodies; the stages' rewritten case, whose
// bodies all come from reduced files, has none either and was checked as the user wrote it.
void check_recovery_nodes(const CaseDefinition& def, const std::vector<CaseBody>& bodies) {
  std::vector<std::unordered_map<int, int>> by_id;
  for (const CaseBody& body : bodies) {
    if (body.from_mesh) by_id.push_back(node_index_by_id(body.mesh));
  }
  if (by_id.empty()) return;
  for (size_t i = 0; i < def.recovery.nodes.size(); ++i) {
    const int id = def.recovery.nodes[i];
    const bool found = std::any_of(by_id.begin(), by_id.end(),
                                   [&](const auto& ids) { return ids.count(id) > 0; });
    if (!found) {
      throw InvalidInput(def.where(fmt::format("recovery.nodes[{}]", i)),
                         fmt::format("node {} is not a node of any body given by a mesh (the "
                                     "bodies recovered)",
                                     id));
    }
  }
}

CaseBodies resolve_case_bodies(const CaseDefinition& def, const ProgressFn& progress,
                               ModelCache* cache) {
  CaseBodies out;
  std::map<std::string, Mesh> meshes;
  for (const auto& [name, md] : def.meshes) {
    if (cache == nullptr) {
      if (progress) progress("mesh " + name);
      meshes.emplace(name, load_mesh(def, name, md));
      continue;
    }
    const std::string fingerprint = mesh_fingerprint(def, name);
    auto& [cached_fingerprint, cached_mesh] = cache->meshes[name];
    if (cached_fingerprint != fingerprint) {
      if (progress) progress("mesh " + name);
      cached_mesh = load_mesh(def, name, md);
      cached_fingerprint = fingerprint;
    } else if (progress) {
      progress("mesh " + name + ": the one already loaded (same definition)");
    }
    meshes.emplace(name, cached_mesh);
  }

  // Bodies: the part of their mesh (bodies given by matrices: only their name here).
  std::map<std::string, int> body_index;
  for (const auto& [name, bd] : def.bodies) {
    CaseBody body;
    body.name = name;
    if (bd.source == BodyDefinition::Source::kMesh) {
      body.from_mesh = true;
      const Mesh& mesh = meshes.at(bd.mesh);
      body.mesh = bd.element_set.empty() ? mesh : [&] {
        try {
          return extract_element_set(mesh, bd.element_set).mesh;
        } catch (const InvalidInput& e) {
          throw InvalidInput(def.where("bodies." + name + ".element_set"), e.message());
        }
      }();
      body.material = body_material(def, name, bd, body.mesh);
    }
    body_index[name] = static_cast<int>(out.bodies.size());
    out.bodies.push_back(std::move(body));
  }

  // Contacts: node pairs, which also name master nodes; then forced, listed and FRF nodes. Each
  // master remembers the first key that asked for it.
  std::vector<std::vector<int>> masters(out.bodies.size());
  const auto add_master = [&](int b, int node, const std::string& key) {
    masters[b].push_back(node);
    out.bodies[b].master_keys.emplace(node, key);
  };
  for (size_t c = 0; c < def.contacts.size(); ++c) {
    out.contacts.push_back(resolve_contact(def, static_cast<int>(c), out.bodies, body_index));
    const ContactDefinition& cd = def.contacts[c];
    const CaseContact& rc = out.contacts.back();
    const bool listed = !cd.pairs.empty();
    for (size_t i = 0; i < rc.node_pairs.size(); ++i) {
      const std::string key = listed ? fmt::format("contacts.{}.pairs[{}]", cd.name, i)
                                     : fmt::format("contacts.{}.between", cd.name);
      add_master(rc.body_a, rc.node_pairs[i].first, key);
      if (!rc.mortar.empty()) {
        for (int a : rc.mortar[i].nodes_a) add_master(rc.body_a, a, key);
        for (int b : rc.mortar[i].nodes_b) add_master(rc.body_b, b, key);
      } else if (rc.body_b >= 0) {
        add_master(rc.body_b, rc.node_pairs[i].second, key);
      }
    }
  }
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const ExcitationDefinition& ed = def.excitation[e];
    const int b = body_index.at(ed.body);
    const std::string key = fmt::format("excitation[{}]", e);
    out.excitation_nodes.push_back(resolve_nodes(def, key, out.bodies[b], ed.nodes));
    for (int n : out.excitation_nodes.back()) add_master(b, n, key);
  }
  for (size_t i = 0; i < def.static_loads.size(); ++i) {
    const StaticLoadDefinition& ld = def.static_loads[i];
    const int b = body_index.at(ld.body);
    const std::string key = fmt::format("static_loads[{}]", i);
    std::vector<int> nodes = resolve_nodes(def, key, out.bodies[b], ld.nodes);
    if (ld.kind != StaticLoadDefinition::Kind::kForce) {
      std::sort(nodes.begin(), nodes.end());
      nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    }
    for (int n : nodes) add_master(b, n, key);
    out.static_load_nodes.push_back(std::move(nodes));
  }
  for (const auto& [name, bd] : def.bodies) {
    const int b = body_index.at(name);
    const std::string key = "bodies." + name + ".masters";
    for (int n : resolve_nodes(def, key, out.bodies[b], bd.masters)) add_master(b, n, key);
  }
  for (size_t i = 0; i < def.output.frf.size(); ++i) {
    const ResponseDofDefinition& r = def.output.frf[i];
    const std::string key = fmt::format("output.frf[{}]", i);
    const auto it = body_index.find(r.body);
    if (it == body_index.end()) throw InvalidInput(def.where(key), "unknown body " + r.body);
    const auto nodes =
        resolve_nodes(def, key, out.bodies[it->second], NodeSelection{{}, {r.node}});
    add_master(it->second, nodes[0], key);
  }
  check_recovery_nodes(def, out.bodies);
  for (const auto& [name, bd] : def.bodies) {
    CaseBody& body = out.bodies[body_index.at(name)];
    std::vector<int>& m = masters[body_index.at(name)];
    std::sort(m.begin(), m.end());
    m.erase(std::unique(m.begin(), m.end()), m.end());
    body.masters = std::move(m);
    if (!body.from_mesh) continue;
    body.clamp = resolve_nodes(def, "bodies." + name + ".clamp", body, bd.clamp);
    for (size_t i = 0; i < bd.supports.size(); ++i) {
      const SupportDefinition& sd = bd.supports[i];
      const std::string key = fmt::format("bodies.{}.supports[{}]", name, i);
      const SourceLocation where = def.where(key);
      if (sd.from_mesh) {
        // The deck's *BOUNDARY lines (all of them, model and step level alike).
        if (body.mesh.boundaries.empty()) {
          throw InvalidInput(where, "from_mesh: the mesh of body " + name +
                                        " has no *BOUNDARY lines (.inp) or D lines (.cdb)");
        }
        for (const MeshBoundary& b : body.mesh.boundaries) {
          if (!b.unsupported.empty()) {
            throw InvalidInput(where, "from_mesh: the *BOUNDARY at " + b.origin +
                                          " cannot be applied as a support: " + b.unsupported);
          }
          std::vector<Eigen::Vector3d> directions;
          for (int d = b.first; d <= b.last; ++d) directions.push_back(Eigen::Vector3d::Unit(d));
          for (int n : b.nodes) body.supports.push_back({n, directions, b.origin});
        }
        continue;
      }
      const std::string origin = fmt::format("{}:{}", where.file, where.line);
      std::vector<Eigen::Vector3d> directions;
      const Eigen::Matrix3d R =
          sd.local_frame ? (sd.t1 == std::array<double, 3>{0, 0, 0}
                                ? frame_from_normal(Eigen::Vector3d(sd.normal.data()))
                                : frame_from_normal(Eigen::Vector3d(sd.normal.data()),
                                                    Eigen::Vector3d(sd.t1.data())))
                         : Eigen::Matrix3d::Identity();
      for (int row : sd.directions) directions.push_back(R.row(row).transpose());
      for (int n : resolve_nodes(def, key + ".nodes", body, sd.nodes))
        body.supports.push_back({n, directions, origin});
    }
    if (bd.cyclic) resolve_cyclic(def, name, *bd.cyclic, body);
  }
  return out;
}

std::vector<Eigen::Vector3d> static_load_forces(const Mesh& mesh, const std::vector<int>& nodes,
                                                const StaticLoadDefinition& load) {
  const Eigen::Vector3d f(load.force[0], load.force[1], load.force[2]);
  switch (load.kind) {
    case StaticLoadDefinition::Kind::kForce:
      return std::vector<Eigen::Vector3d>(nodes.size(), f);
    case StaticLoadDefinition::Kind::kPressure:
      return pressure_nodal_forces(mesh, nodes, load.pressure);
    case StaticLoadDefinition::Kind::kTotalForce:
      break;
  }
  // Consistent nodal areas ∫ N_i dA: the work-equivalent loads of a uniform traction.
  const std::vector<double> areas = nodal_areas(mesh, nodes, NodalAreaRule::kConsistent);
  double total = 0.0;
  for (double a : areas) total += a;
  if (!(total > 0.0)) {
    throw InvalidInput(
        "total_force: its nodes hold no element face to split the force over (select whole "
        "faces, mid-edge nodes included for quadratic elements, or use 'force' per node)");
  }
  std::vector<Eigen::Vector3d> out;
  for (double a : areas) out.push_back(f * (a / total));
  return out;
}

PreparedModel prepare_model(const CaseDefinition& def, const ProgressFn& progress,
                            ModelCache* cache) {
  const auto t0 = Clock::now();
  CaseBodies resolved = resolve_case_bodies(def, progress, cache);
  const CraigBamptonReduction reduction(
      cache, cache ? reduction_fingerprints(def, resolved) : std::vector<std::string>{});
  PreparedModel model = prepare_model(def, std::move(resolved), reduction, progress);
  model.seconds_prepare = seconds_since(t0);  // the meshes included
  return model;
}

PreparedModel prepare_model(const CaseDefinition& def, CaseBodies resolved,
                            const BodyReduction& reduction, const ProgressFn& progress) {
  const auto t0 = Clock::now();
  // A cyclic sector: reduced per nodal diameter, its dynamic harmonics a travelling wave.
  const std::optional<CyclicForcedResponse> cyclic = cyclic_forced_response(def);
  if (cyclic && dynamic_cast<const CraigBamptonReduction*>(&reduction) == nullptr) {
    throw InvalidInput(def.where("bodies." + cyclic->body + ".cyclic"),
                       "body " + cyclic->body +
                           " is a cyclic sector: its forced response is computed by `stickslip "
                           "run` (and the library) only, for now: the stage commands do not store "
                           "a sector's reductions per nodal diameter");
  }
  // Per body of the sector with boundaries: its reduction per nodal diameter.
  std::map<std::string, std::map<int, CyclicReducedSector>> cyclic_reductions;
  const auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  PreparedModel model;

  // Bodies: the resolved mesh part, or the matrices read (first, as they are quick to refuse).
  std::map<std::string, int> body_index;
  for (CaseBody& resolved_body : resolved.bodies) {
    PreparedBody body;
    body.name = resolved_body.name;
    body.from_mesh = resolved_body.from_mesh;
    if (body.from_mesh) {
      body.mesh = std::move(resolved_body.mesh);
      body.material = resolved_body.material;
    } else {
      reduction.reduce(def, resolved_body, body, progress);
    }
    body_index[body.name] = static_cast<int>(model.bodies.size());
    model.bodies.push_back(std::move(body));
  }

  // Reduction, then the assembled reduced model.
  for (auto& [name, bd] : def.bodies) {
    const int b = body_index.at(name);
    PreparedBody& body = model.bodies[b];
    const std::vector<int>& m = resolved.bodies[b].masters;
    if (body.from_mesh && cyclic && !resolved.bodies[b].cyclic_pairs.empty()) {
      cyclic_reductions[name] = reduce_cyclic_body(
          def, resolved.bodies[b], body,
          reached_nodal_diameters(def, cyclic->engine_order, cyclic->symmetry.sectors), progress);
    } else if (body.from_mesh) {
      // The resolved body without its mesh (moved into `body`): its clamps, supports, masters.
      // A body of a sector that crosses no boundary: its ordinary reduction serves every
      // nodal diameter (model/cyclic_forced_response.h).
      reduction.reduce(def, resolved.bodies[b], body, progress);
      body.cyclic = resolved.bodies[b].cyclic;
    }
    body.offset = model.num_dofs;
    for (int j = 0; j < body.reduced.size(); ++j) {
      const ReducedDof& d = body.reduced.dofs[j];
      if (d.kind == ReducedDof::Kind::kPhysical) {
        body.master_dof[{d.node_id, d.direction}] = body.offset + j;
      }
    }
    model.num_dofs += body.reduced.size();
    if (!body.from_mesh) {
      for (int id : m) {
        for (int dir = 0; dir < 3; ++dir) {
          if (body.global_dof(id, dir) < 0) {
            const auto asked = resolved.bodies[b].master_keys.find(id);
            const std::string key =
                asked == resolved.bodies[b].master_keys.end() ? "bodies." + name : asked->second;
            throw InvalidInput(def.where(key),
                               fmt::format("node {} direction {} is not a DOF of the reduced "
                                           "matrices of body {} (its mapping: {})",
                                           id, "xyz"[dir], name,
                                           def.bodies.at(name).reduced.mapping));
          }
        }
      }
    }
  }
  model.K = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  model.M = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  model.C = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  bool modal_ratio = false;  // some body damps its fixed-interface modes: C is not αM + βK
  for (const auto& [name, bd] : def.bodies) {
    const PreparedBody& body = model.bodies[body_index.at(name)];
    const int n = body.reduced.size();
    model.K.block(body.offset, body.offset, n, n) = body.reduced.K;
    model.M.block(body.offset, body.offset, n, n) = body.reduced.M;
    ReducedDampingOptions damping;
    damping.alpha = def.damping.alpha;
    damping.beta = def.damping.beta;
    damping.modal_damping_ratio = bd.modal_damping_ratio;
    try {
      model.C.block(body.offset, body.offset, n, n) = reduced_damping(body.reduced, damping);
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where("bodies." + name + ".modal_damping_ratio"), e.message());
    }
    modal_ratio = modal_ratio || (bd.modal_damping_ratio > 0.0 && body.reduced.num_modal() > 0);
  }
  say(fmt::format("modes of the reduced model ({} DOFs{})", model.num_dofs,
                  modal_ratio ? ", non-proportional damping" : ""));
  const auto t_modes = Clock::now();
  model.linear = modal_ratio ? linear_model_from_matrices(model.K, model.M, model.C)
                             : linear_model_from_matrices(model.K, model.M, def.damping.alpha,
                                                          def.damping.beta);
  say(fmt::format("reduced-model modes: done in {:.1f} s", seconds_since(t_modes)));

  // Contact elements on the reduced DOFs.
  std::vector<bool> balance_rest_force;  // per pair: its force at rest is a typed preload
  for (size_t c = 0; c < def.contacts.size(); ++c) {
    const ContactDefinition& cd = def.contacts[c];
    const CaseContact& rc = resolved.contacts[c];
    const int np = static_cast<int>(rc.node_pairs.size());
    std::vector<double> areas;
    const std::vector<double> shares = pair_shares(def, cd, rc, model.bodies, &areas);
    const std::map<int, double> preload_by_node(cd.preloads.begin(), cd.preloads.end());
    const PreparedBody& A = model.bodies[rc.body_a];
    const ContactLaw& law = [&]() -> const ContactLaw& {
      try {
        return contact_law(cd.law, cd.uses_frame);  // a definition built in C++ may name any
      } catch (const InvalidInput& e) {
        throw InvalidInput(def.where("contacts." + cd.name + ".law"), e.message());
      }
    }();
    Eigen::MatrixXd row_frame;  // m x 3
    try {
      if (law.uses_frame) {
        row_frame = vec3(cd.t1).squaredNorm() > 0 ? frame_from_normal(vec3(cd.normal), vec3(cd.t1))
                                                  : frame_from_normal(vec3(cd.normal));
      } else {
        const Eigen::Vector3d d = vec3(cd.direction);
        if (!(d.norm() > 0)) throw InvalidInput("direction must be a non-zero vector");
        row_frame = d.normalized().transpose();
      }
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where("contacts." + cd.name), e.message());
    }
    for (int i = 0; i < np; ++i) {
      const auto [a, b] = rc.node_pairs[i];
      const ContactParametersDefinition p = pair_parameters(cd, shares[i]);
      ContactPair pair;
      PreparedPair info;
      info.contact = static_cast<int>(c);
      info.share = shares[i];
      info.area = areas[i];
      info.parameters = p;

      info.node_a_id = node_id_of(A, a);
      info.node_b_id = rc.body_b >= 0 ? node_id_of(model.bodies[rc.body_b], b) : 0;
      for (int dir = 0; dir < 3; ++dir) {
        pair.dofs_a.push_back(A.global_dof(info.node_a_id, dir));
        if (rc.body_b >= 0 && rc.mortar.empty()) {
          pair.dofs_b.push_back(model.bodies[rc.body_b].global_dof(info.node_b_id, dir));
        }
      }
      pair.frame = row_frame;
      if (cd.neighbour != 0) {  // B is the given node of the next (previous) sector
        pair.b_sector = cd.neighbour;
        const PreparedBody& B = model.bodies[rc.body_b];
        const Eigen::Matrix3d Rs = sector_rotation(cyclic->symmetry.rotation(), cd.neighbour);
        const Eigen::Vector3d p = cyclic->symmetry.axis_point;
        const Eigen::Vector3d xb = p + Rs * (B.mesh.coordinates.col(b) - p);
        const double distance = (xb - A.mesh.coordinates.col(a)).norm();
        if (!(distance <= cd.tolerance)) {
          throw InvalidInput(
              def.where(fmt::format("contacts.{}.pairs[{}]", cd.name, i)),
              fmt::format("contact {}: node {}'s copy in the {} sector lies at ({:.6g}, {:.6g}, "
                          "{:.6g}), {:.3g} m from node {} (tolerance {:.3g} m): not a pair of "
                          "neighbours",
                          cd.name, info.node_b_id, cd.neighbour > 0 ? "next" : "previous", xb.x(),
                          xb.y(), xb.z(), distance, info.node_a_id, cd.tolerance));
        }
      }
      // The initial gap of the law: the contact's, plus a mortar point's geometric gap where the
      // law has a gap and no typed preload says the surfaces are closed at rest.
      double gap = cd.gap;
      bool geometric_gap = false;
      if (!rc.mortar.empty()) {  // u = R (x_A − Σ_k Φ_k x_Bk): B's nodes as more columns
        const MortarPoint& point = rc.mortar[static_cast<size_t>(i)];
        const PreparedBody& B = model.bodies[rc.body_b];
        const int nb = static_cast<int>(point.nodes_b.size());
        const Eigen::MatrixXd frame =
            law.uses_frame ? mortar_point_frame(row_frame, point.normal) : row_frame;
        // Quadratic faces: the point is Σ_j a_j x_Aj (mesh/mortar.h), node A's weight first.
        std::vector<std::pair<int, double>> a_side{{a, 1.0}};
        for (size_t j = 0; j < point.nodes_a.size(); ++j) {
          if (point.nodes_a[j] == a) {
            a_side[0].second = point.weights_a[j];
          } else {
            a_side.emplace_back(point.nodes_a[j], point.weights_a[j]);
          }
        }
        const int na = static_cast<int>(a_side.size());
        pair.frame.resize(frame.rows(), 3 * (na + nb));
        info.mortar = true;
        info.gap = point.gap;
        info.weight_a = a_side[0].second;
        // Σ_k Φ_k x_Bk − Σ_j a_j x_Aj: B's surface seen from the point (Σ_k Φ_k = 1 for a point
        // wholly over B, the only ones kept).
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
        for (int j = 0; j < na; ++j) {
          const auto [node, w] = a_side[static_cast<size_t>(j)];
          if (j > 0) {
            for (int dir = 0; dir < 3; ++dir)
              pair.dofs_a.push_back(A.global_dof(node_id_of(A, node), dir));
          }
          pair.frame.middleCols(3 * j, 3) = w * frame;
          offset -= w * A.mesh.coordinates.col(node);
          info.point_ids_a.push_back(node_id_of(A, node));
          info.point_weights_a.push_back(w);
        }
        for (int k = 0; k < nb; ++k) {
          const int id = node_id_of(B, point.nodes_b[static_cast<size_t>(k)]);
          const double w = point.weights_b[static_cast<size_t>(k)];
          for (int dir = 0; dir < 3; ++dir) pair.dofs_a.push_back(B.global_dof(id, dir));
          pair.frame.middleCols(3 * (na + k), 3) = -w * frame;
          info.partner_ids.push_back(id);
          info.weights.push_back(w);
          offset += w * B.mesh.coordinates.col(point.nodes_b[static_cast<size_t>(k)]);
        }
        const bool typed_preload = cd.parameters.preload > 0.0 || !preload_by_node.empty();
        if (law.has_gap && !typed_preload) {
          // Along the law's normal row (friction: n; 1D laws: their direction); a gap within
          // round-off of the coordinates is none (it would press coincident surfaces at rest).
          double g = frame.row(frame.rows() - 1).dot(offset);
          const double round_off =
              kRoundOffGap * (A.mesh.coordinates.col(a).norm() + std::sqrt(point.area));
          if (std::abs(g) <= round_off) g = 0.0;
          gap += g;
          geometric_gap = g != 0.0;
        }
        for (int f : point.faces_b) {
          info.partner_elements.push_back(
              B.mesh.element_ids[static_cast<size_t>(rc.mortar_faces_b[static_cast<size_t>(f)])]);
        }
      }
      double preload = p.preload;
      if (!preload_by_node.empty()) {
        const auto it = preload_by_node.find(info.node_a_id);
        if (it == preload_by_node.end()) {
          throw InvalidInput(def.where("contacts." + cd.name + ".preload_file"),
                             "no preload for node " + std::to_string(info.node_a_id) +
                                 " (the A node of a pair of contact " + cd.name + ")");
        }
        preload = it->second;
      }
      const LawValues values = law_values(law, p, preload, gap);
      info.stuck_stiffness = law.stuck_stiffness(values);
      pair.element = law.make_element(values);
      // A force at rest that comes from the geometry (an interference) strains the bodies: it is
      // not balanced like a typed preload (below).
      balance_rest_force.push_back(!geometric_gap);
      model.pairs.push_back(std::move(pair));
      model.pair_info.push_back(info);
    }
  }

  // Excitation on the reduced DOFs: f(t) = Re(F e^{ikΩt}) on each selected node.
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const ExcitationDefinition& ed = def.excitation[e];
    const int b = body_index.at(ed.body);
    const PreparedBody& body = model.bodies[b];
    const std::vector<int>& nodes = resolved.excitation_nodes[e];
    std::array<std::complex<double>, 3> f = ed.force;
    if (ed.by_direction) {
      const Eigen::Vector3d d = vec3(ed.direction).normalized();
      const std::complex<double> amp = std::polar(ed.amplitude, ed.phase_deg * kPi / 180.0);
      for (int i = 0; i < 3; ++i) f[i] = amp * d(i);
    }
    auto [it, inserted] =
        model.excitation.harmonics.try_emplace(ed.harmonic, Eigen::VectorXcd::Zero(model.num_dofs));
    for (int n : nodes) {
      for (int dir = 0; dir < 3; ++dir)
        it->second(body.global_dof(node_id_of(body, n), dir)) += f[dir];
    }
  }

  // Static loads (harmonic 0) on their master nodes: the reduced model sees them exactly, and the
  // recovery applies them to the full bodies with the static contact forces (the mean stress).
  for (size_t i = 0; i < def.static_loads.size(); ++i) {
    const StaticLoadDefinition& ld = def.static_loads[i];
    const PreparedBody& body = model.bodies[body_index.at(ld.body)];
    const std::vector<int>& nodes = resolved.static_load_nodes[i];
    const std::string key = fmt::format("static_loads[{}]", i);
    std::vector<Eigen::Vector3d> forces;
    try {
      forces = static_load_forces(body.mesh, nodes, ld);
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where(key), fmt::format("body {}: {}", ld.body, e.message()));
    }
    auto [it, inserted] =
        model.excitation.harmonics.try_emplace(0, Eigen::VectorXcd::Zero(model.num_dofs));
    for (size_t k = 0; k < nodes.size(); ++k) {
      for (int dir = 0; dir < 3; ++dir)
        it->second(body.global_dof(node_id_of(body, nodes[k]), dir)) += forces[k](dir);
    }
  }

  // Rotation: the centrifugal load of every mesh body, a static load (model/rotation_case.h).
  if (def.rotation && case_rotation_speed(def) != 0.0) {
    auto [it, inserted] =
        model.excitation.harmonics.try_emplace(0, Eigen::VectorXcd::Zero(model.num_dofs));
    for (size_t b = 0; b < model.bodies.size(); ++b) {
      const PreparedBody& body = model.bodies[b];
      if (!body.from_mesh) continue;
      const CaseBody& rb = resolved.bodies[b];
      std::optional<SectorBoundary> sector;
      if (rb.cyclic && !rb.cyclic_pairs.empty()) {
        sector = SectorBoundary{rb.cyclic_pairs, {}, *rb.cyclic};
        for (int d = 0; d < body.constraints.num_dofs(); ++d) {
          if (body.constraints.is_clamped(d)) sector->clamped_dofs.push_back(d);
        }
      }
      const Eigen::VectorXd f =
          reduced_centrifugal_load(def, body, sector ? &*sector : nullptr);
      it->second.segment(body.offset, f.size()) += f.cast<std::complex<double>>();
    }
    say(fmt::format("rotation: {} rpm ({:.6g} rad/s); centrifugal load on every body{}{}",
                    def.rotation->speed_rpm, case_rotation_speed(def),
                    def.rotation->stress_stiffening ? ", stress stiffening" : "",
                    def.rotation->spin_softening ? ", spin softening" : ""));
  }

  // The normal preload N0 is carried by the contact at rest: it is the force of an external
  // static load pressing the two nodes of each pair together (a bolt, a centrifugal load, a
  // spring pack). Without that load the bodies would push each other apart and the static
  // solution would relax N0 almost to zero. So every pair whose element force at zero relative
  // displacement f(0) is not zero adds the static load that balances it: −Rᵀf(0) on B, +Rᵀf(0)
  // on A (harmonic 0). Then u = 0 is the static equilibrium and N = N0 there.
  {
    Eigen::VectorXcd preload = Eigen::VectorXcd::Zero(model.num_dofs);
    bool any = false;
    const int samples = 4;
    for (size_t q = 0; q < model.pairs.size(); ++q) {
      const ContactPair& pair = model.pairs[q];
      if (!balance_rest_force[q]) continue;
      const int m = pair.element->dimension();
      Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(m, samples), f0;
      pair.element->march(u0, nullptr, f0, nullptr);
      const Eigen::VectorXd f_rest = f0.col(0);
      if (f_rest.norm() == 0.0) continue;
      any = true;
      // Rᵀf(0) per frame column: the force on B (global axes), and for a mortar point's B columns
      // −Φ_k times it; A's DOFs receive +, B's −, of their columns.
      const Eigen::VectorXd g = pair.frame.transpose() * f_rest;
      // A neighbour's B: the force of the pair of sector −s on this sector's node, R^{−s} g.
      const Eigen::VectorXd gb =
          pair.b_sector == 0
              ? g
              : Eigen::VectorXd(
                    sector_rotation(cyclic->symmetry.rotation(), pair.b_sector).transpose() * g);
      for (int d = 0; d < static_cast<int>(g.size()); ++d) {
        if (!pair.dofs_b.empty()) preload(pair.dofs_b[d]) -= gb(d);
        if (!pair.dofs_a.empty()) preload(pair.dofs_a[d]) += g(d);
      }
    }
    if (any) {
      auto [it, inserted] =
          model.excitation.harmonics.try_emplace(0, Eigen::VectorXcd::Zero(model.num_dofs));
      it->second += preload;
    }
  }

  // Harmonic balance options.
  const AnalysisDefinition& an = def.analysis;
  model.hbm.harmonic_list = an.harmonics;
  model.hbm.harmonics = an.max_harmonic();
  model.hbm.time_samples = an.time_samples;
  model.hbm.aft = an.aft == AftChoice::kSampled        ? AftMethod::kSampled
                  : an.aft == AftChoice::kEventPlanar ? AftMethod::kEventPlanar
                                                      : AftMethod::kEvent;
  model.hbm.static_coupling = an.static_coupling == StaticChoice::kCoupled
                                  ? StaticCoupling::kCoupled
                                  : StaticCoupling::kUncoupled;
  if (cyclic) {
    model.wave = cyclic_travelling_wave(def, *cyclic, model, cyclic_reductions);
    std::string diameters, bodies;
    for (int h : reached_nodal_diameters(def, cyclic->engine_order, cyclic->symmetry.sectors))
      diameters += (diameters.empty() ? "" : ", ") + std::to_string(h);
    for (const std::string& b : cyclic->bodies) bodies += (bodies.empty() ? "" : ", ") + b;
    say(fmt::format("cyclic sector {} of {} (bodies {}): engine order {}, the travelling wave of "
                    "a tuned structure (every sector identical); nodal diameters {}",
                    cyclic->body, cyclic->symmetry.sectors, bodies, cyclic->engine_order,
                    diameters));
  }
  model.hbm.static_increments = an.static_increments;
  model.seconds_prepare = seconds_since(t0);
  return model;
}

Eigen::MatrixXd stuck_stiffness_matrix(const PreparedModel& model) {
  Eigen::MatrixXd K = model.K;
  for (size_t i = 0; i < model.pairs.size(); ++i) {
    const ContactPair& pair = model.pairs[i];
    const Eigen::VectorXd& k_local = model.pair_info[i].stuck_stiffness;
    const int m = static_cast<int>(pair.frame.rows());
    Eigen::MatrixXd Bp = Eigen::MatrixXd::Zero(m, model.num_dofs);
    for (int d = 0; d < static_cast<int>(pair.frame.cols()); ++d) {
      if (!pair.dofs_a.empty()) Bp.col(pair.dofs_a[d]) += pair.frame.col(d);
      if (!pair.dofs_b.empty()) Bp.col(pair.dofs_b[d]) -= pair.frame.col(d);
    }
    K += Bp.transpose() * k_local.asDiagonal() * Bp;
  }
  return K;
}

ModalResult stuck_modes(const PreparedModel& model, const CaseDefinition& def,
                        Eigen::MatrixXd* stiffness) {
  if (model.wave) {
    throw InvalidInput(def.where("analysis.frequency"),
                       "the stuck modes of a cyclic sector's nodal diameter are not computed yet");
  }
  Eigen::MatrixXd K_stuck = stuck_stiffness_matrix(model);
  ModalResult eig = dense_modes(K_stuck, model.M);  // Jacobi-scaled
  if (stiffness) *stiffness = std::move(K_stuck);
  if (!eig.summary.ok()) {
    throw InvalidInput(def.where("bodies"), "the reduced mass matrix is not positive definite");
  }
  return eig;
}

Eigen::VectorXd stuck_frequencies_hz(const PreparedModel& model, const CaseDefinition& def) {
  return stuck_modes(model, def).eigenvalues.cwiseMax(0.0).cwiseSqrt() / (2 * kPi);
}

std::vector<double> analysis_frequencies_hz(const PreparedModel& model, const CaseDefinition& def,
                                            SweepWindow* window) {
  const FrequencyDefinition& f = def.analysis.frequency;
  double start = f.start_hz, stop = f.stop_hz;
  if (f.kind == FrequencyDefinition::Kind::kAroundMode) {
    const Eigen::VectorXd stuck = stuck_frequencies_hz(model, def);
    if (f.around_mode > stuck.size()) {
      throw InvalidInput(def.where("analysis.frequency.around_mode"),
                         fmt::format("the model has only {} modes", stuck.size()));
    }
    const double centre = stuck(f.around_mode - 1);
    start = centre - f.half_width_hz;
    stop = centre + f.half_width_hz;
    if (!(start > 0)) {
      throw InvalidInput(
          def.where("analysis.frequency.half_width_hz"),
          fmt::format("window reaches below 0 Hz (mode {} at {:.6g} Hz)", f.around_mode, centre));
    }
    if (window) *window = {start, stop, f.around_mode, centre};
  } else if (window) {
    *window = {start, stop, 0, 0.0};
  }
  if (def.analysis.method == SweepMethod::kContinuation) {
    if (f.downward) return {stop, start};
    return {start, stop};
  }
  // `sweep: down` steps from stop by −step_hz: the same step, the other end first (another
  // branch where the response folds).
  std::vector<double> grid;
  const int n = static_cast<int>(std::floor((stop - start) / f.step_hz + 1e-9));
  if (f.downward) {
    for (int i = 0; i <= n; ++i) grid.push_back(stop - i * f.step_hz);
    if (grid.back() - start > 1e-9 * stop) grid.push_back(start);
    return grid;
  }
  for (int i = 0; i <= n; ++i) grid.push_back(start + i * f.step_hz);
  if (stop - grid.back() > 1e-9 * stop) grid.push_back(stop);
  return grid;
}

namespace {

// Refuses an analysis whose harmonic balance cannot fit in this machine's memory (an absurd
// `harmonics` or `time_samples`), at the key, before anything is allocated.
void check_memory(const PreparedModel& model, const CaseDefinition& def) {
  int rows = 0;
  for (const ContactPair& pair : model.pairs) rows += pair.element->dimension();
  const double needed = estimated_memory_bytes(rows, model.hbm);
  const double available =
      static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  if (available > 0 && needed > available) {
    throw InvalidInput(
        def.where("analysis.harmonics"),
        fmt::format("the harmonic balance would need about {:.1f} GB (contact rows {}, highest "
                    "harmonic {}, time samples {}) but this machine has {:.1f} GB: use fewer "
                    "harmonics or time_samples",
                    needed / 1e9, rows, def.analysis.max_harmonic(), def.analysis.time_samples,
                    available / 1e9));
  }
}

}  // namespace

std::string describe_window(const SweepWindow& w) {
  std::string text = fmt::format("sweep window {:.6g} to {:.6g} Hz", w.start_hz, w.stop_hz);
  if (w.stuck_mode > 0) {
    text += fmt::format(" around stuck mode {} at {:.6g} Hz (all contacts stuck)", w.stuck_mode,
                        w.stuck_mode_hz);
  }
  return text;
}

SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& def,
                      const ProgressFn& progress, const SweepProgress* sweep,
                      const SweepRunner* runner) {
  const auto t0 = Clock::now();
  SolvedCase solved;
  solved.warn_aft_fallback = def.analysis.aft_given && def.analysis.aft != AftChoice::kSampled;
  if (def.analysis.method == SweepMethod::kNonlinearMode) {
    throw InvalidInput(def.where("analysis.method"),
                       "a nonlinear mode is solved by solve_nonlinear_mode "
                       "(model/nonlinear_mode_case.h), not as a frequency response");
  }
  check_memory(model, def);
  check_mode_prediction(model, def);
  if (model.pairs.empty() && def.analysis.method == SweepMethod::kContinuation) {
    throw InvalidInput(def.where("analysis.method"),
                       "a model without contacts is linear: its response is computed at the "
                       "frequencies of a stepped sweep (method: stepped, with step_hz), there is "
                       "no nonlinear curve for the continuation to follow");
  }
  if (model.wave) {  // a cyclic sector: its travelling wave (model/cyclic_forced_response.h)
    solved.system = std::make_unique<HarmonicBalanceSystem>(
        model.linear, model.pairs, model.excitation, model.hbm, *model.wave);
  } else {
    solved.system = std::make_unique<HarmonicBalanceSystem>(model.linear, model.pairs,
                                                            model.excitation, model.hbm);
  }
  if (!solved.system->static_summary().converged() &&
      model.hbm.static_coupling == StaticCoupling::kUncoupled && !model.pairs.empty()) {
    throw InvalidInput(
        def.where("analysis.static"),
        "the static contact problem did not converge: " + solved.system->static_summary().message);
  }
  if (progress && !solved.system->damping_matrix_note().empty()) {
    progress("modal damping matrix: one complex LU per frequency and harmonic (slower) because " +
             solved.system->damping_matrix_note());
  }
  solved.frequencies_hz = analysis_frequencies_hz(model, def, &solved.window);
  if (progress) progress(describe_window(solved.window));
  const AnalysisDefinition& an = def.analysis;
  FrequencyResponseOptions o;
  o.stability = an.stability;
  o.initial_guess =
      an.initial_guess == InitialGuessChoice::kFree ? InitialGuess::kLinearFree
                                                    : InitialGuess::kLinearStuck;
  NewtonOptions newton;
  newton.tolerance = an.tolerance;
  newton.max_iterations = an.max_iterations;
  for (const auto& [contact, indices] : def.output.histories) {
    int first = -1, count = 0;
    for (size_t i = 0; i < model.pair_info.size(); ++i) {
      if (def.contacts[model.pair_info[i].contact].name == contact) {
        if (first < 0) first = static_cast<int>(i);
        ++count;
      }
    }
    for (int j : indices) {
      if (j < 0 || j >= count) {
        throw InvalidInput(
            def.where("output.histories." + contact),
            fmt::format("pair {} out of range: contact {} has {} pairs", j, contact, count));
      }
      o.history_pairs.push_back(first + j);
    }
  }
  if (an.method == SweepMethod::kContinuation) {
    o.method = ContinuationMethod::kArcLength;
    const FrequencyDefinition& f = an.frequency;
    o.arclength.lambda_start = hz_to_rad_s(solved.frequencies_hz.front());
    o.arclength.lambda_end = hz_to_rad_s(solved.frequencies_hz.back());
    const double range = std::abs(o.arclength.lambda_end - o.arclength.lambda_start);
    o.arclength.initial_step = hz_to_rad_s(f.step_hz);
    o.arclength.min_step = f.min_step_hz > 0 ? hz_to_rad_s(f.min_step_hz) : range * 1e-7;
    // max_step_hz bounds the frequency's advance per step; the arc-length step itself is set by
    // the Newton iterations and the curvature (arclength.h, 4.), so that the flanks of a
    // resonance, where the response changes at nearly constant frequency, take few points when
    // they are straight.
    o.arclength.max_lambda_step = f.max_step_hz > 0 ? hz_to_rad_s(f.max_step_hz)
                                                    : std::max(range / 20, o.arclength.initial_step);
    o.arclength.max_step = std::max(1e3 * range, o.arclength.initial_step);
    o.arclength.target_turn_angle = kContinuationTurnAngle;
    o.arclength.max_points = an.max_points;
    o.arclength.newton = newton;
    // The FRF DOFs' peaks are located between the points (frequency_response.h, PeakOptions):
    // summary.json and the plots give the located maximum, not the largest sampled point.
    for (const ResponseDofDefinition& r : def.output.frf) {
      const int b = model.body_index(r.body);
      const int g = b < 0 ? -1 : model.bodies[b].global_dof(r.node, r.direction);
      if (g >= 0) o.peaks.dofs.push_back(g);
    }
  } else {
    o.method = ContinuationMethod::kSteppedSweep;
    for (double hz : solved.frequencies_hz) o.omegas.push_back(hz_to_rad_s(hz));
    o.sweep.newton = newton;
    o.sweep.secant_predictor = an.predictor == PredictorChoice::kSecant;
  }
  if (progress) {
    progress(fmt::format(
        "harmonic balance: {} pairs, {} unknowns, {} {}", model.pairs.size(), solved.system->size(),
        an.method == SweepMethod::kContinuation ? "continuation over" : std::to_string(o.omegas.size()),
        an.method == SweepMethod::kContinuation ? "the range" : "points"));
  }
  if (sweep && sweep->start) {
    sweep->start("harmonic balance", static_cast<int>(o.omegas.size()));  // 0: continuation
  }
  if (sweep && sweep->on_point) o.sweep.on_point = o.arclength.on_point = sweep->on_point;
  const bool run_elsewhere = runner && *runner && o.method == ContinuationMethod::kSteppedSweep;
  solved.response = run_elsewhere ? (*runner)(*solved.system, o) : frequency_response(*solved.system, o);
  if (sweep && sweep->finish) sweep->finish();
  if (an.predict_from_mode) predict_from_nonlinear_mode(model, def, progress, sweep, solved);
  solved.seconds_solve = seconds_since(t0);
  return solved;
}

}  // namespace stickslip

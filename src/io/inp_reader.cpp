#include "io/inp_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/errors.h"
#include "fe/element.h"
#include "io/text.h"

namespace stickslip {
namespace {

using text::lower;
using text::rtrim;
using text::split_whitespace;
using text::split_commas;
using text::trim;
using text::upper;

// Upper case, internal runs of white space collapsed to one blank ("*Solid  section").
std::string normalize_name(const std::string& s) {
  std::string out;
  bool blank = false;
  for (char c : trim(s)) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      blank = true;
      continue;
    }
    if (blank && !out.empty()) out += ' ';
    blank = false;
    out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

struct Keyword {
  std::string name;                                         // e.g. "*ELEMENT"
  std::vector<std::pair<std::string, std::string>> params;  // (KEY, value); value may be empty
  int line = 0;
};

struct RawNode {
  int id;
  Eigen::Vector3d x;
  int line;
};

struct RawElement {
  int id;
  ElementType type;
  std::vector<int> node_ids;
  int line;
};

// One item of a set definition: an id, a generated range or the name of another set.
struct SetItem {
  enum class Kind { kId, kRange, kName } kind;
  int first = 0, last = 0, step = 1;
  std::string name;
  int line = 0;
};

// One *EQUATION: the number of terms announced, then (node id, direction 1-3, coefficient) terms.
struct RawEquation {
  int num_terms = 0;
  std::vector<int> node_ids;
  std::vector<int> directions;  // 0-2
  std::vector<double> coefficients;
  int line = 0;  // its first data line
};

// A SPRING1 / SPRING2 / SPRINGA / MASS element: its kind, nodes and the ELSET of its *ELEMENT
// line (its *SPRING or *MASS is found through that set).
enum class DiscreteKind { kSpring1, kSpring2, kSpringA, kMass };
struct RawDiscrete {
  int id;
  DiscreteKind kind;
  std::vector<int> node_ids;
  std::string elset;
  int line;
};

// *SPRING (directions 0-2, -1 = none given) or *MASS data for an element set.
struct DiscreteProperty {
  bool spring;
  std::string elset;
  int dof_a = -1, dof_b = -1;
  bool has_value = false;
  double value = 0.0;  // N/m or kg
  int line;            // the keyword's line
};

// One *BOUNDARY data line: a node id or set name, DOFs first..last (0-based, capped at 2).
struct RawBoundary {
  std::string target;
  int first = 0, last = 2;
  std::string unsupported;
  int line = 0;
};

struct SetDefinition {
  bool is_node_set;
  std::string name;
  std::vector<SetItem> items;
};

// A *SOLID SECTION: the material of an element set.
struct Section {
  std::string elset, material;
  int line;
};
// What a part, an instance or the model holds until the mesh is resolved.
struct Items {
  std::vector<RawNode> nodes;
  std::vector<RawElement> elements;
  std::vector<SetDefinition> sets;
  std::vector<RawEquation> equations;
  std::vector<RawDiscrete> discretes;
  std::vector<DiscreteProperty> properties;
  std::vector<Section> sections;
  void append(Items&& o) {
    const auto add = [](auto& to, auto& from) {
      to.insert(to.end(), std::make_move_iterator(from.begin()),
                std::make_move_iterator(from.end()));
    };
    add(nodes, o.nodes);
    add(elements, o.elements);
    add(sets, o.sets);
    add(equations, o.equations);
    add(discretes, o.discretes);
    add(properties, o.properties);
    add(sections, o.sections);
  }
};
struct PartDefinition {
  Items items;
  int line = 0;
  bool used = false;
};
struct InstanceInfo {
  std::string name;  // upper case
  int node_offset = 0, element_offset = 0;
  int line = 0;
};

// Keywords that would change the stiffness or mass of the model and that the reader does not
// support: refused at their line, with the reason.
struct Refusal {
  const char* name;
  const char* reason;
};
constexpr Refusal kRefused[] = {
    {"*MPC", "multi-point constraints tie DOFs together"},
    {"*TIE", "tied surfaces tie DOFs together"},
    {"*COUPLING", "a coupling ties DOFs to a reference node"},
    {"*KINEMATIC", "a kinematic coupling ties DOFs to a reference node"},
    {"*KINEMATIC COUPLING", "a kinematic coupling ties DOFs to a reference node"},
    {"*DISTRIBUTING", "a distributing coupling ties DOFs to a reference node"},
    {"*DISTRIBUTING COUPLING", "a distributing coupling ties DOFs to a reference node"},
    {"*RIGID BODY", "a rigid body ties DOFs to a reference node"},
    {"*PRE-TENSION SECTION", "a pre-tension section adds constraints"},
    {"*CYCLIC SYMMETRY MODEL", "cyclic symmetry constraints are not read from decks"},
    {"*SHELL SECTION", "shell elements are not supported (solids only)"},
    {"*MEMBRANE SECTION", "membrane elements are not supported (solids only)"},
    {"*BEAM SECTION", "beam elements are not supported (solids only)"},
    {"*BEAM GENERAL SECTION", "beam elements are not supported (solids only)"},
    {"*DASHPOT", "dashpot elements are not supported"},
    {"*ROTARY INERTIA", "rotary inertia is not supported"},
    {"*GAP", "gap elements are not supported"},
    {"*USER ELEMENT", "user elements are not supported"},
    {"*MATRIX", "matrix input is not supported"},
    {"*MATRIX INPUT", "matrix input is not supported"},
    {"*SUBSTRUCTURE PROPERTY", "substructures are not supported"},
    {"*NGEN", "node generation is not supported (write the nodes out)"},
    {"*NFILL", "node generation is not supported (write the nodes out)"},
    {"*NCOPY", "node generation is not supported (write the nodes out)"},
    {"*NMAP", "node mapping is not supported (write the nodes out)"},
    {"*ELGEN", "element generation is not supported (write the elements out)"},
    {"*ELCOPY", "element generation is not supported (write the elements out)"},
};

// Why a keyword the reader skips does not matter to stickslip (the warning's hint).
const char* skip_hint(const std::string& name) {
  if (name == "*PLASTIC" || name == "*EXPANSION" || name == "*CONDUCTIVITY" ||
      name == "*SPECIFIC HEAT" || name == "*HYPERELASTIC" || name == "*CREEP")
    return "linear elastic materials only";
  if (name == "*BOUNDARY")
    return "clamps come from the case file, unless a body's supports say from_mesh: true";
  if (name == "*STEP" || name == "*END STEP" || name == "*STATIC" || name == "*FREQUENCY" ||
      name == "*CLOAD" || name == "*DLOAD" || name == "*STEADY STATE DYNAMICS")
    return "analyses and loads come from the case file";
  if (name == "*CONTACT PAIR" || name == "*SURFACE INTERACTION" || name == "*FRICTION")
    return "contacts come from the case file";
  return "not used by stickslip";
}

class InpParser {
 public:
  InpParser(std::string file, std::vector<std::string>* warnings)
      : file_(std::move(file)), warnings_(warnings) {}

  Mesh parse(std::istream& in) {
    files_.push_back(file_);
    std::error_code ec;
    include_stack_.push_back(std::filesystem::weakly_canonical(file_, ec));
    read_stream(in, 0);
    finish_element_block();
    finish_parts();
    Mesh mesh = resolve();
    report_skipped();
    return mesh;
  }

 private:
  // Reads the lines of one file (index into files_). Lines are numbered globally across the
  // included files (loc_file_, loc_line_ map them back).
  void read_stream(std::istream& in, int file_index) {
    std::string text;
    int number = 0;
    while (std::getline(in, text)) {
      ++number;
      loc_file_.push_back(file_index);
      loc_line_.push_back(number);
      const int g = static_cast<int>(loc_line_.size()) - 1;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      const std::string t = trim(text);
      if (t.empty() || t.rfind("**", 0) == 0) continue;
      if (t[0] == '*') {
        const Keyword k = parse_keyword(t, g);
        if (k.name == "*INCLUDE") {
          include(k, file_index);  // textual: the mode of the keyword before it carries on
          continue;
        }
        finish_element_block();
        start_keyword(k);
      } else {
        data_line(t, g);
      }
    }
    if (in.bad()) throw InvalidInput({files_[file_index], number, ""}, "read error");
  }

  // *INCLUDE, INPUT=path: path relative to the including file's folder; nested includes are
  // read in place; a file that includes itself (directly or through others) is refused.
  void include(const Keyword& k, int file_index) {
    check_params(k, {"INPUT"});
    const auto input = param(k, "INPUT");
    if (!input) fail(k.line, "*INCLUDE without INPUT=");
    namespace fs = std::filesystem;
    fs::path path(*input);
    if (path.is_relative()) path = fs::path(files_[file_index]).parent_path() / path;
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    for (const fs::path& open : include_stack_) {
      if (!ec && open == canonical) {
        fail(k.line, "*INCLUDE of " + path.string() +
                         ", which is already being read: the includes form a cycle");
      }
    }
    constexpr size_t kMaxIncludeDepth = 64;
    if (include_stack_.size() >= kMaxIncludeDepth) {
      fail(k.line, "*INCLUDE nested deeper than " + std::to_string(kMaxIncludeDepth) + " files");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(k.line, "*INCLUDE: cannot open " + path.string());
    files_.push_back(path.string());
    include_stack_.push_back(canonical);
    read_stream(in, static_cast<int>(files_.size()) - 1);
    include_stack_.pop_back();
  }

  // "line L" (of the top file) or "line L of FILE" (an included file), for messages.
  std::string line_text(int g) const {
    const int f = g > 0 ? loc_file_[g] : 0;
    const std::string line = "line " + std::to_string(g > 0 ? loc_line_[g] : 0);
    return f == 0 ? line : line + " of " + files_[f];
  }
  std::string origin(int g) const {
    return files_[g > 0 ? loc_file_[g] : 0] + ":" + std::to_string(g > 0 ? loc_line_[g] : 0);
  }

  [[noreturn]] void fail(int line, const std::string& what) const {
    if (line <= 0) throw InvalidInput({file_, 0, ""}, what);
    throw InvalidInput({files_[loc_file_[line]], loc_line_[line], ""}, what);
  }

  Keyword parse_keyword(const std::string& t, int line) const {
    Keyword k;
    k.line = line;
    const std::vector<std::string> parts = split_commas(t);
    k.name = normalize_name(parts[0]);
    for (size_t i = 1; i < parts.size(); ++i) {
      if (parts[i].empty()) {
        if (i + 1 == parts.size()) break;  // tolerate a trailing comma
        fail(line, k.name + ": empty parameter");
      }
      const size_t eq = parts[i].find('=');
      std::string key = normalize_name(parts[i].substr(0, eq));
      std::string value = eq == std::string::npos ? "" : trim(parts[i].substr(eq + 1));
      if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
        value = value.substr(1, value.size() - 2);
      }
      if (eq != std::string::npos && value.empty()) {
        fail(line, k.name + ": parameter " + key + " has no value");
      }
      k.params.emplace_back(std::move(key), std::move(value));
    }
    return k;
  }

  // Checks that every parameter is one of `allowed`; returns the value of each requested key.
  void check_params(const Keyword& k, std::initializer_list<const char*> allowed) const {
    for (const auto& [key, value] : k.params) {
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      if (!ok) fail(k.line, k.name + ": unsupported parameter " + key);
    }
  }
  static std::optional<std::string> param(const Keyword& k, const std::string& key) {
    for (const auto& [kk, v] : k.params) {
      if (kk == key) return v;
    }
    return std::nullopt;
  }

  // One warning per skipped keyword name, in order of first appearance, with its lines.
  void report_skipped() const {
    if (warnings_ == nullptr) return;
    constexpr size_t kMaxLinesListed = 10;
    for (const auto& [key, lines] : skipped_) {
      const auto& [file, name] = key;
      std::string where;
      for (size_t i = 0; i < lines.size() && i < kMaxLinesListed; ++i) {
        where += (i ? ", " : "") + std::to_string(loc_line_[lines[i]]);
      }
      if (lines.size() > kMaxLinesListed) {
        where += " and " + std::to_string(lines.size() - kMaxLinesListed) + " more";
      }
      warnings_->push_back(files_[file] + ": " + name + " ignored (" + skip_hint(name) + "), line" +
                           (lines.size() > 1 ? "s " : " ") + where);
    }
  }

  void skip(const Keyword& k) {
    const std::pair<int, std::string> key{loc_file_[k.line], k.name};
    for (auto& [kk, lines] : skipped_) {
      if (kk == key) {
        lines.push_back(k.line);
        return;
      }
    }
    skipped_.push_back({key, {k.line}});
  }

  void start_keyword(const Keyword& k) {
    keyword_ = k;
    mode_ = Mode::kSkip;
    current_set_ = -1;
    for (const Refusal& r : kRefused) {
      if (k.name == r.name) {
        fail(k.line, k.name + " is not supported: " + r.reason +
                         "; it would change the stiffness or mass, so the deck is refused");
      }
    }
    if (part_keyword(k)) return;
    if (block_ == Block::kPart || block_ == Block::kInstance) {
      if (k.name == "*BOUNDARY" || k.name == "*MATERIAL" || k.name == "*STEP") {
        fail(k.line, k.name + " inside *" + (block_ == Block::kPart ? "PART" : "INSTANCE") +
                         " " + block_name_ + " is not supported: give it at model level");
      }
    }
    if (uses_parts_ && (block_ == Block::kModel || block_ == Block::kAssembly) &&
        k.name == "*NODE") {
      fail(k.line, std::string("*NODE ") +
                       (block_ == Block::kAssembly ? "in the *ASSEMBLY (a reference point)"
                                                   : "outside the parts") +
                       " is not supported in a deck with parts: nodes belong to parts or "
                       "instances");
    }
    if (k.name == "*NODE") {
      check_params(k, {"NSET"});
      mode_ = Mode::kNode;
      if (auto n = param(k, "NSET")) current_set_ = new_set(true, *n, k.line);
    } else if (k.name == "*ELEMENT") {
      check_params(k, {"TYPE", "ELSET"});
      const auto type = param(k, "TYPE");
      if (!type) fail(k.line, "*ELEMENT without TYPE=");
      const std::string t = upper(*type);
      if (t == "SPRING1" || t == "SPRING2" || t == "SPRINGA" || t == "MASS") {
        discrete_kind_ = t == "SPRING1"   ? DiscreteKind::kSpring1
                         : t == "SPRING2" ? DiscreteKind::kSpring2
                         : t == "SPRINGA" ? DiscreteKind::kSpringA
                                          : DiscreteKind::kMass;
        const auto elset = param(k, "ELSET");
        if (!elset)
          fail(k.line, "*ELEMENT, TYPE=" + t +
                           " without ELSET= (its *SPRING or *MASS "
                           "names that set)");
        discrete_elset_ = upper(*elset);
        mode_ = Mode::kDiscrete;
        return;
      }
      if (uses_parts_ && (block_ == Block::kModel || block_ == Block::kAssembly)) {
        fail(k.line, "*ELEMENT, TYPE=" + upper(*type) +
                         " outside the parts: in a deck with parts only springs and masses "
                         "(SPRING1, SPRING2, SPRINGA, MASS) may join instances at assembly level");
      }
      if (!parse_element_type(*type, &element_type_)) {
        fail(k.line, "*ELEMENT: unsupported element type " + upper(*type) +
                         " (supported: C3D8, C3D8I, C3D8R, C3D8B, C3D20, C3D20R, C3D4, C3D10, "
                         "C3D6, C3D15, C3D5, C3D13)");
      }
      mode_ = Mode::kElement;
      if (auto n = param(k, "ELSET")) current_set_ = new_set(false, *n, k.line);
    } else if (k.name == "*NSET" || k.name == "*ELSET") {
      const bool node = k.name == "*NSET";
      const char* key = node ? "NSET" : "ELSET";
      check_params(k, {key, "GENERATE", "UNSORTED", "INTERNAL", "INSTANCE"});
      const auto n = param(k, key);
      if (!n) fail(k.line, k.name + " without " + key + "=");
      current_set_ = new_set(node, *n, k.line);
      generate_ = param(k, "GENERATE").has_value();
      set_instance_ = -1;
      if (const auto instance = param(k, "INSTANCE")) {
        if (block_ != Block::kAssembly && block_ != Block::kModel) {
          fail(k.line, k.name + ", INSTANCE=" + *instance + " inside *" +
                           (block_ == Block::kPart ? "PART" : "INSTANCE") +
                           ": INSTANCE= belongs to sets of the assembly");
        }
        set_instance_ = instance_index(*instance, k.line);
      }
      mode_ = Mode::kSet;
    } else if (k.name == "*EQUATION") {
      check_params(k, {});
      mode_ = Mode::kEquation;
    } else if (k.name == "*MATERIAL") {
      check_params(k, {"NAME"});
      const auto name = param(k, "NAME");
      if (!name) fail(k.line, "*MATERIAL without NAME=");
      for (const MeshMaterial& m : materials_) {
        if (m.name == upper(*name)) fail(k.line, "*MATERIAL " + upper(*name) + " defined twice");
      }
      materials_.push_back({upper(*name), kNaN, kNaN, kNaN, origin(k.line), ""});
    } else if (k.name == "*ELASTIC" || k.name == "*DENSITY") {
      if (materials_.empty()) fail(k.line, k.name + " before any *MATERIAL");
      if (k.name == "*ELASTIC") {
        check_params(k, {"TYPE"});
        const auto type = param(k, "TYPE");
        if (type && upper(*type) != "ISO" && upper(*type) != "ISOTROPIC") {
          materials_.back().problem = "*ELASTIC, TYPE=" + upper(*type) + " on " +
                                      line_text(k.line) +
                                      ": only isotropic elasticity is supported";
        }
      } else {
        check_params(k, {});
      }
      property_lines_ = 0;
      mode_ = k.name == "*ELASTIC" ? Mode::kElastic : Mode::kDensity;
    } else if (k.name == "*SOLID SECTION") {
      check_params(k, {"ELSET", "MATERIAL", "ORIENTATION"});
      const auto elset = param(k, "ELSET"), material = param(k, "MATERIAL");
      if (!elset || !material) fail(k.line, "*SOLID SECTION needs ELSET= and MATERIAL=");
      sections_.push_back({upper(*elset), upper(*material), k.line});
      mode_ = Mode::kSkip;  // a data line (2D thickness) does not matter for solids
    } else if (k.name == "*SPRING" || k.name == "*MASS") {
      const bool spring = k.name == "*SPRING";
      for (const auto& [key, value] : k.params) {
        if (key == "NONLINEAR")
          fail(k.line, "*SPRING, NONLINEAR: nonlinear springs are not supported");
        if (key == "ORIENTATION") {
          fail(k.line, k.name + ", ORIENTATION: springs in local axes are not supported");
        }
      }
      check_params(k, {"ELSET"});
      const auto elset = param(k, "ELSET");
      if (!elset) fail(k.line, k.name + " without ELSET=");
      properties_.push_back({spring, upper(*elset), -1, -1, false, 0.0, k.line});
      mode_ = Mode::kProperty;
    } else if (k.name == "*BOUNDARY") {
      skip(k);  // listed in the warning: recorded, applied only on request
      mode_ = Mode::kBoundary;
      boundary_type_.clear();
      for (const auto& [key, value] : k.params) {
        if (key == "TYPE" && upper(value) != "DISPLACEMENT") {
          boundary_type_ = "*BOUNDARY, TYPE=" + value + " (only displacements are supports)";
        } else if (key != "TYPE" && key != "OP" && key != "AMPLITUDE" && key != "FIXED" &&
                   key != "USER" && key != "LOAD CASE" && key != "SUBMODEL" && key != "STEP") {
          boundary_type_ = "*BOUNDARY parameter " + key;
        } else if (key == "USER" || key == "SUBMODEL" || key == "FIXED") {
          boundary_type_ = "*BOUNDARY, " + key;
        }
      }
    } else {
      skip(k);
    }
  }

  // ---- parts, assemblies and instances (Abaqus/CAE decks) ----------------------------------
  //
  // A part's items (nodes, elements, sets, equations, springs, masses, sections) are recorded
  // apart while *PART is open; each *INSTANCE copies them (plus whatever the instance block
  // defines itself), places the nodes by its data lines, renumbers ids after those of the
  // instances above and prefixes the names of its sets with "INSTANCE.", then adds them to the
  // model. References from the assembly ("INSTANCE.12", "INSTANCE.SET", INSTANCE= on a set) are
  // resolved when read, since instances come before the items that use them.

  // Handles *PART, *END PART, *ASSEMBLY, *END ASSEMBLY, *INSTANCE and *END INSTANCE; false for
  // any other keyword.
  bool part_keyword(const Keyword& k) {
    const std::string& n = k.name;
    const bool begins = n == "*PART" || n == "*ASSEMBLY" || n == "*INSTANCE";
    const bool ends = n == "*END PART" || n == "*END ASSEMBLY" || n == "*END INSTANCE";
    if (!begins && !ends) return false;
    if (ends) {
      check_params(k, {});
      const Block expected = n == "*END PART"       ? Block::kPart
                             : n == "*END ASSEMBLY" ? Block::kAssembly
                                                    : Block::kInstance;
      if (block_ != expected) {
        fail(k.line, n + " without its *" + n.substr(5) +
                         (block_ == Block::kModel ? "" : " (" + open_block_text() + " is open)"));
      }
      if (expected == Block::kPart) {
        parts_[block_name_] = PartDefinition{take_items(), block_line_, false};
        put_items(std::move(stash_));
        block_ = Block::kModel;
      } else if (expected == Block::kInstance) {
        end_instance();
        block_ = Block::kAssembly;
      } else {
        block_ = Block::kModel;
      }
      return true;
    }
    if (n == "*INSTANCE") {
      if (param(k, "LIBRARY")) {
        fail(k.line, "*INSTANCE, LIBRARY=: instances of substructure libraries are not supported");
      }
      check_params(k, {"NAME", "PART"});
      if (block_ != Block::kAssembly) {
        fail(k.line, "*INSTANCE outside an *ASSEMBLY" +
                         (block_ == Block::kModel ? "" : " (" + open_block_text() + " is open)"));
      }
      const auto name = param(k, "NAME"), part = param(k, "PART");
      if (!name || !part) fail(k.line, "*INSTANCE needs NAME= and PART=");
      const auto it = parts_.find(upper(*part));
      if (it == parts_.end()) {
        fail(k.line, "*INSTANCE " + upper(*name) + ": unknown part " + upper(*part) +
                         " (parts are defined by *PART ... *END PART above the assembly)");
      }
      for (const InstanceInfo& other : instances_) {
        if (other.name == upper(*name)) {
          fail(k.line, "*INSTANCE " + other.name + " defined twice (first on " +
                           line_text(other.line) + ")");
        }
      }
      it->second.used = true;
      stash_ = take_items();
      put_items(Items(it->second.items));
      block_ = Block::kInstance;
      block_name_ = upper(*name);
      block_line_ = k.line;
      translation_.setZero();
      rotation_.setIdentity();
      rotation_point_.setZero();
      position_lines_ = 0;
      mode_ = Mode::kInstance;
      return true;
    }
    check_params(k, {"NAME"});
    const auto name = param(k, "NAME");
    if (n == "*PART" && !name) fail(k.line, "*PART without NAME=");
    if (block_ != Block::kModel) {
      fail(k.line, n + " inside " + open_block_text() + ": parts and the assembly are defined " +
                       "at model level");
    }
    if (!uses_parts_ && (!nodes_.empty() || !elements_.empty() || !discretes_.empty())) {
      const int first = !nodes_.empty() ? nodes_[0].line
                        : !elements_.empty() ? elements_[0].line
                                             : discretes_[0].line;
      fail(k.line, n + " after nodes or elements outside any part (" + line_text(first) +
                       "): a deck has its mesh either in parts or flat, not both");
    }
    uses_parts_ = true;
    if (n == "*ASSEMBLY") {
      if (assembly_line_ > 0) {
        fail(k.line, "a second *ASSEMBLY (the first on " + line_text(assembly_line_) + ")");
      }
      assembly_line_ = k.line;
      block_ = Block::kAssembly;
      block_name_ = name ? upper(*name) : "";
      block_line_ = k.line;
      return true;
    }
    const std::string key = upper(*name);
    if (parts_.count(key)) {
      fail(k.line, "*PART " + key + " defined twice (first on " + line_text(parts_[key].line) + ")");
    }
    stash_ = take_items();
    block_ = Block::kPart;
    block_name_ = key;
    block_line_ = k.line;
    return true;
  }

  std::string open_block_text() const {
    switch (block_) {
      case Block::kPart:
        return "*PART " + block_name_ + " of " + line_text(block_line_);
      case Block::kInstance:
        return "*INSTANCE " + block_name_ + " of " + line_text(block_line_);
      case Block::kAssembly:
        return "the *ASSEMBLY of " + line_text(block_line_);
      case Block::kModel:
        break;
    }
    return "the model";
  }

  // An *INSTANCE's data lines: the translation "dx, dy, dz", then optionally the rotation
  // "ax, ay, az, bx, by, bz, angle": by angle degrees about the axis from point a to point b
  // (right-hand rule), applied after the translation (Abaqus keyword reference, *INSTANCE).
  void instance_position(const std::vector<std::string>& tokens, int line) {
    if (position_lines_ == 0) {
      if (tokens.size() != 3) {
        fail(line, "*INSTANCE: the first data line is the translation 'dx, dy, dz', got " +
                       std::to_string(tokens.size()) + " values");
      }
      for (int d = 0; d < 3; ++d) translation_(d) = parse_double(tokens[d], line);
    } else if (position_lines_ == 1) {
      if (tokens.size() != 7) {
        fail(line,
             "*INSTANCE: the second data line is the rotation 'ax, ay, az, bx, by, bz, angle' "
             "(degrees about the axis from a to b), got " +
                 std::to_string(tokens.size()) + " values");
      }
      Eigen::Vector3d a, b;
      for (int d = 0; d < 3; ++d) {
        a(d) = parse_double(tokens[d], line);
        b(d) = parse_double(tokens[3 + d], line);
      }
      const double angle = parse_double(tokens[6], line);
      if (!((b - a).norm() > 0.0)) {
        fail(line, "*INSTANCE: the rotation axis has zero length (points a and b coincide)");
      }
      rotation_ = Eigen::AngleAxisd(angle * std::acos(-1.0) / 180.0, (b - a).normalized())
                      .toRotationMatrix();
      rotation_point_ = a;
    } else {
      fail(line, "*INSTANCE: more than two data lines (translation, rotation)");
    }
    ++position_lines_;
  }

  // *END INSTANCE: the instance's items placed, renumbered after everything above and named
  // "INSTANCE.NAME", with an element set "INSTANCE" of all its elements, into the model.
  void end_instance() {
    Items inst = take_items();
    int node_offset = 0, element_offset = 0;
    for (const RawNode& n : stash_.nodes) node_offset = std::max(node_offset, n.id);
    for (const RawElement& e : stash_.elements) element_offset = std::max(element_offset, e.id);
    for (const RawDiscrete& d : stash_.discretes) element_offset = std::max(element_offset, d.id);
    const std::string q = block_name_ + ".";
    for (RawNode& n : inst.nodes) {
      n.id += node_offset;
      n.x = rotation_point_ + rotation_ * (n.x + translation_ - rotation_point_);
    }
    SetDefinition all{false, block_name_, {}};
    for (RawElement& e : inst.elements) {
      e.id += element_offset;
      for (int& id : e.node_ids) id += node_offset;
      all.items.push_back({SetItem::Kind::kId, e.id, 0, 1, "", e.line});
    }
    for (SetDefinition& set : inst.sets) {
      set.name = q + set.name;
      const int offset = set.is_node_set ? node_offset : element_offset;
      for (SetItem& item : set.items) {
        if (item.kind == SetItem::Kind::kName) {
          item.name = q + item.name;
        } else {
          item.first += offset;
          item.last += offset;
        }
      }
    }
    inst.sets.insert(inst.sets.begin(), std::move(all));
    for (RawEquation& eq : inst.equations) {
      for (int& id : eq.node_ids) id += node_offset;
    }
    for (RawDiscrete& d : inst.discretes) {
      d.id += element_offset;
      for (int& id : d.node_ids) id += node_offset;
      d.elset = q + d.elset;
    }
    for (DiscreteProperty& p : inst.properties) p.elset = q + p.elset;
    for (Section& sec : inst.sections) sec.elset = q + sec.elset;
    instances_.push_back({block_name_, node_offset, element_offset, block_line_});
    stash_.append(std::move(inst));
    put_items(std::move(stash_));
  }

  // End of the deck: every block closed; parts never instanced are reported.
  void finish_parts() {
    if (block_ != Block::kModel) {
      const char* end = block_ == Block::kPart       ? "*END PART"
                        : block_ == Block::kInstance ? "*END INSTANCE"
                                                     : "*END ASSEMBLY";
      fail(block_line_, open_block_text() + " has no " + end + " before the end of the deck");
    }
    if (warnings_ == nullptr) return;
    for (const auto& [name, part] : parts_) {
      if (!part.used) {
        warnings_->push_back(files_[loc_file_[part.line]] + ": *PART " + name +
                             " ignored (no *INSTANCE of it), line " +
                             std::to_string(loc_line_[part.line]));
      }
    }
  }

  int instance_index(const std::string& name, int line) const {
    for (size_t i = 0; i < instances_.size(); ++i) {
      if (instances_[i].name == upper(name)) return static_cast<int>(i);
    }
    fail(line, keyword_.name + ": unknown instance " + upper(name) +
                   (uses_parts_ ? " (instances are defined by *INSTANCE in the assembly above)"
                                : " (the deck has no *INSTANCE)"));
  }

  // "INSTANCE.12" in a deck with parts, at assembly or model level.
  bool qualified_number(const std::string& token) const {
    const size_t dot = token.find('.');
    if (!uses_parts_ || dot == std::string::npos || dot == 0 || dot + 1 == token.size()) {
      return false;
    }
    return std::all_of(token.begin() + static_cast<long>(dot) + 1, token.end(),
                       [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
  }

  bool at_assembly_level() const {
    return uses_parts_ && (block_ == Block::kAssembly || block_ == Block::kModel);
  }

  // The (model-wide) id of a node or element named by `token`: "INSTANCE.12" or, in a part or
  // instance block or a deck without parts, "12".
  int reference(const std::string& token, int line, bool node) const {
    const char* what = node ? "node id" : "element id";
    if (qualified_number(token)) {
      if (!at_assembly_level()) {
        fail(line, keyword_.name + ": " + token + " inside " + open_block_text() +
                       " (ids inside a part or an instance are its own, unqualified)");
      }
      const size_t dot = token.find('.');
      const InstanceInfo& inst = instances_[instance_index(token.substr(0, dot), line)];
      return parse_id(token.substr(dot + 1), line, what) +
             (node ? inst.node_offset : inst.element_offset);
    }
    if (node && at_assembly_level()) {
      fail(line, keyword_.name + ": node " + token +
                     " at assembly level: nodes belong to instances; write INSTANCE." + token);
    }
    return parse_id(token, line, what);
  }
  int node_reference(const std::string& token, int line) const {
    return reference(token, line, true);
  }
  int element_reference(const std::string& token, int line) const {
    return reference(token, line, false);
  }

  // Added to plain ids of a set's data lines: the instance's offset for a set with INSTANCE=;
  // at assembly level elements of the assembly (springs, masses) follow the instances above.
  int set_id_offset(bool node, int line) {
    if (set_instance_ >= 0) {
      const InstanceInfo& inst = instances_[set_instance_];
      return node ? inst.node_offset : inst.element_offset;
    }
    if (!at_assembly_level()) return 0;
    if (node) {
      fail(line, keyword_.name + ": plain node ids at assembly level: nodes belong to "
                                 "instances; write INSTANCE.id or give INSTANCE= on the set");
    }
    return assembly_element_offset();
  }

  // Ids of springs and masses defined at assembly level are shifted past the elements of the
  // instances defined before the first of them (fixed then; later instances follow them).
  int assembly_element_offset() {
    if (!at_assembly_level()) return 0;
    if (assembly_element_offset_ < 0) {
      assembly_element_offset_ = 0;
      for (const RawElement& e : elements_) {
        assembly_element_offset_ = std::max(assembly_element_offset_, e.id);
      }
      for (const RawDiscrete& d : discretes_) {
        assembly_element_offset_ = std::max(assembly_element_offset_, d.id);
      }
    }
    return assembly_element_offset_;
  }

  Items take_items() {
    Items t;
    std::swap(t.nodes, nodes_);
    std::swap(t.elements, elements_);
    std::swap(t.sets, sets_);
    std::swap(t.equations, equations_);
    std::swap(t.discretes, discretes_);
    std::swap(t.properties, properties_);
    std::swap(t.sections, sections_);
    return t;
  }
  void put_items(Items&& t) {
    nodes_ = std::move(t.nodes);
    elements_ = std::move(t.elements);
    sets_ = std::move(t.sets);
    equations_ = std::move(t.equations);
    discretes_ = std::move(t.discretes);
    properties_ = std::move(t.properties);
    sections_ = std::move(t.sections);
  }

  int new_set(bool node, const std::string& name, int line) {
    if (name.empty()) fail(line, "empty set name");
    sets_.push_back({node, upper(name), {}});
    return static_cast<int>(sets_.size()) - 1;
  }

  int parse_int(const std::string& token, int line, const char* what) const {
    int value = 0;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, value);
    if (token.empty() || ec != std::errc() || ptr != end) {
      fail(line, keyword_.name + ": '" + token + "' is not a valid " + what);
    }
    return value;
  }

  int parse_id(const std::string& token, int line, const char* what) const {
    const int id = parse_int(token, line, what);
    if (id <= 0) fail(line, keyword_.name + ": " + what + " " + token + " must be positive");
    return id;
  }

  double parse_double(const std::string& token, int line) const {
    std::string t = token;
    std::replace(t.begin(), t.end(), 'd', 'e');  // Fortran exponents 1.0D+03
    std::replace(t.begin(), t.end(), 'D', 'e');
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v)) {
      fail(line, keyword_.name + ": '" + token + "' is not a valid coordinate");
    }
    return v;
  }

  // Tokens of a data line; a trailing comma (continuation mark) is dropped, an empty field in the
  // middle is an error.
  std::vector<std::string> data_tokens(const std::string& t, int line) const {
    std::vector<std::string> tokens = split_commas(t);
    if (tokens.size() > 1 && tokens.back().empty()) tokens.pop_back();
    for (const auto& tok : tokens) {
      if (tok.empty()) fail(line, keyword_.name + ": empty field in data line");
    }
    return tokens;
  }

  void data_line(const std::string& t, int line) {
    switch (mode_) {
      case Mode::kNone:
        fail(line, "data line before any keyword");
      case Mode::kSkip:
        return;
      case Mode::kInstance:
        instance_position(data_tokens(t, line), line);
        return;
      case Mode::kNode: {
        const auto tokens = data_tokens(t, line);
        if (tokens.size() < 2 || tokens.size() > 4) {
          fail(line, "*NODE: expected 'id, x[, y[, z]]', got " + std::to_string(tokens.size()) +
                         " values");
        }
        RawNode node{parse_id(tokens[0], line, "node id"), Eigen::Vector3d::Zero(), line};
        for (size_t i = 1; i < tokens.size(); ++i) {
          node.x[static_cast<Eigen::Index>(i - 1)] = parse_double(tokens[i], line);
        }
        nodes_.push_back(node);
        if (current_set_ >= 0) {
          sets_[current_set_].items.push_back({SetItem::Kind::kId, node.id, 0, 1, "", line});
        }
        return;
      }
      case Mode::kElement: {
        const auto tokens = data_tokens(t, line);
        size_t i = 0;
        if (!pending_) {
          pending_ = RawElement{parse_id(tokens[0], line, "element id"), element_type_, {}, line};
          i = 1;
        }
        const size_t needed = static_cast<size_t>(nodes_per_element(element_type_));
        for (; i < tokens.size(); ++i) {
          if (pending_->node_ids.size() == needed) {
            fail(line, "element " + std::to_string(pending_->id) + " of type " +
                           element_type_name(element_type_) + " has more than " +
                           std::to_string(needed) + " nodes");
          }
          pending_->node_ids.push_back(parse_id(tokens[i], line, "node id"));
        }
        if (pending_->node_ids.size() == needed) {
          elements_.push_back(std::move(*pending_));
          if (current_set_ >= 0) {
            sets_[current_set_].items.push_back(
                {SetItem::Kind::kId, elements_.back().id, 0, 1, "", line});
          }
          pending_.reset();
        }
        return;
      }
      case Mode::kElastic:
      case Mode::kDensity: {
        const auto tokens = data_tokens(t, line);
        MeshMaterial& m = materials_.back();
        if (mode_ == Mode::kElastic && !m.problem.empty()) return;  // anisotropic: not read
        if (++property_lines_ > 1) {
          if (m.problem.empty()) {
            m.problem = keyword_.name + " with more than one line (temperature-dependent) on " +
                        line_text(line) + ": not supported";
          }
          return;
        }
        if (mode_ == Mode::kElastic) {
          if (tokens.size() < 2 || tokens.size() > 3) {
            fail(line, "*ELASTIC: expected 'E, nu[, temperature]'");
          }
          m.youngs_modulus = parse_double(tokens[0], line);
          m.poisson_ratio = parse_double(tokens[1], line);
        } else {
          if (tokens.empty() || tokens.size() > 2)
            fail(line, "*DENSITY: expected 'rho[, temperature]'");
          m.density = parse_double(tokens[0], line);
        }
        return;
      }
      case Mode::kDiscrete: {
        const auto tokens = data_tokens(t, line);
        const size_t needed =
            discrete_kind_ == DiscreteKind::kSpring1 || discrete_kind_ == DiscreteKind::kMass ? 2
                                                                                              : 3;
        if (tokens.size() != needed) {
          fail(line, "*ELEMENT, TYPE=" + std::string(discrete_name(discrete_kind_)) +
                         ": expected 'id, node" + (needed == 3 ? ", node'" : "'") + ", got " +
                         std::to_string(tokens.size()) + " values");
        }
        RawDiscrete d{parse_id(tokens[0], line, "element id") + assembly_element_offset(),
                      discrete_kind_,
                      {},
                      discrete_elset_,
                      line};
        for (size_t i = 1; i < tokens.size(); ++i) {
          d.node_ids.push_back(node_reference(tokens[i], line));
        }
        discretes_.push_back(std::move(d));
        return;
      }
      case Mode::kProperty: {
        const auto tokens = data_tokens(t, line);
        DiscreteProperty& p = properties_.back();
        const bool integers = std::all_of(tokens.begin(), tokens.end(), [](const std::string& s) {
          return s.find_first_of(".eEdD") == std::string::npos;
        });
        if (p.spring && integers && p.dof_a < 0 && !p.has_value) {
          // SPRING1 / SPRING2: the DOF line (integers; ccx tells it from the stiffness line so).
          if (tokens.size() > 2) fail(line, "*SPRING: expected 'first DOF[, second DOF]'");
          p.dof_a = parse_id(tokens[0], line, "degree of freedom");
          if (tokens.size() == 2) p.dof_b = parse_id(tokens[1], line, "degree of freedom");
          if (p.dof_a > 3 || p.dof_b > 3) {
            fail(line, "*SPRING: degree of freedom above 3 (solid nodes have translations only)");
          }
          return;
        }
        if (p.has_value) {
          fail(line, keyword_.name +
                         ": a second data line (temperature-dependent data) is not "
                         "supported");
        }
        if (tokens.size() != 1) {
          fail(line, keyword_.name + ": expected one value (" +
                         (p.spring ? "the spring constant, N/m" : "the mass, kg") + "), got " +
                         std::to_string(tokens.size()));
        }
        p.value = parse_double(tokens[0], line);
        p.has_value = true;
        return;
      }
      case Mode::kEquation: {
        const auto tokens = data_tokens(t, line);
        if (equation_terms_left_ == 0) {
          if (tokens.size() != 1) {
            fail(line, "*EQUATION: expected the number of terms alone on the line, got " +
                           std::to_string(tokens.size()) + " values");
          }
          equations_.push_back({parse_id(tokens[0], line, "number of terms"), {}, {}, {}, line});
          equation_terms_left_ = equations_.back().num_terms;
          return;
        }
        if (tokens.size() % 3 != 0) {
          fail(line, "*EQUATION: expected terms 'node, direction, coefficient', got " +
                         std::to_string(tokens.size()) + " values");
        }
        RawEquation& eq = equations_.back();
        for (size_t i = 0; i < tokens.size(); i += 3) {
          if (equation_terms_left_ == 0) {
            fail(line, "*EQUATION: more terms than the " + std::to_string(eq.num_terms) +
                           " announced on " + line_text(eq.line));
          }
          if (!std::isdigit(static_cast<unsigned char>(tokens[i][0])) &&
              !qualified_number(tokens[i])) {
            fail(line, "*EQUATION: node set " + tokens[i] +
                           " in an equation is not supported (write node numbers)");
          }
          eq.node_ids.push_back(node_reference(tokens[i], line));
          const int direction = parse_id(tokens[i + 1], line, "degree of freedom");
          if (direction > 3) {
            fail(line, "*EQUATION: degree of freedom " + tokens[i + 1] +
                           " is not supported (solid nodes have translations 1, 2, 3 only)");
          }
          eq.directions.push_back(direction - 1);
          eq.coefficients.push_back(parse_double(tokens[i + 2], line));
          if (eq.node_ids.size() == 1 && eq.coefficients[0] == 0.0) {
            fail(line, "*EQUATION: the coefficient of the first (dependent) term must not be 0");
          }
          --equation_terms_left_;
        }
        return;
      }
      case Mode::kBoundary: {
        // "node or set, first[, last[, value]]" or "node or set, ENCASTRE|PINNED|XSYMM|...".
        const auto tokens = data_tokens(t, line);
        RawBoundary b{tokens[0], 0, 2, boundary_type_, line};
        if (qualified_number(b.target)) b.target = std::to_string(node_reference(b.target, line));
        if (tokens.size() < 2 || tokens.size() > 4) {
          fail(line, "*BOUNDARY: expected 'node or set, first DOF[, last DOF[, value]]'");
        }
        const std::string what = upper(tokens[1]);
        if (what == "ENCASTRE" || what == "PINNED") {
          b.first = 0, b.last = 2;
        } else if (what == "XSYMM" || what == "YSYMM" || what == "ZSYMM") {
          b.first = b.last = what[0] - 'X';
        } else if (!std::isdigit(static_cast<unsigned char>(what[0]))) {
          b.first = 0, b.last = 2;
          if (b.unsupported.empty()) b.unsupported = "*BOUNDARY type " + what;
        } else {
          const int first = parse_id(tokens[1], line, "degree of freedom");
          const int last = tokens.size() >= 3 ? parse_id(tokens[2], line, "degree of freedom")
                                              : first;
          if (last < first) fail(line, "*BOUNDARY: last DOF " + tokens[2] + " < first " + tokens[1]);
          if (tokens.size() == 4 && parse_double(tokens[3], line) != 0.0 && b.unsupported.empty()) {
            b.unsupported = "a prescribed non-zero displacement " + tokens[3];
          }
          if (first > 3 && b.unsupported.empty()) {
            b.unsupported = "rotational DOFs (solid elements have none)";
          }
          b.first = std::min(first, 3) - 1;
          b.last = std::min(last, 3) - 1;
        }
        boundaries_.push_back(std::move(b));
        return;
      }
      case Mode::kSet: {
        const auto tokens = data_tokens(t, line);
        SetDefinition& set = sets_[current_set_];
        if (generate_) {
          if (tokens.size() < 2 || tokens.size() > 3) {
            fail(line, keyword_.name + ", GENERATE: expected 'first, last[, increment]'");
          }
          const char* what = set.is_node_set ? "node id" : "element id";
          const int offset = set_id_offset(set.is_node_set, line);
          SetItem item{SetItem::Kind::kRange,
                       parse_id(tokens[0], line, what) + offset,
                       parse_id(tokens[1], line, what) + offset,
                       1,
                       "",
                       line};
          if (tokens.size() == 3) item.step = parse_id(tokens[2], line, "increment");
          if (item.last < item.first) {
            fail(line, keyword_.name + ", GENERATE: last " + tokens[1] + " < first " + tokens[0]);
          }
          set.items.push_back(item);
        } else {
          for (const auto& tok : tokens) {
            const bool numeric =
                std::isdigit(static_cast<unsigned char>(tok[0])) || tok[0] == '-' || tok[0] == '+';
            if (numeric) {
              set.items.push_back({SetItem::Kind::kId,
                                   parse_id(tok, line, set.is_node_set ? "node id" : "element id") +
                                       set_id_offset(set.is_node_set, line),
                                   0, 1, "", line});
            } else if (qualified_number(tok)) {  // INSTANCE.id
              set.items.push_back({SetItem::Kind::kId,
                                   set.is_node_set ? node_reference(tok, line)
                                                   : element_reference(tok, line),
                                   0, 1, "", line});
            } else {
              // A set of the set's instance (INSTANCE=), of an instance (INSTANCE.SET), or of
              // the block the set is in.
              const bool dotted = tok.find('.') != std::string::npos;
              if (dotted && !instances_.empty()) instance_index(tok.substr(0, tok.find('.')), line);
              const std::string name =
                  set_instance_ >= 0 && !dotted ? instances_[set_instance_].name + "." + upper(tok)
                                                : upper(tok);
              set.items.push_back({SetItem::Kind::kName, 0, 0, 1, name, line});
            }
          }
        }
        return;
      }
    }
  }

  void finish_element_block() {
    if (equation_terms_left_ > 0) {
      const RawEquation& eq = equations_.back();
      fail(eq.line, "*EQUATION: " + std::to_string(eq.num_terms) + " terms announced, " +
                        std::to_string(eq.node_ids.size()) + " given");
    }
    if (pending_) {
      fail(pending_->line, "element " + std::to_string(pending_->id) + " of type " +
                               element_type_name(pending_->type) + " has " +
                               std::to_string(pending_->node_ids.size()) + " nodes, needs " +
                               std::to_string(nodes_per_element(pending_->type)));
    }
  }

  Mesh resolve() {
    Mesh mesh;
    std::unordered_map<int, int> node_index;
    std::unordered_map<int, int> node_line;
    mesh.coordinates.resize(3, static_cast<Eigen::Index>(nodes_.size()));
    for (const RawNode& n : nodes_) {
      const auto [it, inserted] = node_index.emplace(n.id, mesh.num_nodes());
      if (!inserted) {
        fail(n.line, "duplicate node id " + std::to_string(n.id) + " (first defined on " +
                         line_text(node_line[n.id]) + ")");
      }
      node_line[n.id] = n.line;
      mesh.coordinates.col(mesh.num_nodes()) = n.x;
      mesh.node_ids.push_back(n.id);
    }
    std::unordered_map<int, int> element_index;
    std::unordered_map<int, int> element_line;
    std::vector<int> local;
    for (const RawElement& e : elements_) {
      if (element_index.count(e.id)) {
        fail(e.line, "duplicate element id " + std::to_string(e.id) + " (first defined on " +
                         line_text(element_line[e.id]) + ")");
      }
      local.clear();
      for (int id : e.node_ids) {
        const auto it = node_index.find(id);
        if (it == node_index.end()) {
          fail(e.line,
               "element " + std::to_string(e.id) + " refers to unknown node " + std::to_string(id));
        }
        if (std::find(local.begin(), local.end(), it->second) != local.end()) {
          fail(e.line,
               "element " + std::to_string(e.id) + " uses node " + std::to_string(id) + " twice");
        }
        local.push_back(it->second);
      }
      element_line[e.id] = e.line;
      element_index[e.id] = mesh.add_element(e.id, e.type, local);
      check_shape(mesh, e);
    }
    for (const SetDefinition& def : sets_) {
      auto& sets = def.is_node_set ? mesh.node_sets : mesh.element_sets;
      const auto& index = def.is_node_set ? node_index : element_index;
      const char* kind = def.is_node_set ? "node" : "element";
      std::vector<int> members = sets[def.name];
      auto add_id = [&](int id, int line) {
        const auto it = index.find(id);
        if (it == index.end()) {
          fail(line, std::string(kind) + " set " + def.name + ": unknown " + kind + " " +
                         std::to_string(id));
        }
        members.push_back(it->second);
      };
      for (const SetItem& item : def.items) {
        switch (item.kind) {
          case SetItem::Kind::kId:
            add_id(item.first, item.line);
            break;
          case SetItem::Kind::kRange:
            for (long long id = item.first; id <= item.last; id += item.step) {
              add_id(static_cast<int>(id), item.line);
            }
            break;
          case SetItem::Kind::kName: {
            const auto it = sets.find(item.name);
            if (it == sets.end()) {
              fail(item.line, std::string(kind) + " set " + def.name + ": unknown " + kind +
                                  " set " + item.name + " (sets must be defined before use)");
            }
            members.insert(members.end(), it->second.begin(), it->second.end());
            break;
          }
        }
      }
      std::sort(members.begin(), members.end());
      members.erase(std::unique(members.begin(), members.end()), members.end());
      sets[def.name] = std::move(members);
    }
    for (const RawEquation& eq : equations_) {
      LinearConstraint c{{}, eq.coefficients, origin(eq.line)};
      for (size_t k = 0; k < eq.node_ids.size(); ++k) {
        const auto it = node_index.find(eq.node_ids[k]);
        if (it == node_index.end()) {
          fail(eq.line, "*EQUATION: unknown node " + std::to_string(eq.node_ids[k]));
        }
        const int dof = 3 * it->second + eq.directions[k];
        if (std::find(c.dofs.begin(), c.dofs.end(), dof) != c.dofs.end()) {
          fail(eq.line, "*EQUATION: node " + std::to_string(eq.node_ids[k]) + " direction " +
                            std::to_string(eq.directions[k] + 1) + " appears twice");
        }
        c.dofs.push_back(dof);
      }
      mesh.equations.push_back(std::move(c));
    }
    resolve_discretes(mesh, node_index, element_index);
    resolve_sections(mesh);
    for (const RawBoundary& b : boundaries_) {
      MeshBoundary out{{}, b.first, b.last, b.unsupported, origin(b.line)};
      const bool numeric = std::isdigit(static_cast<unsigned char>(b.target[0])) != 0;
      if (numeric) {
        const int id = parse_id(b.target, b.line, "node id");
        const auto it = node_index.find(id);
        if (it == node_index.end()) fail(b.line, "*BOUNDARY: unknown node " + b.target);
        out.nodes.push_back(it->second);
      } else {
        const auto it = mesh.node_sets.find(upper(b.target));
        if (it == mesh.node_sets.end()) fail(b.line, "*BOUNDARY: unknown node set " + b.target);
        out.nodes = it->second;
      }
      mesh.boundaries.push_back(std::move(out));
    }
    check_mesh(mesh);
    return mesh;
  }

  // *SOLID SECTION: each element of the set gets the material (Mesh::element_material).
  void resolve_sections(Mesh& mesh) const {
    mesh.materials = materials_;
    if (sections_.empty()) return;
    mesh.element_material.assign(static_cast<size_t>(mesh.num_elements()), -1);
    for (const Section& sec : sections_) {
      int index = -1;
      for (size_t m = 0; m < materials_.size(); ++m) {
        if (materials_[m].name == sec.material) index = static_cast<int>(m);
      }
      if (index < 0) fail(sec.line, "*SOLID SECTION: unknown material " + sec.material);
      const auto set = mesh.element_sets.find(sec.elset);
      if (set == mesh.element_sets.end())
        fail(sec.line, "*SOLID SECTION: unknown element set " + sec.elset);
      for (int e : set->second) {
        if (mesh.element_material[e] >= 0 && mesh.element_material[e] != index) {
          fail(sec.line, "*SOLID SECTION: element " + std::to_string(mesh.element_ids[e]) +
                             " is already in a section of material " +
                             materials_[mesh.element_material[e]].name);
        }
        mesh.element_material[e] = index;
      }
    }
  }

  static const char* discrete_name(DiscreteKind k) {
    switch (k) {
      case DiscreteKind::kSpring1:
        return "SPRING1";
      case DiscreteKind::kSpring2:
        return "SPRING2";
      case DiscreteKind::kSpringA:
        return "SPRINGA";
      case DiscreteKind::kMass:
        return "MASS";
    }
    return "?";
  }

  // Springs and masses into the mesh, each with the *SPRING / *MASS of its element set.
  void resolve_discretes(Mesh& mesh, const std::unordered_map<int, int>& node_index,
                         const std::unordered_map<int, int>& element_index) const {
    std::unordered_map<int, int> ids;  // discrete element id -> line
    std::vector<char> used(properties_.size(), 0);
    for (const RawDiscrete& d : discretes_) {
      const std::string what =
          std::string(discrete_name(d.kind)) + " element " + std::to_string(d.id);
      if (element_index.count(d.id) || !ids.emplace(d.id, d.line).second) {
        fail(d.line, "duplicate element id " + std::to_string(d.id));
      }
      const bool spring = d.kind != DiscreteKind::kMass;
      int found = -1;
      for (size_t p = 0; p < properties_.size(); ++p) {
        if (properties_[p].spring == spring && properties_[p].elset == d.elset) {
          if (found >= 0) {
            fail(properties_[p].line, (spring ? "*SPRING" : "*MASS") + std::string(", ELSET=") +
                                          d.elset + " given twice");
          }
          found = static_cast<int>(p);
        }
      }
      if (found < 0) {
        fail(d.line, what + " (ELSET " + d.elset + ") has no " + (spring ? "*SPRING" : "*MASS") +
                         ", ELSET=" + d.elset);
      }
      const DiscreteProperty& p = properties_[found];
      used[found] = 1;
      if (!p.has_value)
        fail(p.line, std::string(spring ? "*SPRING" : "*MASS") + " without a value");
      if (!(p.value >= 0.0)) fail(p.line, "a negative spring constant or mass is not supported");
      std::vector<int> nodes;
      for (int id : d.node_ids) {
        const auto it = node_index.find(id);
        if (it == node_index.end())
          fail(d.line, what + " refers to unknown node " + std::to_string(id));
        nodes.push_back(it->second);
      }
      if (d.kind == DiscreteKind::kMass) {
        mesh.point_masses.push_back({d.id, nodes[0], p.value, origin(d.line)});
        continue;
      }
      DiscreteSpring k;
      k.id = d.id;
      k.node_a = nodes[0];
      k.stiffness = p.value;
      k.origin = origin(d.line);
      if (d.kind == DiscreteKind::kSpringA) {
        if (p.dof_a >= 0) fail(p.line, "*SPRING for SPRINGA elements takes no degrees of freedom");
        if (nodes[0] == nodes[1])
          fail(d.line, what + " joins node " + std::to_string(d.node_ids[0]) + " to itself");
        const Eigen::Vector3d axis =
            mesh.coordinates.col(nodes[1]) - mesh.coordinates.col(nodes[0]);
        if (!(axis.norm() > 0.0)) {
          fail(d.line, what + ": its nodes coincide, so it has no axis");
        }
        k.node_b = nodes[1];
        k.direction_a = k.direction_b = axis.normalized();
      } else {
        const bool two = d.kind == DiscreteKind::kSpring2;
        if (p.dof_a < 0 || (two && p.dof_b < 0) || (!two && p.dof_b >= 0)) {
          fail(p.line, std::string("*SPRING for ") + discrete_name(d.kind) + " elements needs " +
                           (two ? "two degrees of freedom" : "one degree of freedom") +
                           " on its first data line");
        }
        k.direction_a = Eigen::Vector3d::Unit(p.dof_a - 1);
        if (two) {
          if (nodes[0] == nodes[1])
            fail(d.line, what + " joins node " + std::to_string(d.node_ids[0]) + " to itself");
          k.node_b = nodes[1];
          k.direction_b = Eigen::Vector3d::Unit(p.dof_b - 1);
        }
      }
      mesh.springs.push_back(std::move(k));
    }
    for (size_t p = 0; p < properties_.size(); ++p) {
      if (!used[p]) {
        fail(properties_[p].line, std::string(properties_[p].spring ? "*SPRING" : "*MASS") +
                                      ", ELSET=" + properties_[p].elset + ": no " +
                                      (properties_[p].spring ? "spring" : "MASS") +
                                      " element has that ELSET");
      }
    }
  }

  // An element whose geometry cannot be integrated (inverted, flat, distorted) stops at its line.
  void check_shape(const Mesh& mesh, const RawElement& e) const {
    const auto nodes = mesh.element_nodes(mesh.num_elements() - 1);
    Eigen::Matrix3Xd X(3, static_cast<Eigen::Index>(nodes.size()));
    for (size_t i = 0; i < nodes.size(); ++i) {
      X.col(static_cast<Eigen::Index>(i)) = mesh.coordinates.col(nodes[i]);
    }
    const std::string problem = element_shape_problem(e.type, X);
    if (!problem.empty()) {
      fail(e.line, "element " + std::to_string(e.id) + " (" + element_type_name(e.type) +
                       "): " + problem);
    }
  }

  enum class Mode {
    kNone,
    kSkip,
    kNode,
    kElement,
    kSet,
    kEquation,
    kDiscrete,
    kProperty,
    kElastic,
    kDensity,
    kBoundary,
    kInstance
  };
  enum class Block { kModel, kPart, kAssembly, kInstance };
  Block block_ = Block::kModel;
  std::string block_name_;  // of the open part or instance
  int block_line_ = 0;      // its keyword's line
  bool uses_parts_ = false;  // a *PART or *ASSEMBLY was read
  int assembly_line_ = 0;
  std::map<std::string, PartDefinition> parts_;
  std::vector<InstanceInfo> instances_;
  Items stash_;  // the model's items while a part or an instance is read
  int set_instance_ = -1;  // INSTANCE= of the set being read
  int assembly_element_offset_ = -1;
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d rotation_point_ = Eigen::Vector3d::Zero();
  int position_lines_ = 0;
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<MeshMaterial> materials_;
  std::vector<Section> sections_;
  int property_lines_ = 0;

  std::string file_;
  std::vector<std::string>* warnings_;
  // (file index, keyword name) -> its (global) lines, in order of first appearance
  std::vector<std::pair<std::pair<int, std::string>, std::vector<int>>> skipped_;
  std::vector<std::string> files_;                       // [0] = the top file, then includes
  std::vector<std::filesystem::path> include_stack_;     // files being read (cycle check)
  std::vector<int> loc_file_{0}, loc_line_{0};           // global line -> (file, line)
  Keyword keyword_;
  Mode mode_ = Mode::kNone;
  ElementType element_type_ = ElementType::kC3D8;
  DiscreteKind discrete_kind_ = DiscreteKind::kMass;
  std::string discrete_elset_;
  std::vector<RawDiscrete> discretes_;
  std::vector<DiscreteProperty> properties_;
  bool generate_ = false;
  int current_set_ = -1;
  std::optional<RawElement> pending_;
  std::vector<RawNode> nodes_;
  std::vector<RawElement> elements_;
  std::vector<SetDefinition> sets_;
  std::vector<RawEquation> equations_;
  int equation_terms_left_ = 0;
  std::vector<RawBoundary> boundaries_;
  std::string boundary_type_;  // why the current *BOUNDARY block cannot be applied (empty: it can)
};

}  // namespace

std::vector<std::string> inp_files(const std::string& path) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  std::vector<fs::path> seen;
  std::function<void(const fs::path&)> visit = [&](const fs::path& file) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(file, ec);
    if (std::find(seen.begin(), seen.end(), canonical) != seen.end()) return;
    seen.push_back(canonical);
    out.push_back(file.string());
    std::ifstream in(file, std::ios::binary);
    std::string line;
    while (std::getline(in, line)) {
      const std::string t = trim(line);
      if (t.empty() || t[0] != '*' || t.rfind("**", 0) == 0) continue;
      const std::vector<std::string> parts = split_commas(t);
      if (normalize_name(parts[0]) != "*INCLUDE") continue;
      for (size_t i = 1; i < parts.size(); ++i) {
        const size_t eq = parts[i].find('=');
        if (eq == std::string::npos || normalize_name(parts[i].substr(0, eq)) != "INPUT") continue;
        std::string value = trim(parts[i].substr(eq + 1));
        if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
          value = value.substr(1, value.size() - 2);
        }
        fs::path included(value);
        if (included.is_relative()) included = file.parent_path() / included;
        visit(included);
      }
    }
  };
  visit(path);
  return out;
}

Mesh read_inp(std::istream& in, const std::string& source_name,
              std::vector<std::string>* warnings) {
  return InpParser(source_name, warnings).parse(in);
}

Mesh read_inp(const std::string& path, std::vector<std::string>* warnings) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open the file for reading");
  return read_inp(in, path, warnings);
}

}  // namespace stickslip

#include "io/cdb_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

#include "core/errors.h"
#include "fe/element.h"
#include "io/text.h"

namespace stickslip {
namespace {

using text::trim;
using text::split_commas;
using text::upper;

// Why a command the reader does not use does not matter here (the warning's reason).
const char* ignore_reason(const std::string& key) {
  static const std::pair<const char*, const char*> kReasons[] = {
      {"F", "loads come from the case file"},
      {"SFE", "loads come from the case file"},
      {"SFEB", "loads come from the case file"},
      {"SF", "loads come from the case file"},
      {"BF", "loads come from the case file"},
      {"BFE", "loads come from the case file"},
      {"BFUN", "loads come from the case file"},
      {"ACEL", "loads come from the case file"},
      {"OMEG", "loads come from the case file"},
      {"DOME", "loads come from the case file"},
      {"CGLO", "loads come from the case file"},
      {"CGOM", "loads come from the case file"},
      {"DCGO", "loads come from the case file"},
      {"IRLF", "loads come from the case file"},
      {"ALPH", "damping comes from the case file"},
      {"BETA", "damping comes from the case file"},
      {"DMPR", "damping comes from the case file"},
      {"DMPS", "damping comes from the case file"},
      {"ANTY", "analyses come from the case file"},
      {"MODO", "analyses come from the case file"},
      {"MODC", "analyses come from the case file"},
      {"QRDO", "analyses come from the case file"},
      {"TIME", "analyses come from the case file"},
      {"KUSE", "analyses come from the case file"},
      {"CRPL", "analyses come from the case file"},
      {"NCNV", "analyses come from the case file"},
      {"NEQI", "analyses come from the case file"},
      {"ERES", "analyses come from the case file"},
      {"TREF", "no thermal analysis"},
      {"SECT", "sections are for shells, beams or layered solids (refused if an element is one)"},
      {"SECD", "sections are for shells, beams or layered solids (refused if an element is one)"},
      {"RLBL", "real constants: the solid elements read here have none"},
  };
  for (const auto& [k, why] : kReasons) {
    if (key == k) return why;
  }
  return "not used by stickslip";
}

// Commands that tie DOFs together or add stiffness or mass the reader does not build: refused.
const char* refusal(const std::string& key) {
  static const std::pair<const char*, const char*> kRefused[] = {
      {"CERI", "a rigid region ties DOFs to a master node"},
      {"RBE3", "a distributing constraint ties DOFs to a master node"},
      {"E", "elements given by E commands (write the model with CDWRITE: EBLOCK)"},
      {"EN", "elements given by EN commands (write the model with CDWRITE: EBLOCK)"},
      {"DA", "constraints on solid-model areas (write them as D on nodes)"},
      {"DL", "constraints on solid-model lines (write them as D on nodes)"},
      {"DK", "constraints on solid-model keypoints (write them as D on nodes)"},
      {"DSYM", "symmetry constraints (write them as D on nodes)"},
  };
  for (const auto& [k, why] : kRefused) {
    if (key == k) return why;
  }
  return nullptr;
}

// Commands that only structure the file or set things that cannot change K or M: no warning.
bool is_structure(const std::string& key) {
  static const char* kStructure[] = {"/COM", "/PRE", "/NOP", "/TIT", "/GO",  "FINI", "*IF",
                                     "*ELS", "*END", "NUMO", "DOF",  "*SET", "TYPE", "MAT",
                                     "REAL", "ESYS", "EXTO", "MPTE", "/GOP", "/NOL", "/UNI"};
  for (const char* k : kStructure) {
    if (key == k) return true;
  }
  return key.rfind("_CDRDOFF", 0) == 0;
}

// One field of a Fortran format: its width and whether it is an integer.
struct FortranField {
  int width;
  bool integer;
};

struct RawElement {
  int id, type, material;
  std::vector<int> nodes;  // ANSYS order, 0 = left out
  int line;
};

struct RawSet {
  bool node;
  std::string name;
  std::vector<std::pair<int, int>> ranges;  // [first, last]
  int line;
};

struct EType {
  int number = 0;  // 185, 186, 187, 200 or another ANSYS element number (0 = by name, unknown)
  std::string name;
  std::map<int, int> keyopts;
  int line = 0;
};

class CdbParser {
 public:
  CdbParser(std::string file, std::vector<std::string>* warnings,
            std::map<int, DeckMaterial>* materials)
      : file_(std::move(file)), warnings_(warnings), materials_(materials) {}

  Mesh parse(std::istream& in) {
    std::string text;
    while (std::getline(in, text)) {
      if (!text.empty() && text.back() == '\r') text.pop_back();
      lines_.push_back(text);
    }
    if (in.bad()) throw InvalidInput({file_, 0, ""}, "read error");
    for (line_ = 0; line_ < static_cast<int>(lines_.size()); ++line_) command(lines_[line_]);
    Mesh mesh = resolve();
    report_ignored();
    return mesh;
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const {
    throw InvalidInput({file_, line + 1, ""}, what);
  }
  std::string where(int line) const { return file_ + ":" + std::to_string(line + 1); }

  // --- numbers ---
  int parse_int(const std::string& token, int line, const std::string& what) const {
    const std::string t = trim(token);
    int value = 0;
    const char* end = t.data() + t.size();
    const char* begin = t.data() + (!t.empty() && t[0] == '+' ? 1 : 0);
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (t.empty() || ec != std::errc() || ptr != end) {
      fail(line, what + ": '" + t + "' is not an integer");
    }
    return value;
  }
  double parse_real(const std::string& token, int line, const std::string& what) const {
    std::string t = trim(token);
    std::replace(t.begin(), t.end(), 'd', 'e');
    std::replace(t.begin(), t.end(), 'D', 'e');
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v)) {
      fail(line, what + ": '" + t + "' is not a number");
    }
    return v;
  }

  // "(3i9,6e21.13e3)" -> 3 integer fields of 9 columns, 6 real fields of 21 columns.
  std::vector<FortranField> parse_format(int line) const {
    if (line >= static_cast<int>(lines_.size())) fail(line - 1, "the format line is missing");
    std::string f = upper(trim(lines_[line]));
    if (f.size() < 3 || f.front() != '(' || f.back() != ')') {
      fail(line, "expected a Fortran format line such as (3i9,6e21.13e3), got '" + f + "'");
    }
    std::vector<FortranField> out;
    for (const std::string& item : split_commas(f.substr(1, f.size() - 2))) {
      size_t i = 0;
      int repeat = 0;
      while (i < item.size() && std::isdigit(static_cast<unsigned char>(item[i]))) {
        repeat = 10 * repeat + (item[i++] - '0');
      }
      if (repeat == 0) repeat = 1;
      if (i >= item.size() || std::string("IEFGD").find(item[i]) == std::string::npos) {
        fail(line, "format item '" + item + "' is not understood (expected e.g. 3i9 or 6e21.13)");
      }
      const bool integer = item[i++] == 'I';
      int width = 0;
      while (i < item.size() && std::isdigit(static_cast<unsigned char>(item[i]))) {
        width = 10 * width + (item[i++] - '0');
      }
      if (width <= 0 || width > 64 || repeat > 1000) {
        fail(line, "format item '" + item + "' has no usable width");
      }
      for (int k = 0; k < repeat; ++k) out.push_back({width, integer});
    }
    return out;
  }

  // The fixed-width fields of a data line (only as many as the line holds).
  std::vector<std::string> fixed_fields(const std::string& text, int width, int max_fields) const {
    std::vector<std::string> out;
    const std::string t = text_rtrim(text);
    for (size_t start = 0; start < t.size() && static_cast<int>(out.size()) < max_fields;
         start += static_cast<size_t>(width)) {
      out.push_back(t.substr(start, static_cast<size_t>(width)));
    }
    return out;
  }
  static std::string text_rtrim(const std::string& s) { return text::rtrim(s); }

  // --- commands ---
  void command(const std::string& text) {
    const std::string t = trim(text);
    if (t.empty() || t[0] == '!') return;
    std::string body = t.substr(0, t.find('!'));  // trailing comment
    const std::vector<std::string> f = split_commas(body);
    const std::string name = upper(f[0]);
    const std::string key = name.substr(0, std::min<size_t>(4, name.size()));
    if (name.find('=') != std::string::npos) return;  // a parameter assignment (_CDRDOFF=)
    if (key == "NBLO") return nblock(f);
    if (key == "EBLO") return eblock(f);
    if (key == "CMBL") return cmblock(f);
    if (key == "ET") return et(f);
    if (key == "KEYO") return keyopt(f);
    if (key == "MPDA") return mpdata(f);
    if (key == "D") return d(f);
    if (name == "CE") return ce(f);
    if (name == "CP") return cp(f);
    if (name == "N" || key == "EN") {
      // "N,R5.3,LOC,-1" and "EN,R5.5,ATTR,-1" close blocks; a real N or EN command defines a node
      // or element outside the blocks.
      if (f.size() > 1 && !f[1].empty() && std::toupper(static_cast<unsigned char>(f[1][0])) == 'R')
        return;
      if (name == "N")
        fail(line_, "N command: nodes must be given in an NBLOCK (write with CDWRITE)");
    }
    if (const char* why = refusal(key)) {
      fail(line_, name + " is not supported: " + why +
                      "; it would change the stiffness or mass, "
                      "so the file is refused");
    }
    if (is_structure(key)) return;
    ignore(name, ignore_reason(key));
    if (name.size() > 5 && name.substr(name.size() - 5) == "BLOCK") {
      // Another block (SFEBLOCK, RLBLOCK, ...): its format and data lines are not commands.
      while (line_ + 1 < static_cast<int>(lines_.size())) {
        const std::string next = trim(lines_[line_ + 1]);
        const bool data = next.empty() || std::isdigit(static_cast<unsigned char>(next[0])) ||
                          next[0] == '-' || next[0] == '+' || next[0] == '.' || next[0] == '(';
        if (!data) break;
        ++line_;
      }
    }
  }

  void ignore(const std::string& name, const std::string& why) {
    for (auto& [w, list] : ignored_) {
      if (w == why) {
        for (auto& [n, l] : list) {
          if (n == name) return;  // listed once, with its first line
        }
        list.emplace_back(name, line_);
        return;
      }
    }
    ignored_.push_back({why, {{name, line_}}});
  }

  void report_ignored() const {
    if (warnings_ == nullptr) return;
    for (const auto& [why, list] : ignored_) {
      std::string what;
      for (const auto& [name, line] : list) {
        what += (what.empty() ? "" : ", ") + name + " (line " + std::to_string(line + 1) + ")";
      }
      warnings_->push_back(file_ + ": ignored (" + why + "): " + what);
    }
    for (const std::string& w : notes_) warnings_->push_back(w);
  }

  void nblock(const std::vector<std::string>& f) {
    const int header = line_;
    if (f.size() < 3 || upper(f[2]) != "SOLID") {
      fail(header, "NBLOCK: only the SOLID form ('NBLOCK,6,SOLID,...') is supported");
    }
    int announced = -1;
    if (f.size() > 4 && !f[4].empty()) announced = parse_int(f[4], header, "NBLOCK node count");
    const std::vector<FortranField> format = parse_format(++line_);
    int ints = 0;
    while (ints < static_cast<int>(format.size()) && format[ints].integer) ++ints;
    if (ints < 1 || static_cast<int>(format.size()) - ints < 3) {
      fail(line_, "NBLOCK format: expected integer fields then at least 3 real fields");
    }
    int count = 0;
    while (++line_ < static_cast<int>(lines_.size())) {
      const std::string& text = lines_[line_];
      const std::string t = upper(trim(text));
      if (t.rfind("N,", 0) == 0 || t == "-1" || t.rfind("-1", 0) == 0) break;
      if (t.empty()) continue;
      size_t pos = 0;
      std::vector<std::string> fields;
      for (const FortranField& ff : format) {
        if (pos >= text.size()) break;
        fields.push_back(text.substr(pos, static_cast<size_t>(ff.width)));
        pos += static_cast<size_t>(ff.width);
      }
      if (static_cast<int>(fields.size()) <= 0 || pos < text_rtrim(text).size()) {
        fail(line_, "NBLOCK: the line is longer than its format allows");
      }
      const int id = parse_int(fields[0], line_, "NBLOCK node id");
      if (id <= 0) fail(line_, "NBLOCK: node id " + std::to_string(id) + " must be positive");
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      bool rotated = false;
      for (int k = ints; k < static_cast<int>(fields.size()); ++k) {
        if (trim(fields[k]).empty()) continue;
        const double v = parse_real(fields[k], line_, "NBLOCK coordinate");
        if (k - ints < 3) {
          x[k - ints] = v;
        } else if (v != 0.0) {
          rotated = true;
        }
      }
      node_ids_.push_back(id);
      node_x_.push_back(x);
      node_lines_.push_back(line_);
      if (rotated) rotated_nodes_.insert(id);
      ++count;
    }
    if (announced >= 0 && count != announced) {
      fail(header, "NBLOCK announces " + std::to_string(announced) + " nodes, " +
                       std::to_string(count) + " follow");
    }
  }

  void eblock(const std::vector<std::string>& f) {
    const int header = line_;
    if (f.size() < 3 || upper(f[2]) != "SOLID") {
      fail(header,
           "EBLOCK: only the solid-element form ('EBLOCK,19,SOLID,...') is supported "
           "(shells, beams and contact elements are not)");
    }
    const std::vector<FortranField> format = parse_format(++line_);
    const int width = format[0].width;
    for (const FortranField& ff : format) {
      if (!ff.integer || ff.width != width) fail(line_, "EBLOCK format: expected e.g. (19i10)");
    }
    const int per_line = static_cast<int>(format.size());
    constexpr int kHeaderFields = 11;
    while (++line_ < static_cast<int>(lines_.size())) {
      const std::string t = trim(lines_[line_]);
      if (t == "-1") return;
      if (t.empty()) continue;
      const std::vector<std::string> h = fixed_fields(lines_[line_], width, per_line);
      if (static_cast<int>(h.size()) < kHeaderFields) {
        fail(line_, "EBLOCK: an element record needs 11 fields before its nodes, got " +
                        std::to_string(h.size()));
      }
      RawElement e;
      e.line = line_;
      e.material = parse_int(h[0], line_, "EBLOCK material number");
      e.type = parse_int(h[1], line_, "EBLOCK element type number");
      const int birth = parse_int(h[5], line_, "EBLOCK birth/death flag");
      const int n = parse_int(h[8], line_, "EBLOCK number of nodes");
      e.id = parse_int(h[10], line_, "EBLOCK element id");
      if (e.id <= 0)
        fail(line_, "EBLOCK: element id " + std::to_string(e.id) + " must be positive");
      if (n < 1 || n > 20)
        fail(line_, "EBLOCK: element " + std::to_string(e.id) + " has " + std::to_string(n) +
                        " nodes (1 to 20 expected)");
      if (birth != 0) {
        fail(line_, "EBLOCK: element " + std::to_string(e.id) +
                        " is killed (birth/death flag set): not supported");
      }
      for (size_t k = kHeaderFields; k < h.size() && static_cast<int>(e.nodes.size()) < n; ++k) {
        e.nodes.push_back(parse_int(h[k], line_, "EBLOCK node"));
      }
      while (static_cast<int>(e.nodes.size()) < n) {
        if (++line_ >= static_cast<int>(lines_.size()) || trim(lines_[line_]) == "-1") {
          fail(e.line, "EBLOCK: element " + std::to_string(e.id) + " announces " +
                           std::to_string(n) + " nodes, the block ends after " +
                           std::to_string(e.nodes.size()));
        }
        for (const std::string& field : fixed_fields(lines_[line_], width, per_line)) {
          if (static_cast<int>(e.nodes.size()) < n) {
            e.nodes.push_back(parse_int(field, line_, "EBLOCK node"));
          }
        }
      }
      elements_.push_back(std::move(e));
    }
    fail(header, "EBLOCK: the block does not end (no line -1)");
  }

  void cmblock(const std::vector<std::string>& f) {
    const int header = line_;
    if (f.size() < 4) fail(header, "CMBLOCK: expected 'CMBLOCK,name,NODE|ELEM,count'");
    RawSet set{true, upper(f[1]), {}, header};
    const std::string kind = upper(f[2]);
    if (set.name.empty()) fail(header, "CMBLOCK: empty component name");
    if (kind == "ELEM" || kind == "ELEMENT") {
      set.node = false;
    } else if (kind != "NODE") {
      fail(header, "CMBLOCK: component type '" + f[2] + "' (NODE or ELEM expected)");
    }
    std::string count_text = f[3];
    const int count = parse_int(count_text, header, "CMBLOCK count");
    const std::vector<FortranField> format = parse_format(++line_);
    const int width = format[0].width;
    const int per_line = static_cast<int>(format.size());
    std::vector<int> values;
    while (static_cast<int>(values.size()) < count) {
      if (++line_ >= static_cast<int>(lines_.size())) {
        fail(header, "CMBLOCK " + set.name + ": " + std::to_string(count) +
                         " numbers announced, the file ends after " +
                         std::to_string(values.size()));
      }
      for (const std::string& field : fixed_fields(lines_[line_], width, per_line)) {
        if (static_cast<int>(values.size()) < count) {
          values.push_back(parse_int(field, line_, "CMBLOCK " + set.name));
        }
      }
    }
    for (size_t i = 0; i < values.size(); ++i) {
      const int v = values[i];
      if (v > 0) {
        set.ranges.emplace_back(v, v);
      } else if (v < 0 && !set.ranges.empty() && -v >= set.ranges.back().second) {
        set.ranges.back().second = -v;
      } else {
        fail(header, "CMBLOCK " + set.name + ": value " + std::to_string(v) +
                         " is neither an id nor the end of a range after one");
      }
    }
    sets_.push_back(std::move(set));
  }

  EType& etype(int number, int line) {
    auto [it, inserted] = etypes_.try_emplace(number);
    if (inserted) it->second.line = line;
    return it->second;
  }

  void et(const std::vector<std::string>& f) {
    if (f.size() < 3) fail(line_, "ET: expected 'ET,itype,element'");
    const int itype = parse_int(f[1], line_, "ET type number");
    EType& t = etype(itype, line_);
    t.line = line_;
    std::string name = upper(f[2]);
    const size_t digits = name.find_first_of("0123456789");
    t.name = name;
    t.number = 0;
    if (digits != std::string::npos) {
      const std::string number = name.substr(digits);
      if (!number.empty() && std::all_of(number.begin(), number.end(), ::isdigit)) {
        t.number = parse_int(number, line_, "ET element number");
      }
    }
    if (digits == 0) t.name = "element " + name;
    for (size_t k = 3; k < f.size() && k < 9; ++k) {
      if (!f[k].empty()) t.keyopts[static_cast<int>(k) - 2] = parse_int(f[k], line_, "ET KEYOPT");
    }
  }

  void keyopt(const std::vector<std::string>& f) {
    if (f.size() < 4) fail(line_, "KEYOPT: expected 'KEYOPT,itype,k,value'");
    const int itype = parse_int(f[1], line_, "KEYOPT type number");
    const int k = parse_int(f[2], line_, "KEYOPT number");
    etype(itype, line_).keyopts[k] = parse_int(f[3], line_, "KEYOPT value");
  }

  void mpdata(const std::vector<std::string>& f) {
    // Blocked: MPDATA,R5.0|UNBL,length,LAB,mat,stloc,values...; plain: MPDATA,LAB,mat,stloc,...
    const bool blocked = f.size() > 1 && (upper(f[1]) == "UNBL" || upper(f[1]).rfind("R5", 0) == 0);
    const size_t lab_at = blocked ? 3 : 1;
    if (f.size() < lab_at + 4)
      fail(line_, "MPDATA: expected a label, a material, a location and a value");
    const std::string lab = upper(f[lab_at]);
    const int mat = parse_int(f[lab_at + 1], line_, "MPDATA material number");
    std::vector<double> values;
    for (size_t k = lab_at + 3; k < f.size(); ++k) {
      if (!f[k].empty()) values.push_back(parse_real(f[k], line_, "MPDATA " + lab));
    }
    const std::string stloc = f[lab_at + 2];
    if (values.size() != 1 || (!stloc.empty() && parse_int(stloc, line_, "MPDATA location") != 1)) {
      fail(line_, "MPDATA " + lab + " of material " + std::to_string(mat) +
                      ": temperature-dependent data (more than one value) is not supported");
    }
    const double v = values[0];
    double DeckMaterial::*field = nullptr;
    if (lab == "EX") field = &DeckMaterial::youngs_modulus;
    if (lab == "NUXY" || lab == "PRXY") field = &DeckMaterial::poisson_ratio;
    if (lab == "DENS") field = &DeckMaterial::density;
    static const char* kAnisotropic[] = {"EY",   "EZ",   "GXY",  "GYZ", "GXZ",
                                         "NUYZ", "NUXZ", "PRYZ", "PRXZ"};
    for (const char* a : kAnisotropic) {
      if (lab == a) {
        fail(line_, "MPDATA " + lab + " of material " + std::to_string(mat) +
                        ": anisotropic elasticity is not supported (isotropic EX, NUXY only)");
      }
    }
    if (field == nullptr) {
      ignore("MPDATA " + lab, std::string(lab == "ALPD" || lab == "BETD" || lab == "DMPR"
                                              ? "damping comes from the case file"
                                              : "material property not used by stickslip"));
      return;
    }
    DeckMaterial& m = deck_materials_[mat];
    if (m.origin.empty()) m.origin = where(line_);
    if (!std::isnan(m.*field) && m.*field != v) {
      fail(line_, "MPDATA " + lab + " of material " + std::to_string(mat) +
                      " given twice with different values");
    }
    m.*field = v;
  }

  void d(const std::vector<std::string>& f) {
    if (f.size() < 3) fail(line_, "D: expected 'D,node,label,value'");
    const std::string node = upper(f[1]);
    if (node.empty() || !std::isdigit(static_cast<unsigned char>(node[0]))) {
      fail(line_, "D on '" + f[1] + "': only node numbers are supported (not ALL or components)");
    }
    const int first = parse_int(f[1], line_, "D node");
    const std::string lab = upper(f[2]);
    for (size_t k = 3; k < 5 && k < f.size(); ++k) {
      if (!f[k].empty() && parse_real(f[k], line_, "D value") != 0.0) {
        fail(line_, "D " + lab + " on node " + f[1] +
                        ": a non-zero prescribed displacement is not supported");
      }
    }
    int last = first, step = 1;
    if (f.size() > 5 && !f[5].empty()) last = parse_int(f[5], line_, "D NEND");
    if (f.size() > 6 && !f[6].empty()) step = parse_int(f[6], line_, "D NINC");
    if (last < first || step <= 0) fail(line_, "D: bad node range " + f[1] + " to " + f[5]);
    if (f.size() > 7) {
      for (size_t k = 7; k < f.size(); ++k) {
        if (!f[k].empty()) fail(line_, "D: further labels (Lab2..Lab6) are not supported");
      }
    }
    int mask = 0;
    if (lab == "UX") mask = 1;
    if (lab == "UY") mask = 2;
    if (lab == "UZ") mask = 4;
    if (lab == "ALL" || lab == "UALL") mask = 7;
    if (mask == 0) {
      ignore("D " + lab, "solid elements have no such degree of freedom");
      return;
    }
    for (long long n = first; n <= last; n += step) {
      auto& [m, line] = held_[static_cast<int>(n)];
      if (m == 0) line = line_;
      m |= mask;
    }
    d_lines_.push_back({first, last, step, mask == 7 ? 0 : mask / 2, mask == 7 ? 2 : mask / 2,
                        line_});
  }

  // Constraint equations as CDWRITE writes them: "CE,R5.0,DEFI,nterms,neqn,constant", then
  // "CE,R5.0,NODE,node,lab,coef[,node,lab,coef]" lines; or one plain
  // "CE,NEQN,CONST,NODE1,Lab1,C1[,NODE2,Lab2,C2[,NODE3,Lab3,C3]]".
  void ce(const std::vector<std::string>& f) {
    const auto term = [&](size_t k) {
      const std::string lab = upper(trim(f[k + 1]));
      int direction = -1;
      if (lab == "UX") direction = 0;
      if (lab == "UY") direction = 1;
      if (lab == "UZ") direction = 2;
      if (direction < 0) {
        fail(line_, "CE: degree of freedom '" + trim(f[k + 1]) +
                        "' is not a translation UX, UY, UZ of a solid element");
      }
      RawEquationTerm t{parse_int(f[k], line_, "CE node"), direction,
                        parse_real(f[k + 2], line_, "CE coefficient")};
      if (t.coefficient == 0.0) fail(line_, "CE: a coefficient is 0");
      return t;
    };
    const auto constant = [&](const std::string& c) {
      if (!trim(c).empty() && parse_real(c, line_, "CE constant") != 0.0) {
        fail(line_, "CE: a non-zero constant (prescribed relative displacement) is not supported");
      }
    };
    const std::string second = f.size() > 1 ? upper(trim(f[1])) : "";
    if (!second.empty() && second[0] == 'R') {  // blocked form
      const std::string what = f.size() > 2 ? upper(trim(f[2])) : "";
      if (what == "DEFI") {
        if (f.size() < 5) fail(line_, "CE,R5.0,DEFI: expected 'CE,R5.0,DEFI,nterms,neqn,const'");
        if (ce_terms_left_ > 0) fail(line_, "CE: the previous equation has terms missing");
        const int n = parse_int(f[3], line_, "CE number of terms");
        if (n < 1) fail(line_, "CE: an equation needs at least one term");
        if (f.size() > 5) constant(f[5]);
        ce_.push_back({{}, line_});
        ce_terms_left_ = n;
        return;
      }
      if (what == "NODE") {
        if (ce_terms_left_ <= 0) fail(line_, "CE,R5.0,NODE without a CE,R5.0,DEFI before it");
        for (size_t k = 3; k + 2 < f.size() && ce_terms_left_ > 0; k += 3) {
          if (trim(f[k]).empty()) break;
          ce_.back().terms.push_back(term(k));
          --ce_terms_left_;
        }
        return;
      }
      fail(line_, "CE,R5.0," + what + ": unknown form (DEFI and NODE are read)");
    }
    if (f.size() < 6) fail(line_, "CE: expected 'CE,NEQN,CONST,NODE1,Lab1,C1,...'");
    constant(f[2]);
    ce_.push_back({{}, line_});
    for (size_t k = 3; k + 2 < f.size(); k += 3) {
      if (trim(f[k]).empty()) continue;
      ce_.back().terms.push_back(term(k));
    }
  }

  // Coupled DOF sets: "CP,NSET,Lab,NODE1,...,NODE17" (ANSYS's CP command). NSET a number, HIGH
  // (the default: the highest set defined) or NEXT (one above it); Lab UX, UY or UZ (ALL: one set
  // per direction, numbered from NSET; blank: the set's own label). A CP on an existing set adds
  // its nodes; a negative node number takes the node out; duplicates are ignored. The set's first
  // node is its primary (retained) node.
  void cp(const std::vector<std::string>& f) {
    if (f.size() > 1 && !trim(f[1]).empty() && upper(trim(f[1]))[0] == 'R') {
      fail(line_, "CP: the blocked form (CP," + trim(f[1]) +
                      ",...) is not read; write coupled sets as CP,NSET,Lab,NODE1,NODE2,...");
    }
    const std::string nset = f.size() > 1 ? upper(trim(f[1])) : "";
    const std::string lab = f.size() > 2 ? upper(trim(f[2])) : "";
    const int highest = cp_sets_.empty() ? 0 : cp_sets_.rbegin()->first;
    int number = 0;
    if (nset.empty() || nset == "HIGH") {
      number = lab == "ALL" ? highest + 1 : std::max(highest, 1);
    } else if (nset == "NEXT") {
      number = highest + 1;
    } else if (nset == "LOW") {
      number = cp_sets_.empty() ? 1 : cp_sets_.begin()->first;
    } else {
      number = parse_int(f[1], line_, "CP set number");
      if (number < 1) fail(line_, "CP: set number " + std::to_string(number) + " (needs >= 1)");
    }
    if (f.size() > 3 && (upper(trim(f[3])) == "ALL" || upper(trim(f[3])) == "P")) {
      fail(line_, "CP: NODE1 = " + upper(trim(f[3])) +
                      " takes the nodes selected in ANSYS, which the file does not record; list "
                      "the nodes");
    }
    std::vector<int> directions;
    if (lab == "ALL") {
      directions = {0, 1, 2};
    } else if (lab == "UX" || lab == "UY" || lab == "UZ") {
      directions = {lab[1] - 'X'};
    } else if (!lab.empty()) {
      fail(line_, "CP: degree of freedom '" + trim(f[2]) +
                      "' is not a translation UX, UY, UZ of a solid element");
    }
    if (lab == "ALL") {
      for (int d = 0; d < 3; ++d) {
        if (cp_sets_.count(number + d)) {
          fail(line_, "CP: Lab = ALL needs new set numbers; set " + std::to_string(number + d) +
                          " exists");
        }
      }
    }
    for (size_t s = 0; s < std::max<size_t>(directions.size(), 1); ++s) {
      const int set_number = number + static_cast<int>(s);
      auto [it, inserted] = cp_sets_.try_emplace(set_number, RawCp{-1, {}, line_});
      RawCp& set = it->second;
      if (!directions.empty()) {
        if (!inserted && set.direction >= 0 && set.direction != directions[s]) {
          fail(line_, "CP: set " + std::to_string(set_number) + " couples " +
                          "XYZ"[set.direction] + " (line " + std::to_string(set.line + 1) +
                          "); a different label for it is not supported");
        }
        set.direction = directions[s];
      } else if (set.direction < 0) {
        fail(line_, "CP: set " + std::to_string(set_number) +
                        " is new and the command gives no label (UX, UY or UZ)");
      }
      for (size_t k = 3; k < f.size(); ++k) {
        if (trim(f[k]).empty()) continue;
        const int node = parse_int(f[k], line_, "CP node");
        if (node == 0) continue;
        const auto at = std::find_if(set.nodes.begin(), set.nodes.end(),
                                     [&](const auto& n) { return n.first == std::abs(node); });
        if (node < 0) {
          if (at != set.nodes.end()) set.nodes.erase(at);
        } else if (at == set.nodes.end()) {
          set.nodes.emplace_back(node, line_);
        }
      }
    }
  }

  // --- building the mesh ---
  Mesh resolve() {
    if (ce_terms_left_ > 0) {
      fail(ce_.back().line, "CE: the equation defined here has " + std::to_string(ce_terms_left_) +
                                " term(s) missing at the end of the file");
    }
    Mesh mesh;
    std::unordered_map<int, int> node_index;
    mesh.coordinates.resize(3, static_cast<Eigen::Index>(node_ids_.size()));
    for (size_t i = 0; i < node_ids_.size(); ++i) {
      const auto [it, inserted] = node_index.emplace(node_ids_[i], static_cast<int>(i));
      if (!inserted) {
        fail(node_lines_[i], "duplicate node id " + std::to_string(node_ids_[i]) +
                                 " (first on line " + std::to_string(node_lines_[it->second] + 1) +
                                 ")");
      }
      mesh.coordinates.col(static_cast<Eigen::Index>(i)) = node_x_[i];
      mesh.node_ids.push_back(node_ids_[i]);
    }
    std::unordered_map<int, int> element_index;
    std::set<int> skipped_elements;
    std::vector<int> element_numbers;  // material number of each element kept
    int mesh200 = 0, mesh200_line = -1, wedges = 0, wedge_line = -1;
    int pyramids = 0, pyramid_line = -1, pyramids13 = 0, pyramid13_line = -1;
    for (const RawElement& e : elements_) {
      std::vector<int> nodes;
      const std::optional<ElementType> type = map_element(e, &nodes);
      if (!type) {
        skipped_elements.insert(e.id);
        if (mesh200++ == 0) mesh200_line = e.line;
        continue;
      }
      if (element_index.count(e.id) || skipped_elements.count(e.id)) {
        fail(e.line, "duplicate element id " + std::to_string(e.id));
      }
      std::vector<int> local;
      for (int id : nodes) {
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
      if (*type == ElementType::kC3D6 || *type == ElementType::kC3D15) {
        if (wedges++ == 0) wedge_line = e.line;
      }
      if (*type == ElementType::kC3D5 && pyramids++ == 0) pyramid_line = e.line;
      if (*type == ElementType::kC3D13 && pyramids13++ == 0) pyramid13_line = e.line;
      element_index[e.id] = mesh.add_element(e.id, *type, local);
      Eigen::Matrix3Xd X(3, static_cast<Eigen::Index>(local.size()));
      for (size_t a = 0; a < local.size(); ++a) {
        X.col(static_cast<Eigen::Index>(a)) = mesh.coordinates.col(local[a]);
      }
      const std::string problem = element_shape_problem(*type, X);
      if (!problem.empty()) {
        fail(e.line,
             "element " + std::to_string(e.id) + " (" + element_type_name(*type) + "): " + problem);
      }
      element_numbers.push_back(e.material);
    }
    // Materials by number: MAT<n>; each element's from its material field.
    std::map<int, int> material_index;
    for (const auto& [number, dm] : deck_materials_) {
      material_index[number] = static_cast<int>(mesh.materials.size());
      mesh.materials.push_back({"MAT" + std::to_string(number), dm.youngs_modulus, dm.poisson_ratio,
                                dm.density, dm.origin, ""});
    }
    if (!mesh.materials.empty()) {
      for (int number : element_numbers) {
        const auto it = material_index.find(number);
        mesh.element_material.push_back(it == material_index.end() ? -1 : it->second);
      }
    }
    if (mesh200 > 0) {
      notes_.push_back(file_ + ": " + std::to_string(mesh200) +
                       " MESH200 element(s) skipped (mesh-only, no stiffness or mass), first on "
                       "line " +
                       std::to_string(mesh200_line + 1));
    }
    if (wedges > 0) {
      notes_.push_back(file_ + ": " + std::to_string(wedges) +
                       " degenerate SOLID185/186 element(s) of wedge shape (first on line " +
                       std::to_string(wedge_line + 1) +
                       ") read as CalculiX wedges C3D6/C3D15: the same shape functions as "
                       "ANSYS's collapsed hexahedra, CalculiX's integration rules (ANSYS's may "
                       "differ; no B-bar on SOLID185 wedges)");
    }
    if (pyramids > 0) {
      notes_.push_back(file_ + ": " + std::to_string(pyramids) +
                       " degenerate SOLID185 element(s) of pyramid shape (first on line " +
                       std::to_string(pyramid_line + 1) +
                       ") read as C3D5, ANSYS's collapsed hexahedron with 2x2x2 Gauss points, "
                       "without B-bar");
    }
    if (pyramids13 > 0) {
      notes_.push_back(file_ + ": " + std::to_string(pyramids13) +
                       " degenerate SOLID186 element(s) of pyramid shape (first on line " +
                       std::to_string(pyramid13_line + 1) +
                       ") read as C3D13, the collapsed 20-node hexahedron with 3x3x3 Gauss points "
                       "(CalculiX's C3D20 with a collapsed face); ANSYS integrates its pyramid "
                       "with 2x2x2 points and its own 13-node pyramid functions, so ANSYS's "
                       "results may differ");
    }
    for (const RawSet& s : sets_) {
      auto& target = s.node ? mesh.node_sets : mesh.element_sets;
      const auto& index = s.node ? node_index : element_index;
      std::vector<int> members = target[s.name];
      for (const auto& [a, b] : s.ranges) {
        for (long long id = a; id <= b; ++id) {
          const auto it = index.find(static_cast<int>(id));
          if (it != index.end()) {
            members.push_back(it->second);
          } else if (s.node || !skipped_elements.count(static_cast<int>(id))) {
            fail(s.line, std::string("CMBLOCK ") + s.name + ": unknown " +
                             (s.node ? "node " : "element ") + std::to_string(id));
          }
        }
      }
      std::sort(members.begin(), members.end());
      members.erase(std::unique(members.begin(), members.end()), members.end());
      target[s.name] = std::move(members);
    }
    if (!held_.empty()) {
      if (mesh.node_sets.count("D_ALL")) {
        fail(held_.begin()->second.second,
             "D: the file already has a component D_ALL, the name given to the nodes held by D");
      }
      std::vector<int> all;
      for (const auto& [id, held] : held_) {
        const auto& [mask, line] = held;
        const auto it = node_index.find(id);
        if (it == node_index.end()) fail(line, "D on unknown node " + std::to_string(id));
        if (rotated_nodes_.count(id)) {
          fail(line, "D on node " + std::to_string(id) +
                         ", whose nodal coordinate system is rotated: not supported");
        }
        if (mask == 7) all.push_back(it->second);
      }
      std::sort(all.begin(), all.end());
      const size_t num_all = all.size();
      if (!all.empty()) mesh.node_sets["D_ALL"] = std::move(all);
      // Every D line, as the DOF-level supports of a deck (Mesh::boundaries, like *BOUNDARY).
      for (const DLine& d : d_lines_) {
        MeshBoundary b{{}, d.dof_first, d.dof_last, "", where(d.line)};
        for (long long n = d.first; n <= d.last; n += d.step) {
          b.nodes.push_back(node_index.at(static_cast<int>(n)));
        }
        mesh.boundaries.push_back(std::move(b));
      }
      notes_.push_back(file_ + ": D holds " + std::to_string(held_.size()) + " node(s), " +
                       std::to_string(num_all) + " of them in UX, UY, UZ (first D on line " +
                       std::to_string(held_.begin()->second.second + 1) +
                       "): applied only if the case file says so (supports: [{from_mesh: "
                       "true}], per direction; or the node set D_ALL as a clamp)");
    }
    for (const RawCe& c : ce_) {
      LinearConstraint lc;
      lc.origin = where(c.line);
      for (const RawEquationTerm& t : c.terms) {
        const auto it = node_index.find(t.node);
        if (it == node_index.end()) fail(c.line, "CE on unknown node " + std::to_string(t.node));
        if (rotated_nodes_.count(t.node)) {
          fail(c.line, "CE on node " + std::to_string(t.node) +
                           ", whose nodal coordinate system is rotated: not supported");
        }
        const int dof = 3 * it->second + t.direction;
        if (std::find(lc.dofs.begin(), lc.dofs.end(), dof) != lc.dofs.end()) {
          fail(c.line, "CE: node " + std::to_string(t.node) + " " + "XYZ"[t.direction] +
                           " appears twice in one equation");
        }
        lc.dofs.push_back(dof);
        lc.coefficients.push_back(t.coefficient);
      }
      mesh.equations.push_back(std::move(lc));
    }
    // Coupled sets: u(node) - u(primary) = 0 for every other node, the node's DOF dependent.
    for (const auto& [number, set] : cp_sets_) {
      std::vector<int> dofs;
      for (const auto& [node, line] : set.nodes) {
        const auto it = node_index.find(node);
        if (it == node_index.end()) fail(line, "CP on unknown node " + std::to_string(node));
        if (rotated_nodes_.count(node)) {
          fail(line, "CP on node " + std::to_string(node) +
                         ", whose nodal coordinate system is rotated: not supported");
        }
        dofs.push_back(3 * it->second + set.direction);
      }
      for (size_t k = 1; k < dofs.size(); ++k) {
        mesh.equations.push_back(
            {{dofs[k], dofs[0]}, {1.0, -1.0}, where(set.nodes[k].second)});
      }
    }
    if (materials_ != nullptr) {
      materials_->clear();
      for (const auto& [number, m] : deck_materials_) (*materials_)[number] = m;
    }
    check_mesh(mesh);
    return mesh;
  }

  // The stickslip element of a CDB element and its nodes in CalculiX order; nullopt for an
  // element that is skipped (MESH200). Refuses what it cannot map.
  std::optional<ElementType> map_element(const RawElement& e, std::vector<int>* nodes) const {
    const auto it = etypes_.find(e.type);
    const std::string id = "element " + std::to_string(e.id);
    if (it == etypes_.end()) {
      fail(e.line, id + ": element type " + std::to_string(e.type) + " has no ET command");
    }
    const EType& t = it->second;
    auto keyopt = [&](int k) {
      const auto kt = t.keyopts.find(k);
      return kt == t.keyopts.end() ? 0 : kt->second;
    };
    const std::string what =
        id + " (SOLID" + std::to_string(t.number) + ", type " + std::to_string(e.type) + ")";
    auto refuse = [&](const std::string& why) -> std::optional<ElementType> {
      fail(e.line, what + ": " + why);
    };
    if (t.number == 200) return std::nullopt;
    if (t.number != 185 && t.number != 186 && t.number != 187) {
      fail(e.line, id + ": element type " + std::to_string(e.type) + " is " + t.name +
                       " (ET on line " + std::to_string(t.line + 1) +
                       "), not supported (SOLID185, SOLID186, SOLID187, MESH200 are)");
    }
    for (const auto& [k, v] : t.keyopts) {
      if (v == 0 || k == 2) continue;
      if (k == 3)
        return refuse("KEYOPT(3) = " + std::to_string(v) + ": layered solids are not supported");
      if (k == 6)
        return refuse("KEYOPT(6) = " + std::to_string(v) +
                      ": the mixed u-P formulation is not supported");
      return refuse("KEYOPT(" + std::to_string(k) + ") = " + std::to_string(v) +
                    " is not supported");
    }
    const std::vector<int>& n = e.nodes;
    if (std::find(n.begin(), n.end(), 0) != n.end()) {
      return refuse("has nodes left out (0): mid-side nodes must all be given");
    }
    if (t.number == 187) {
      if (n.size() != 10) {
        return refuse("has " + std::to_string(n.size()) +
                      " nodes; a SOLID187 needs its 4 corners and 6 mid-side nodes");
      }
      *nodes = n;  // I J K L M N O P Q R: CalculiX C3D10's order
      return ElementType::kC3D10;
    }
    const size_t full = t.number == 185 ? 8 : 20;
    if (n.size() != full) {
      return refuse("has " + std::to_string(n.size()) + " nodes, needs " + std::to_string(full) +
                    (t.number == 186 ? " (mid-side nodes left out are not supported)" : ""));
    }
    // Corners I J K L M N O P; degenerate shapes repeat some of them.
    const bool kl = n[2] == n[3], op = n[6] == n[7];
    const bool mnop = n[4] == n[5] && n[5] == n[6] && n[6] == n[7];
    const std::set<int> corners(n.begin(), n.begin() + 8);
    std::string shape;
    if (corners.size() == 8) {
      shape = "hexahedron";
    } else if (kl && mnop && corners.size() == 4) {
      shape = "tetrahedron";
    } else if (kl && op && corners.size() == 6) {
      shape = "wedge";
    } else if (mnop && corners.size() == 5) {
      shape = "pyramid";
    } else {
      return refuse("its corner nodes repeat in a way that is no ANSYS shape");
    }
    const int k2 = keyopt(2);
    if (t.number == 185) {
      if (shape == "tetrahedron") {
        return refuse("the tetrahedral shape of SOLID185 is not supported (mesh with SOLID187)");
      }
      if (k2 == 1) {
        return refuse(
            "KEYOPT(2) = 1, uniform reduced integration with hourglass control: ANSYS's "
            "hourglass stiffness is not published, and stickslip's C3D8R (CalculiX's) is a "
            "different one");
      }
      if (k2 == 2) {
        return refuse(
            "KEYOPT(2) = 2, enhanced strain with 13 internal DOFs (9 against shear locking, 4 "
            "against volumetric locking): ANSYS does not publish the 4 volumetric modes, so "
            "stickslip cannot reproduce them (KEYOPT(2) = 3, the 9 bending modes alone, is read "
            "as C3D8I; KEYOPT(2) = 0 as B-bar)");
      }
      if (k2 == 3 && shape != "hexahedron") {
        return refuse("KEYOPT(2) = 3 (simplified enhanced strain) on the " + shape +
                      " shape is not supported (only its hexahedron is: C3D8I)");
      }
      if (k2 == 3) {
        // Simplified enhanced strain: 9 enhanced strain modes against shear locking (Simo and
        // Rifai's method), for a linear elastic hexahedron the incompatible modes of Wilson and
        // Taylor with Taylor's modification: C3D8I.
        *nodes = n;
        return ElementType::kC3D8I;
      }
      if (k2 != 0) return refuse("KEYOPT(2) = " + std::to_string(k2) + " is not supported");
      if (shape == "pyramid") {
        // Pyramid I J K L M M M M: C3D5 is this collapsed hexahedron (same shape functions and
        // 2x2x2 rule), without B-bar.
        *nodes = {n[0], n[1], n[2], n[3], n[4]};
        return ElementType::kC3D5;
      }
      if (shape == "wedge") {
        // Prism I J K K M N O O: the collapsed hexahedron interpolates exactly as the 6-node
        // wedge (its shape functions are the wedge's), integrated here with CalculiX's C3D6 rule.
        *nodes = {n[0], n[1], n[2], n[4], n[5], n[6]};
        return ElementType::kC3D6;
      }
      *nodes = n;
      return ElementType::kC3D8B;
    }
    if (k2 != 0 && k2 != 1)
      return refuse("KEYOPT(2) = " + std::to_string(k2) + " is not supported");
    if (shape == "tetrahedron") {
      // Corners I J K M; mid-side Q (IJ), R (JK), T (LI = KI), Y (IM), Z (JM), A (KM).
      *nodes = {n[0], n[1], n[2], n[4], n[8], n[9], n[11], n[16], n[17], n[18]};
      return ElementType::kC3D10;
    }
    if (shape == "pyramid") {
      // Pyramid I J K L M M M M Q R S T M M M M Y Z A B: corners I J K L M; mid-side Q R S T
      // (base), Y Z A B (lateral edges IM, JM, KM, LM): C3D13's order, the collapsed C3D20.
      for (int a = 12; a < 16; ++a) {
        if (n[static_cast<size_t>(a)] != n[4]) {
          return refuse(
              "a pyramid shape (M = N = O = P) whose top mid-side nodes U V W X are not "
              "all its apex M");
        }
      }
      *nodes = {n[0], n[1], n[2], n[3], n[4], n[8], n[9], n[10], n[11], n[16], n[17], n[18], n[19]};
      return ElementType::kC3D13;
    }
    if (shape == "wedge") {
      // Prism: K = L, O = P (and S = K, W = O, A = B). Corners I J K M N O; mid-side Q (IJ),
      // R (JK), T (LI = KI), U (MN), V (NO), X (PM = OM), Y (IM), Z (JN), A (KO): C3D15's order.
      *nodes = {n[0], n[1], n[2], n[4],  n[5],  n[6],  n[8], n[9],
                n[11], n[12], n[13], n[15], n[16], n[17], n[18]};
      return ElementType::kC3D15;
    }
    *nodes = n;  // I..P, Q R S T (bottom edges), U V W X (top), Y Z A B (vertical): C3D20's order
    return k2 == 1 ? ElementType::kC3D20 : ElementType::kC3D20R;
  }

  std::string file_;
  std::vector<std::string>* warnings_;
  std::map<int, DeckMaterial>* materials_;
  std::vector<std::string> lines_;
  int line_ = 0;
  std::vector<int> node_ids_, node_lines_;
  std::vector<Eigen::Vector3d> node_x_;
  std::set<int> rotated_nodes_;
  std::vector<RawElement> elements_;
  std::vector<RawSet> sets_;
  std::map<int, EType> etypes_;
  std::map<int, DeckMaterial> deck_materials_;
  std::map<int, std::pair<int, int>> held_;  // node id -> (direction mask, first D line)
  struct DLine {
    int first, last, step;  // node ids
    int dof_first, dof_last;
    int line;
  };
  std::vector<DLine> d_lines_;
  struct RawEquationTerm {
    int node;
    int direction;
    double coefficient;
  };
  struct RawCe {
    std::vector<RawEquationTerm> terms;
    int line;
  };
  std::vector<RawCe> ce_;
  int ce_terms_left_ = 0;
  struct RawCp {
    int direction;                             // 0-2, -1 before a label is given
    std::vector<std::pair<int, int>> nodes;    // (node id, line), the first the primary
    int line;                                  // where the set is first defined
  };
  std::map<int, RawCp> cp_sets_;
  // reason -> (command, first line), in order of first appearance
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, int>>>> ignored_;
  std::vector<std::string> notes_;
};

}  // namespace

Mesh read_cdb(std::istream& in, const std::string& source_name, std::vector<std::string>* warnings,
              std::map<int, DeckMaterial>* materials) {
  return CdbParser(source_name, warnings, materials).parse(in);
}

Mesh read_cdb(const std::string& path, std::vector<std::string>* warnings,
              std::map<int, DeckMaterial>* materials) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path, 0, ""}, "cannot open the file for reading");
  return read_cdb(in, path, warnings, materials);
}

}  // namespace stickslip

#include "io/case_file.h"
#include "io/case_keys.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "contact/contact_law.h"
#include "core/printable.h"
#include "io/ansys_mapping.h"

namespace stickslip {

double* ContactParametersDefinition::field(const std::string& key) {
  if (key == "kt") return &kt;
  if (key == "kn") return &kn;
  if (key == "mu") return &mu;
  if (key == "preload") return &preload;
  if (key == "k") return &k;
  if (key == "k1") return &k1;
  if (key == "k3") return &k3;
  return &other[key];  // a key of a law registered by the program
}

double ContactParametersDefinition::value(const std::string& key) const {
  if (key == "kt") return kt;
  if (key == "kn") return kn;
  if (key == "mu") return mu;
  if (key == "preload") return preload;
  if (key == "k") return k;
  if (key == "k1") return k1;
  if (key == "k3") return k3;
  const auto it = other.find(key);
  return it == other.end() ? 0.0 : it->second;
}

SourceLocation CaseDefinition::where(const std::string& path) const {
  std::string p = path;
  while (!p.empty()) {
    const auto it = locations.find(p);
    if (it != locations.end()) return {it->second.file, it->second.line, path};
    const size_t cut = p.find_last_of(".[");
    if (cut == std::string::npos) break;
    p.resize(cut);
  }
  return {file, 0, path};
}

namespace {

// The names of the case file's choices (case_file.h), in the order the messages list them.
template <class E>
using Choices = std::vector<std::pair<const char*, E>>;
const Choices<MeshFileFormat>& choices_of(MeshFileFormat) {
  static const Choices<MeshFileFormat> c{
      {"inp", MeshFileFormat::kInp}, {"msh", MeshFileFormat::kMsh}, {"cdb", MeshFileFormat::kCdb}};
  return c;
}
const Choices<ReducedFileFormat>& choices_of(ReducedFileFormat) {
  static const Choices<ReducedFileFormat> c{{"harwell_boeing", ReducedFileFormat::kHarwellBoeing},
                                            {"matrix_market", ReducedFileFormat::kMatrixMarket},
                                            {"abaqus_matrix", ReducedFileFormat::kAbaqusMatrix}};
  return c;
}
const Choices<PreloadSplit>& choices_of(PreloadSplit) {
  static const Choices<PreloadSplit> c{{"equal", PreloadSplit::kEqual},
                                       {"area", PreloadSplit::kArea}};
  return c;
}
const Choices<ContactCoupling>& choices_of(ContactCoupling) {
  static const Choices<ContactCoupling> c{{"auto", ContactCoupling::kAuto},
                                          {"nodes", ContactCoupling::kNodes},
                                          {"mortar", ContactCoupling::kMortar},
                                          {"node_to_surface", ContactCoupling::kNodeToSurface}};
  return c;
}
const Choices<UnpairedChoice>& choices_of(UnpairedChoice) {
  static const Choices<UnpairedChoice> c{{"error", UnpairedChoice::kError},
                                         {"skip", UnpairedChoice::kSkip}};
  return c;
}
const Choices<SweepMethod>& choices_of(SweepMethod) {
  static const Choices<SweepMethod> c{{"stepped", SweepMethod::kStepped},
                                      {"continuation", SweepMethod::kContinuation},
                                      {"nonlinear_mode", SweepMethod::kNonlinearMode}};
  return c;
}
const Choices<AftChoice>& choices_of(AftChoice) {
  static const Choices<AftChoice> c{{"event", AftChoice::kEvent},
                                    {"sampled", AftChoice::kSampled},
                                    {"event_planar", AftChoice::kEventPlanar}};
  return c;
}
const Choices<StaticChoice>& choices_of(StaticChoice) {
  static const Choices<StaticChoice> c{{"uncoupled", StaticChoice::kUncoupled},
                                       {"coupled", StaticChoice::kCoupled}};
  return c;
}
const Choices<InitialGuessChoice>& choices_of(InitialGuessChoice) {
  static const Choices<InitialGuessChoice> c{{"stuck", InitialGuessChoice::kStuck},
                                             {"free", InitialGuessChoice::kFree}};
  return c;
}
const Choices<PredictorChoice>& choices_of(PredictorChoice) {
  static const Choices<PredictorChoice> c{{"secant", PredictorChoice::kSecant},
                                          {"previous", PredictorChoice::kPrevious}};
  return c;
}
const Choices<RecoveryPoints>& choices_of(RecoveryPoints) {
  static const Choices<RecoveryPoints> c{{"peak", RecoveryPoints::kPeak},
                                         {"all", RecoveryPoints::kAll},
                                         {"none", RecoveryPoints::kNone},
                                         {"list", RecoveryPoints::kList}};
  return c;
}
const Choices<RecoveryMethod>& choices_of(RecoveryMethod) {
  static const Choices<RecoveryMethod> c{{"direct", RecoveryMethod::kDirect},
                                         {"modal", RecoveryMethod::kModal},
                                         {"expansion", RecoveryMethod::kExpansion}};
  return c;
}
const Choices<RecoveryField>& choices_of(RecoveryField) {
  static const Choices<RecoveryField> c{{"displacement", RecoveryField::kDisplacement},
                                        {"stress", RecoveryField::kStress}};
  return c;
}
const Choices<TwoBeamOptions::Arrangement>& choices_of(TwoBeamOptions::Arrangement) {
  static const Choices<TwoBeamOptions::Arrangement> c{{"butt", TwoBeamOptions::Arrangement::kButt},
                                                      {"lap", TwoBeamOptions::Arrangement::kLap}};
  return c;
}
template <class E>
const char* name_of(E v) {
  for (const auto& [name, value] : choices_of(E{}))
    if (value == v) return name;
  STICKSLIP_VERIFY(false, "a value of a case-file choice without a name");
  return "";
}

}  // namespace

const char* case_name(MeshFileFormat v) { return name_of(v); }
const char* case_name(ReducedFileFormat v) { return name_of(v); }
const char* case_name(PreloadSplit v) { return name_of(v); }
const char* case_name(ContactCoupling v) { return name_of(v); }
const char* case_name(UnpairedChoice v) { return name_of(v); }
const char* case_name(SweepMethod v) { return name_of(v); }
const char* case_name(AftChoice v) { return name_of(v); }
const char* case_name(StaticChoice v) { return name_of(v); }
const char* case_name(InitialGuessChoice v) { return name_of(v); }
const char* case_name(PredictorChoice v) { return name_of(v); }
const char* case_name(RecoveryPoints v) { return name_of(v); }
const char* case_name(RecoveryMethod v) { return name_of(v); }
const char* case_name(RecoveryField v) { return name_of(v); }
const char* case_name(TwoBeamOptions::Arrangement v) { return name_of(v); }

namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Value rules shared by the parser and with_parameter(), by the last key of the path.
// Returns an empty string when `value` is allowed.
// Every number of a case (and of its preload file) is 0 or of magnitude in [1e-30, 1e30]
// (kMinNumberMagnitude, kMaxNumberMagnitude, case_file.h). Empty string when `value` is.
std::string magnitude_rule_violation(double value) {
  const double a = std::abs(value);
  if (a == 0.0 || (a >= kMinNumberMagnitude && a <= kMaxNumberMagnitude)) return {};
  return fmt::format("{} is out of range: numbers of a case are 0 or of magnitude between {:g} "
                     "and {:g} (SI units; a product or a square of such numbers must stay a "
                     "finite double)",
                     value, kMinNumberMagnitude, kMaxNumberMagnitude);
}

std::string numeric_rule_violation(const std::string& key, double value) {
  if (!std::isfinite(value)) return "must be a finite number";
  if (std::string range = magnitude_rule_violation(value); !range.empty()) return range;
  if (key == "youngs_modulus" || key == "density" || key == "kt" || key == "kn" || key == "k") {
    if (!(value > 0)) return "must be > 0";
  } else if (key == "poisson_ratio") {
    if (!(value > -1 && value < 0.5)) return "must be in (-1, 0.5)";
  } else if (key == "mu" || key == "preload" || key == "gap" || key == "k1" || key == "alpha" ||
             key == "beta") {
    if (!(value >= 0)) return "must be >= 0";
  } else if (key == "speed_rpm") {
    if (!(value >= 0)) return "must be >= 0";
  } else if (key == "modal_damping_ratio") {
    if (!(value >= 0 && value < 1)) return "must be in [0, 1)";
  } else if (LawParameter::Rule rule; key != "k3" && contact_parameter_rule(key, &rule)) {
    // A parameter of a law registered by the program (contact/contact_law.h).
    if (rule == LawParameter::Rule::kPositive && !(value > 0)) return "must be > 0";
    if (rule == LawParameter::Rule::kNonNegative && !(value >= 0)) return "must be >= 0";
  }
  return {};
}

// The law variant a parsed contact has (contact/contact_law.h).
const ContactLaw& law_of(const ContactDefinition& d) { return contact_law(d.law, d.uses_frame); }

// The key of a contact's parameter block.
std::string parameter_block(const ContactDefinition& d) {
  switch (d.parameters_given) {
    case ContactDefinition::Parameters::kPerPair: return "per_pair";
    case ContactDefinition::Parameters::kTotal: return "total";
    case ContactDefinition::Parameters::kPerArea: return "per_area";
  }
  return "per_pair";
}

// Every parameter key of a law name, over its variants (1D and frame), in registration order.
std::vector<std::string> law_name_keys(const std::string& law) {
  std::vector<std::string> keys;
  for (const ContactLaw* l : find_contact_laws(law)) {
    for (const std::string& key : l->parameter_keys()) {
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    }
  }
  return keys;
}

// The parameters a parsed contact has: its law variant's.
std::vector<std::string> parameter_keys(const ContactDefinition& d) {
  return law_of(d).parameter_keys();
}

// Whether the contact acts in the frame normal/t1 (3D) rather than along `direction` (1D).
bool uses_frame(const ContactDefinition& d) { return d.uses_frame; }

double* contact_parameter(ContactParametersDefinition& p, const std::string& key) {
  return p.field(key);
}

// Optimal string alignment distance: insertions, deletions, substitutions and transpositions of
// adjacent characters each cost 1 ("jiont" -> "joint" is 1).
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// " (did you mean 'x'?)" for the closest candidate within a small edit distance, else "".
std::string suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::string::npos;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance) best = c, best_distance = d;
  }
  const size_t allowed = std::max<size_t>(1, std::min(word.size(), best.size()) / 3);
  if (best.empty() || best_distance > allowed) return {};
  return " (did you mean '" + best + "'?)";
}

std::string join(const std::vector<std::string>& words, const char* separator) {
  std::string s;
  for (size_t i = 0; i < words.size(); ++i) s += (i ? separator : "") + words[i];
  return s;
}

std::string format_number(double v) { return fmt::format("{}", v); }

int line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

std::string node_text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "nothing";
}

// ---------------------------------------------------------------------------------------------
class Parser {
 public:
  Parser(const std::string& file, const std::string& base_dir, CaseDefinition& out)
      : file_(file), base_dir_(base_dir), out_(out) {}

  [[noreturn]] void fail(const std::string& path, int line, const std::string& message) const {
    throw InvalidInput(SourceLocation{file_, line, path}, message);
  }
  void check(bool ok, const std::string& path, int line, const std::string& message) const {
    if (!ok) fail(path, line, message);
  }
  void record(const std::string& path, int line) { out_.locations[path] = {file_, line, path}; }
  int line(const std::string& path) const {
    const auto it = out_.locations.find(path);
    return it == out_.locations.end() ? 0 : it->second.line;
  }

  // --- typed values (node = the value, at = the line of its key) ---
  // A scalar is reported on its own line (an item of a block list may be below its key).
  static int here(const YAML::Node& node, int at) {
    return node.IsScalar() && line_of(node) > 0 ? line_of(node) : at;
  }
  double number(const YAML::Node& node, const std::string& path, int at) const {
    at = here(node, at);
    check(node.IsScalar(), path, at, "expected a number, got " + node_text(node));
    // A quoted scalar has the non-specific tag "!": text, even when it looks like a number.
    check(node.Tag() != "!", path, at,
          "expected a number, got the string \"" + node.Scalar() + "\"");
    double v = 0;
    check(YAML::convert<double>::decode(node, v), path, at,
          "expected a number, got '" + node.Scalar() + "'");
    check(std::isfinite(v), path, at, "must be a finite number");
    const std::string range = magnitude_rule_violation(v);
    check(range.empty(), path, at, range);
    return v;
  }
  double checked_number(const YAML::Node& node, const std::string& path, const std::string& key,
                        int at) const {
    at = here(node, at);
    const double v = number(node, path, at);
    const std::string rule = numeric_rule_violation(key, v);
    check(rule.empty(), path, at, rule + ", got " + format_number(v));
    return v;
  }
  bool is_integer(const YAML::Node& node) const {
    if (!node.IsScalar() || node.Tag() == "!") return false;
    const std::string& s = node.Scalar();
    if (s.empty()) return false;
    size_t i = (s[0] == '-' || s[0] == '+') ? 1 : 0;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
      if (s[i] < '0' || s[i] > '9') return false;
    return true;
  }
  int integer(const YAML::Node& node, const std::string& path, int at) const {
    at = here(node, at);
    check(is_integer(node), path, at, "expected an integer, got " + describe(node));
    const std::string& s = node.Scalar();
    long long v = 0;
    const char* begin = s.data() + (s[0] == '+' ? 1 : 0);
    const auto [end, ec] = std::from_chars(begin, s.data() + s.size(), v);
    check(ec == std::errc() && end == s.data() + s.size() && v >= std::numeric_limits<int>::min() &&
              v <= std::numeric_limits<int>::max(),
          path, at, "integer out of range: " + s);
    return static_cast<int>(v);
  }
  std::string text(const YAML::Node& node, const std::string& path, int at) const {
    at = here(node, at);
    check(node.IsScalar(), path, at, "expected a string, got " + node_text(node));
    return node.Scalar();
  }
  bool boolean(const YAML::Node& node, const std::string& path, int at) const {
    at = here(node, at);
    bool v = false;
    check(node.IsScalar() && node.Tag() != "!" && YAML::convert<bool>::decode(node, v), path, at,
          "expected true or false, got " + describe(node));
    return v;
  }
  std::string choice(const YAML::Node& node, const std::string& path, int at,
                     const std::vector<std::string>& options) const {
    at = here(node, at);
    const std::string v = text(node, path, at);
    if (std::find(options.begin(), options.end(), v) == options.end())
      fail(path, at,
           "must be one of " + join(options, " | ") + ", got '" + v + "'" + suggestion(v, options));
    return v;
  }
  void sequence(const YAML::Node& node, const std::string& path, int at) const {
    check(node.IsSequence(), path, at, "expected a list, got " + describe(node));
  }
  std::array<double, 3> vector3(const YAML::Node& node, const std::string& path, int at) const {
    sequence(node, path, at);
    check(node.size() == 3, path, at,
          "expected a list of 3 numbers, got " + std::to_string(node.size()) + " entries");
    std::array<double, 3> v{};
    for (size_t i = 0; i < 3; ++i) v[i] = number(node[i], path, at);
    return v;
  }
  // x | y | z | -x | -y | -z, or a nonzero vector (normalised).
  std::array<double, 3> direction(const YAML::Node& node, const std::string& path, int at) const {
    if (node.IsScalar()) {
      const std::vector<std::string> names{"x", "y", "z", "-x", "-y", "-z", "+x", "+y", "+z"};
      const std::string s = choice(node, path, at, names);
      std::array<double, 3> v{0, 0, 0};
      v[static_cast<size_t>(s.back() - 'x')] = s[0] == '-' ? -1.0 : 1.0;
      return v;
    }
    std::array<double, 3> v = vector3(node, path, at);
    const double norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    check(norm > 0, path, at, "must be a nonzero vector");
    for (double& c : v) c /= norm;
    return v;
  }
  // Resolved path of an existing file.
  std::string existing_file(const YAML::Node& node, const std::string& path, int at) const {
    const std::string name = text(node, path, at);
    check(!name.empty(), path, at, "expected a file name");
    const std::string resolved = resolve(name);
    std::error_code ec;
    check(fs::is_regular_file(resolved, ec), path, at,
          "file not found: " + resolved + (name != resolved ? " ('" + name + "')" : ""));
    return resolved;
  }
  std::string resolve(const std::string& name) const {
    const fs::path p(name);
    if (p.is_absolute() || base_dir_.empty()) return p.lexically_normal().string();
    return (fs::path(base_dir_) / p).lexically_normal().string();
  }
  std::string describe(const YAML::Node& node) const {
    if (node.IsScalar() && node.Tag() == "!") return "the string \"" + node.Scalar() + "\"";
    if (node.IsScalar()) return "'" + node.Scalar() + "'";
    return node_text(node);
  }

  const std::string& file() const { return file_; }
  CaseDefinition& out() { return out_; }

 private:
  std::string file_;
  std::string base_dir_;
  CaseDefinition& out_;
};

// A YAML map whose keys are checked against the known ones (unknown and duplicate keys rejected)
// and whose values are read with their locations recorded under `path`.
class MapView {
 public:
  MapView(Parser& p, const YAML::Node& node, std::string path, int at,
          std::vector<std::string> known, const std::string& context = "")
      : p_(p), path_(std::move(path)), line_(at) {
    if (line_ <= 0) line_ = line_of(node);
    p_.check(node.IsMap(), path_.empty() ? "(document)" : path_, line_,
             "expected a map of keys, got " + p_.describe(node));
    for (auto it = node.begin(); it != node.end(); ++it) {
      const int key_line = line_of(it->first);
      const std::string key = p_.text(it->first, path_, key_line);
      const std::string key_path = full(key);
      if (std::find(known.begin(), known.end(), key) == known.end()) {
        p_.fail(key_path, key_line,
                "unknown key '" + key + "'" + context + suggestion(key, known) +
                    "; known keys: " + join(known, ", "));
      }
      if (entries_.count(key))
        p_.fail(key_path, key_line,
                "duplicate key (first given on line " + std::to_string(entries_[key].line) + ")");
      entries_[key] = {it->second, key_line};
      p_.record(key_path, key_line);
    }
  }

  bool has(const std::string& key) const { return entries_.count(key) > 0; }
  const YAML::Node& value(const std::string& key) const { return entries_.at(key).value; }
  int line(const std::string& key) const {
    const auto it = entries_.find(key);
    return it == entries_.end() ? line_ : it->second.line;
  }
  int line() const { return line_; }
  std::string full(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& path() const { return path_; }
  std::vector<std::string> keys() const {
    std::vector<std::string> k;
    for (const auto& e : entries_) k.push_back(e.first);
    return k;
  }

  void require(const std::string& key, const std::string& why = "") const {
    if (!has(key))
      p_.fail(full(key), line_, "required key missing" + (why.empty() ? "" : " (" + why + ")"));
  }
  void exclusive(const std::string& a, const std::string& b, const std::string& why = "") const {
    if (has(a) && has(b))
      p_.fail(full(b), line(b),
              "give either '" + a + "' or '" + b + "', not both" + (why.empty() ? "" : ": " + why));
  }
  void forbid(const std::string& key, const std::string& why) const {
    if (has(key)) p_.fail(full(key), line(key), "not allowed " + why);
  }

  // Readers: leave *dst unchanged (the default) when the key is absent.
  void number(const std::string& key, double* dst) const {
    if (has(key)) *dst = p_.checked_number(value(key), full(key), key, line(key));
  }
  void integer(const std::string& key, int* dst, int min) const {
    if (!has(key)) return;
    *dst = p_.integer(value(key), full(key), line(key));
    p_.check(*dst >= min, full(key), line(key),
             "must be >= " + std::to_string(min) + ", got " + std::to_string(*dst));
  }
  // The same with an upper bound; `why` says what the bound is for.
  void integer(const std::string& key, int* dst, int min, int max, const std::string& why) const {
    if (!has(key)) return;
    integer(key, dst, min);
    p_.check(*dst <= max, full(key), line(key),
             "must be <= " + std::to_string(max) + " (" + why + "), got " + std::to_string(*dst));
  }
  void text(const std::string& key, std::string* dst) const {
    if (has(key)) *dst = p_.text(value(key), full(key), line(key));
  }
  void boolean(const std::string& key, bool* dst) const {
    if (has(key)) *dst = p_.boolean(value(key), full(key), line(key));
  }
  void choice(const std::string& key, std::string* dst,
              const std::vector<std::string>& options) const {
    if (has(key)) *dst = p_.choice(value(key), full(key), line(key), options);
  }
  // One of the names of the enum's table (choices_of below).
  template <class E>
  void choice(const std::string& key, E* dst) const {
    if (!has(key)) return;
    const auto& table = choices_of(E{});
    std::vector<std::string> names;
    for (const auto& [name, value] : table) names.emplace_back(name);
    const std::string v = p_.choice(value(key), full(key), line(key), names);
    for (const auto& [name, value] : table)
      if (v == name) *dst = value;
  }
  void file(const std::string& key, std::string* dst) const {
    if (has(key)) *dst = p_.existing_file(value(key), full(key), line(key));
  }

 private:
  struct Entry {
    YAML::Node value;
    int line = 0;
  };
  Parser& p_;
  std::string path_;
  int line_ = 0;
  std::map<std::string, Entry> entries_;
};

// A node selection: a set name, a node id, or a list of them.
NodeSelection node_selection(Parser& p, const YAML::Node& node, const std::string& path, int at) {
  NodeSelection s;
  auto one = [&](const YAML::Node& item) {
    p.check(item.IsScalar(), path, at,
            "expected a node set name or a node id, got " + p.describe(item));
    if (p.is_integer(item)) {
      const int id = p.integer(item, path, at);
      p.check(id > 0, path, at, "node ids are positive, got " + std::to_string(id));
      s.ids.push_back(id);
    } else {
      s.sets.push_back(item.Scalar());
    }
  };
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) one(item);
  } else {
    one(node);
  }
  p.check(!s.empty(), path, at, "expected at least one node set or node id");
  return s;
}

// ------------------------------------------------------------------------------ CSV files ---
struct CsvRecord {
  std::vector<std::string> fields;
  int line = 0;
};

bool parse_int(const std::string& s, long long* v) {
  const char* begin = s.data() + (!s.empty() && s[0] == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(begin, s.data() + s.size(), *v);
  return ec == std::errc() && end == s.data() + s.size() && !s.empty();
}

bool parse_double(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

std::vector<CsvRecord> read_csv_records(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput(SourceLocation{path, 0, ""}, "cannot open the file");
  std::vector<CsvRecord> records;
  std::string text;
  int line = 0;
  bool first = true;
  while (std::getline(in, text)) {
    ++line;
    CsvRecord r;
    r.line = line;
    std::string field;
    for (const char c : text + "\n") {
      if (c == ',' || c == ';' || c == ' ' || c == '\t' || c == '\r' || c == '\n') {
        if (!field.empty()) r.fields.push_back(field);
        field.clear();
      } else {
        field += c;
      }
    }
    if (r.fields.empty() || r.fields[0][0] == '#') continue;
    double ignored = 0;
    if (first && !parse_double(r.fields[0], &ignored)) {  // a header line
      first = false;
      continue;
    }
    first = false;
    records.push_back(std::move(r));
  }
  if (records.empty()) throw InvalidInput(SourceLocation{path, 0, ""}, "no records in the file");
  return records;
}

int csv_id(const std::string& path, const CsvRecord& r, size_t i, bool zero_allowed) {
  long long v = 0;
  const std::string& s = r.fields[i];
  if (!parse_int(s, &v) || v < (zero_allowed ? 0 : 1) || v > std::numeric_limits<int>::max())
    throw InvalidInput(SourceLocation{path, r.line, ""},
                       "field " + std::to_string(i + 1) + ": expected a " +
                           (zero_allowed ? "node id or 0 (ground)" : "positive node id") +
                           ", got '" + s + "'");
  return static_cast<int>(v);
}

// Re-throws an error of a referenced file with the case key that referenced it.
template <typename F>
auto with_key(const std::string& key, F&& f) {
  try {
    return f();
  } catch (const InvalidInput& e) {
    SourceLocation where = e.where();
    where.key = key;
    throw InvalidInput(where, e.message());
  }
}

// Names appear in dotted paths (contacts.joint.per_pair.kt): no '.', '[', ']'; and in file and
// folder names of the results (recovery/<body>/, loads_p<N>_<body>.mac): no '/'.
void check_name(const Parser& p, const std::string& name, const std::string& path, int line) {
  p.check(!name.empty(), path, line, "empty name");
  p.check(name.find_first_of(".[]/") == std::string::npos, path, line,
          "names may not contain '.', '[', ']' or '/', got '" + name + "'");
}

// Iterates the entries of a map whose keys are user-chosen names.
template <typename F>
void for_each_named(Parser& p, const MapView& parent, const std::string& key, F&& f) {
  if (!parent.has(key)) return;
  const YAML::Node& node = parent.value(key);
  p.check(node.IsMap(), key, parent.line(key), "expected a map of names, got " + p.describe(node));
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const int line = line_of(it->first);
    const std::string name = p.text(it->first, key, line);
    const std::string path = key + "." + name;
    check_name(p, name, path, line);
    p.check(seen.insert(name).second, path, line, "duplicate name");
    p.record(path, line);
    f(name, it->second, path, line);
  }
}

void parse_materials(Parser& p, const MapView& top) {
  for_each_named(
      p, top, "materials",
      [&](const std::string& name, const YAML::Node& node, const std::string& path, int line) {
        MapView m(p, node, path, line, case_keys_in("materials.NAME"));
        MaterialDefinition d;
        for (const char* key : {"youngs_modulus", "poisson_ratio", "density"}) m.require(key);
        m.number("youngs_modulus", &d.youngs_modulus);
        m.number("poisson_ratio", &d.poisson_ratio);
        m.number("density", &d.density);
        p.out().materials[name] = d;
      });
}

void parse_two_beam(Parser& p, const MapView& m, TwoBeamDefinition& d) {
  m.choice("arrangement", &d.arrangement);
  if (m.has("element")) {
    std::string e = p.text(m.value("element"), m.full("element"), m.line("element"));
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::toupper(c); });
    const std::vector<std::string> hexahedra{"C3D8", "C3D8I", "C3D20", "C3D20R"};
    p.check(std::find(hexahedra.begin(), hexahedra.end(), e) != hexahedra.end(), m.full("element"),
            m.line("element"),
            "must be a hexahedron type, one of " + join(hexahedra, " | ") + ", got '" + e + "'" +
                suggestion(e, hexahedra));
    parse_element_type(e, &d.element);
  }
  m.boolean("coarse", &d.coarse);
  const auto counts = [&](const char* key, std::array<int, 3>& dst) {
    const YAML::Node& v = m.value(key);
    p.sequence(v, m.full(key), m.line(key));
    p.check(v.size() == 3, m.full(key), m.line(key),
            "expected 3 element counts [x, y, z], got " + std::to_string(v.size()));
    for (size_t i = 0; i < 3; ++i) {
      dst[i] = p.integer(v[i], m.full(key), m.line(key));
      p.check(dst[i] >= 1, m.full(key), m.line(key), "element counts must be >= 1");
    }
  };
  if (m.has("box")) counts("box", d.box);
  if (m.has("end_block")) counts("end_block", d.end_block);
  if (m.has("beam2_box")) counts("beam2_box", d.beam2_box.emplace());
  if (m.has("beam2_end_block")) counts("beam2_end_block", d.beam2_end_block.emplace());
  // Elements of one beam, the product saturated at the limit (three counts below 2^31 each
  // could overflow 64 bits).
  const auto elements = [](const std::array<int, 3>& c) {
    long long e = 1;
    for (int n : c) e = std::min(e * n, kMaxGeneratedElements + 1);
    return e;
  };
  const auto text = [](const std::array<int, 3>& c) {
    return fmt::format("[{}, {}, {}]", c[0], c[1], c[2]);
  };
  // Each beam's box and end block (beam 2's under the keys `prefix`), checked where given.
  const auto check_beam = [&](const std::array<int, 3>& box, const std::array<int, 3>& end_block,
                              const std::string& prefix) {
    const std::string box_key = prefix + "box", end_key = prefix + "end_block";
    if (!m.has(box_key) && !m.has(end_key)) return;
    const std::string key = m.has(end_key) ? end_key : box_key;
    p.check(elements(box) + elements(end_block) <= kMaxGeneratedElements, m.full(key),
            m.line(key),
            prefix + "box " + text(box) + " and " + prefix + "end_block " + text(end_block) +
                " make more than " + std::to_string(kMaxGeneratedElements) +
                " elements per beam");
    if (d.coarse) return;
    const std::string y_key = m.has(end_key) ? end_key : box_key;
    const std::string z_key = m.has(box_key) ? box_key : end_key;
    p.check(end_block[1] == box[1], m.full(y_key), m.line(y_key),
            "a conforming mesh needs " + end_key + "[1] (y) = " + box_key + "[1], got " +
                std::to_string(end_block[1]) + " and " + std::to_string(box[1]));
    p.check(box[2] > end_block[2], m.full(z_key), m.line(z_key),
            "a conforming mesh needs " + box_key + "[2] (z) > " + end_key + "[2], got " +
                std::to_string(box[2]) + " and " + std::to_string(end_block[2]));
  };
  check_beam(d.box, d.end_block, "");
  if (d.beam2_box || d.beam2_end_block) {
    p.check(!d.coarse, m.full("coarse"), m.line("coarse"),
            "the thesis's coarse mesh has no beam2_box or beam2_end_block");
    check_beam(d.beam2_box.value_or(d.box), d.beam2_end_block.value_or(d.end_block), "beam2_");
  }
  for (const char* key : {"beam_length", "width", "thickness", "end_length"}) {
    if (!m.has(key)) continue;
    const double v = p.number(m.value(key), m.full(key), m.line(key));
    p.check(v > 0, m.full(key), m.line(key), "must be > 0, got " + format_number(v));
    const std::string k = key;
    (k == "beam_length" ? d.beam_length
     : k == "width"     ? d.width
     : k == "thickness" ? d.thickness
                        : d.end_length) = v;
  }
}

// An element type among `allowed` (msh hexahedra).
void element_choice(Parser& p, const MapView& m, const std::string& key,
                    const std::vector<ElementType>& allowed, ElementType* dst) {
  if (!m.has(key)) return;
  std::vector<std::string> names;
  for (ElementType t : allowed) names.emplace_back(element_type_name(t));
  const std::string v = p.choice(m.value(key), m.full(key), m.line(key), names);
  parse_element_type(v, dst);
}

void parse_meshes(Parser& p, const MapView& top) {
  for_each_named(
      p, top, "meshes",
      [&](const std::string& name, const YAML::Node& node, const std::string& path, int line) {
        const std::vector<std::string> two_beam_keys{
            "arrangement", "element",     "coarse", "box",       "end_block",  "beam2_box",
            "beam2_end_block", "beam_length", "width", "thickness", "end_length"};
        MapView m(p, node, path, line, case_keys_in("meshes.NAME"));
        MeshDefinition d;
        m.exclusive("generate", "file");
        if (!m.has("file")) m.require("generate", "or 'file'");
        if (m.has("generate")) {
          d.source = MeshDefinition::Source::kGenerate;
          m.choice("generate", &d.generate, {"two_beam"});
          for (const char* key : {"format", "hexahedron8", "hexahedron20"})
            m.forbid(key, "with 'generate' (it is for mesh files)");
          parse_two_beam(p, m, d.two_beam);
        } else {
          d.source = MeshDefinition::Source::kFile;
          for (const std::string& key : two_beam_keys)
            m.forbid(key, "with 'file' (it is for 'generate: two_beam')");
          m.file("file", &d.file);
          if (m.has("format")) {
            m.choice("format", &d.format);
          } else {
            std::string ext = fs::path(d.file).extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(),
                           [](unsigned char c) { return std::tolower(c); });
            p.check(ext == ".inp" || ext == ".msh" || ext == ".cdb", m.full("file"), m.line("file"),
                    "cannot tell the format from the extension '" + ext +
                        "': name it .inp, .msh or .cdb, or add 'format: inp | msh | cdb'");
            d.format = ext == ".inp"   ? MeshFileFormat::kInp
                       : ext == ".msh" ? MeshFileFormat::kMsh
                                       : MeshFileFormat::kCdb;
          }
          if (d.format != MeshFileFormat::kMsh) {
            for (const char* key : {"hexahedron8", "hexahedron20"})
              m.forbid(key, std::string("for a .") + case_name(d.format) +
                                " file (its element types are in the file)");
          }
          element_choice(p, m, "hexahedron8",
                         {ElementType::kC3D8, ElementType::kC3D8I, ElementType::kC3D8R},
                         &d.hexahedron8);
          element_choice(p, m, "hexahedron20", {ElementType::kC3D20, ElementType::kC3D20R},
                         &d.hexahedron20);
        }
        p.out().meshes[name] = d;
      });
}

// A support direction's name: x, y, z, or t1, t2, n in a local frame.
const char* support_direction_name(int row, bool local_frame) {
  static const char* const kGlobal[3] = {"x", "y", "z"};
  static const char* const kLocal[3] = {"t1", "t2", "n"};
  return (local_frame ? kLocal : kGlobal)[row];
}

// bodies.B.supports: a list of {nodes, directions, normal, t1}.
std::vector<SupportDefinition> parse_supports(Parser& p, const MapView& body) {
  const YAML::Node& list = body.value("supports");
  p.sequence(list, body.full("supports"), body.line("supports"));
  p.check(list.size() > 0, body.full("supports"), body.line("supports"),
          "expected at least one support");
  std::vector<SupportDefinition> out;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = body.full("supports") + "[" + std::to_string(i) + "]";
    MapView m(p, list[i], path, line_of(list[i]) > 0 ? line_of(list[i]) : body.line("supports"),
              case_keys_in("bodies.NAME.supports"));
    p.record(path, m.line());
    SupportDefinition d;
    m.boolean("from_mesh", &d.from_mesh);
    if (d.from_mesh) {
      for (const char* key : {"nodes", "directions", "normal", "t1"})
        m.forbid(key, "with from_mesh (the *BOUNDARY lines of the mesh say which DOFs)");
      out.push_back(std::move(d));
      continue;
    }
    m.require("nodes");
    m.require("directions", "x, y, z, or with 'normal' t1, t2, n");
    d.nodes = node_selection(p, m.value("nodes"), m.full("nodes"), m.line("nodes"));
    d.local_frame = m.has("normal");
    if (d.local_frame) {
      d.normal = p.direction(m.value("normal"), m.full("normal"), m.line("normal"));
      if (m.has("t1")) {
        d.t1 = p.direction(m.value("t1"), m.full("t1"), m.line("t1"));
        const double c = d.t1[0] * d.normal[0] + d.t1[1] * d.normal[1] + d.t1[2] * d.normal[2];
        p.check(std::abs(c) < 1 - 1e-6, m.full("t1"), m.line("t1"),
                "must not be parallel to the normal");
      }
    } else {
      m.forbid("t1", "without 'normal' (t1 is a hint for the local frame of 'normal')");
    }
    const std::vector<std::string> names =
        d.local_frame ? std::vector<std::string>{"t1", "t2", "n"}
                      : std::vector<std::string>{"x", "y", "z"};
    const YAML::Node& v = m.value("directions");
    std::vector<YAML::Node> items;
    if (v.IsSequence()) {
      for (const YAML::Node& item : v) items.push_back(item);
    } else {
      items.push_back(v);
    }
    p.check(!items.empty(), m.full("directions"), m.line("directions"),
            "expected at least one direction");
    for (const YAML::Node& item : items) {
      const std::string name = p.text(item, m.full("directions"), m.line("directions"));
      p.check(std::find(names.begin(), names.end(), name) != names.end(), m.full("directions"),
              m.line("directions"),
              "unknown direction '" + name + "': expected " + join(names, ", ") +
                  (d.local_frame ? " (the rows of the frame of 'normal')"
                                 : " (global axes; t1, t2, n need 'normal')"));
      const int row = static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
      p.check(std::find(d.directions.begin(), d.directions.end(), row) == d.directions.end(),
              m.full("directions"), m.line("directions"), "direction '" + name + "' given twice");
      d.directions.push_back(row);
    }
    out.push_back(std::move(d));
  }
  return out;
}

// bodies.B.cyclic: {sectors, axis: {point, direction}, low, high, tolerance}.
CyclicDefinition parse_cyclic(Parser& p, const MapView& body) {
  MapView m(p, body.value("cyclic"), body.full("cyclic"), body.line("cyclic"),
            case_keys_in("bodies.NAME.cyclic"));
  for (const char* key : {"sectors", "axis"}) m.require(key);
  // A body of the sector that crosses no boundary (a damper between two blades) has neither.
  p.check(m.has("low") == m.has("high"), m.full(m.has("low") ? "low" : "high"),
          m.line(m.has("low") ? "low" : "high"),
          "give both boundaries (low and high) or neither (a body of the sector that crosses "
          "no sector boundary, e.g. a damper between two blades)");
  CyclicDefinition d;
  m.integer("sectors", &d.sectors, 2, kMaxCyclicSectors,
            "one modal analysis per nodal diameter 0..N/2");
  MapView axis(p, m.value("axis"), m.full("axis"), m.line("axis"),
               case_keys_in("bodies.NAME.cyclic.axis"));
  axis.require("point");
  axis.require("direction");
  d.axis_point = p.vector3(axis.value("point"), axis.full("point"), axis.line("point"));
  d.axis_direction =
      p.direction(axis.value("direction"), axis.full("direction"), axis.line("direction"));
  if (m.has("low")) {
    d.low = node_selection(p, m.value("low"), m.full("low"), m.line("low"));
    d.high = node_selection(p, m.value("high"), m.full("high"), m.line("high"));
  }
  if (m.has("tolerance")) {
    d.tolerance = p.number(m.value("tolerance"), m.full("tolerance"), m.line("tolerance"));
    p.check(d.tolerance > 0, m.full("tolerance"), m.line("tolerance"),
            "must be > 0, got " + format_number(d.tolerance));
  }
  return d;
}

void parse_bodies(Parser& p, const MapView& top) {
  for_each_named(
      p, top, "bodies",
      [&](const std::string& name, const YAML::Node& node, const std::string& path, int line) {
        p.check(name != "ground", path, line,
                "'ground' is reserved (the fixed ground of contacts)");
        MapView m(p, node, path, line,
                  case_keys_in("bodies.NAME"));
        BodyDefinition d;
        m.number("modal_damping_ratio", &d.modal_damping_ratio);
        if (m.has("reduced")) {
          d.source = BodyDefinition::Source::kReduced;
          for (const char* key : {"mesh", "element_set", "material", "clamp", "supports", "masters",
                                  "modes", "mass_rule", "cyclic"})
            m.forbid(key, "with 'reduced' (the matrices are the body)");
          MapView r(p, m.value("reduced"), m.full("reduced"), m.line("reduced"),
                    case_keys_in("bodies.NAME.reduced"));
          r.require("stiffness");
          r.require("mass");
          r.file("stiffness", &d.reduced.stiffness);
          r.file("mass", &d.reduced.mass);
          const std::string ext = fs::path(d.reduced.stiffness).extension().string();
          d.reduced.format = ext == ".mtx" ? ReducedFileFormat::kMatrixMarket
                                           : ReducedFileFormat::kHarwellBoeing;
          r.choice("format", &d.reduced.format);
          if (d.reduced.format == ReducedFileFormat::kAbaqusMatrix) {
            // Abaqus matrix input format: every entry names its node and DOF, no mapping.
            r.forbid("mapping", "with format: abaqus_matrix (its entries name node and DOF)");
          } else if (r.has("mapping")) {
            r.file("mapping", &d.reduced.mapping);
          } else {
            p.check(d.reduced.format == ReducedFileFormat::kHarwellBoeing, r.full("mapping"),
                    r.line(),
                    "required key missing (only Harwell-Boeing matrices have a default mapping)");
            d.reduced.mapping =
                fs::path(d.reduced.stiffness).replace_extension(".mapping").string();
            std::error_code ec;
            p.check(fs::is_regular_file(d.reduced.mapping, ec), r.full("mapping"), r.line(),
                    "file not found: " + d.reduced.mapping +
                        " (the default mapping next to the stiffness matrix; or give 'mapping')");
          }
        } else {
          d.source = BodyDefinition::Source::kMesh;
          m.require("mesh", "or 'reduced'");
          m.text("mesh", &d.mesh);
          if (!p.out().meshes.count(d.mesh)) {
            std::vector<std::string> names;
            for (const auto& [n, _] : p.out().meshes) names.push_back(n);
            p.fail(m.full("mesh"), m.line("mesh"),
                   "unknown mesh '" + d.mesh + "'" + suggestion(d.mesh, names) +
                       (names.empty() ? "; no meshes defined" : "; meshes: " + join(names, ", ")));
          }
          m.text("material", &d.material);  // none: the mesh file's (pipeline)
          if (!d.material.empty() && !p.out().materials.count(d.material)) {
            std::vector<std::string> names;
            for (const auto& [n, _] : p.out().materials) names.push_back(n);
            p.fail(m.full("material"), m.line("material"),
                   "unknown material '" + d.material + "'" + suggestion(d.material, names) +
                       (names.empty() ? "; no materials defined"
                                      : "; materials: " + join(names, ", ")));
          }
          m.text("element_set", &d.element_set);
          if (m.has("clamp"))
            d.clamp = node_selection(p, m.value("clamp"), m.full("clamp"), m.line("clamp"));
          if (m.has("supports")) d.supports = parse_supports(p, m);
          if (m.has("masters"))
            d.masters = node_selection(p, m.value("masters"), m.full("masters"), m.line("masters"));
          m.integer("modes", &d.modes, 0, kMaxReducedBodyDofs,
                    "the largest reduced body, in DOFs: K_r and M_r are dense");
          std::string rule = "exact";
          m.choice("mass_rule", &rule, {"exact", "calculix"});
          d.mass_rule =
              rule == "calculix" ? MassIntegration::kStiffnessRule : MassIntegration::kExact;
          if (m.has("cyclic")) d.cyclic = parse_cyclic(p, m);
        }
        p.out().bodies[name] = d;
      });
}

// A body reference (optionally "ground").
void check_body(Parser& p, const std::string& body, const std::string& path, int at,
                bool ground_allowed) {
  if (ground_allowed && body == "ground") return;
  if (p.out().bodies.count(body)) return;
  std::vector<std::string> names;
  for (const auto& [n, _] : p.out().bodies) names.push_back(n);
  if (ground_allowed) names.push_back("ground");
  p.fail(path, at,
         "unknown body '" + body + "'" + suggestion(body, names) +
             (names.empty() ? "; no bodies defined" : "; bodies: " + join(names, ", ")));
}

void check_selection_on_body(Parser& p, const std::string& body, const NodeSelection& s,
                             const std::string& path, int at) {
  const auto it = p.out().bodies.find(body);
  if (it == p.out().bodies.end() || it->second.source != BodyDefinition::Source::kReduced) return;
  p.check(s.sets.empty(), path, at,
          "body '" + body + "' is given by reduced matrices: it has no node sets, give node ids");
}

void parse_contacts(Parser& p, const MapView& top) {
  if (!top.has("contacts")) return;
  const YAML::Node& list = top.value("contacts");
  p.sequence(list, "contacts", top.line("contacts"));
  std::set<std::string> names;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node& node = list[i];
    const std::string index_path = "contacts[" + std::to_string(i) + "]";
    // The name is needed for the path, so read it first.
    std::string name;
    if (node.IsMap() && node["name"] && node["name"].IsScalar()) name = node["name"].Scalar();
    const std::string path = name.empty() ? index_path : "contacts." + name;
    MapView m(p, node, path, line_of(node),
              case_keys_in("contacts[]"));
    p.record(path, m.line());
    ContactDefinition d;
    m.require("name");
    m.text("name", &d.name);
    check_name(p, d.name, m.full("name"), m.line("name"));
    p.check(names.insert(d.name).second, m.full("name"), m.line("name"),
            "duplicate contact name '" + d.name + "'");
    m.require("law");
    m.choice("law", &d.law, contact_law_names());

    // Nodes: between (coincidence) or listed pairs.
    const int given = int(m.has("between")) + int(m.has("pairs")) + int(m.has("pairs_file"));
    p.check(given == 1, given == 0 ? m.full("between") : m.full("pairs"),
            given == 0 ? m.line() : m.line(m.has("pairs") ? "pairs" : "pairs_file"),
            given == 0 ? "required key missing: give 'between' (node sets), 'pairs' or 'pairs_file'"
                       : "give only one of 'between', 'pairs', 'pairs_file'");
    if (m.has("between")) {
      m.forbid("bodies", "with 'between' (its keys are the bodies)");
      const YAML::Node& b = m.value("between");
      const std::string bpath = m.full("between");
      p.check(b.IsMap() && (b.size() == 1 || b.size() == 2), bpath, m.line("between"),
              "expected a map of one or two bodies to their node sets, e.g. {beam1: CONTACT1, "
              "beam2: CONTACT2}; one body = contact with the ground");
      int k = 0;
      std::set<std::string> seen;
      for (auto it = b.begin(); it != b.end(); ++it, ++k) {
        const int at = line_of(it->first);
        const std::string body = p.text(it->first, bpath, at);
        check_body(p, body, bpath + "." + body, at, false);
        p.check(seen.insert(body).second, bpath + "." + body, at, "duplicate key");
        p.check(p.out().bodies.at(body).source == BodyDefinition::Source::kMesh, bpath + "." + body,
                at,
                "body '" + body +
                    "' is given by reduced matrices (no coordinates): list the pairs instead");
        p.record(bpath + "." + body, at);
        (k == 0 ? d.body_a : d.body_b) = body;
        (k == 0 ? d.nodes_a : d.nodes_b) = node_selection(p, it->second, bpath + "." + body, at);
      }
      if (d.body_b.empty()) d.body_b = "ground";
      m.choice("coupling", &d.coupling);
      // mortar and node_to_surface couple two surfaces (their points' partners from geometry).
      const bool surfaces = d.coupling == ContactCoupling::kMortar ||
                            d.coupling == ContactCoupling::kNodeToSurface;
      if (surfaces) {
        const std::string name(case_name(d.coupling));
        p.check(d.body_b != "ground", m.full("coupling"), m.line("coupling"),
                name + " couples two surfaces: 'between' needs two bodies");
        m.forbid("tolerance", "with coupling: " + name + " (use 'search_distance')");
      }
      // One body (to the ground): each node is a pair, nothing is mortar's.
      const bool nodes_only = d.coupling == ContactCoupling::kNodes || d.body_b == "ground";
      if (nodes_only) {
        const std::string why = d.body_b == "ground" ? "with one body (it is mortar's)"
                                                     : "with coupling: nodes (it is mortar's)";
        m.forbid("search_distance", why);
        m.forbid("unpaired", why);
      }
      // auto: the coincidence tolerance decides whether the surfaces match; mortar's keys
      // apply when they do not.
      if (!nodes_only) {
        m.number("search_distance", &d.search_distance);
        p.check(d.search_distance >= 0, m.full("search_distance"), m.line("search_distance"),
                "must be >= 0 (0: automatic), got " + format_number(d.search_distance));
        m.choice("unpaired", &d.unpaired);
      }
      if (!surfaces) {
        m.number("tolerance", &d.tolerance);
        p.check(d.tolerance > 0, m.full("tolerance"), m.line("tolerance"),
                "must be > 0, got " + format_number(d.tolerance));
      }
    } else {
      for (const char* key : {"coupling", "search_distance", "unpaired"})
        m.forbid(key, "with listed pairs (it belongs to 'between')");
      m.forbid("tolerance", "with listed pairs (it is the coincidence distance of 'between')");
      m.require("bodies", "the two bodies the pair node ids belong to, e.g. [beam1, beam2]");
      const YAML::Node& b = m.value("bodies");
      p.sequence(b, m.full("bodies"), m.line("bodies"));
      p.check(b.size() == 2, m.full("bodies"), m.line("bodies"),
              "expected two bodies [A, B] (B may be ground), got " + std::to_string(b.size()));
      d.body_a = p.text(b[0], m.full("bodies"), m.line("bodies"));
      d.body_b = p.text(b[1], m.full("bodies"), m.line("bodies"));
      check_body(p, d.body_a, m.full("bodies"), m.line("bodies"), false);
      check_body(p, d.body_b, m.full("bodies"), m.line("bodies"), true);
      if (m.has("pairs")) {
        const YAML::Node& pairs = m.value("pairs");
        const std::string ppath = m.full("pairs");
        p.sequence(pairs, ppath, m.line("pairs"));
        p.check(pairs.size() > 0, ppath, m.line("pairs"), "expected at least one pair");
        for (const YAML::Node& pair : pairs) {
          const int at = line_of(pair) > 0 ? line_of(pair) : m.line("pairs");
          std::array<int, 2> ids{0, 0};
          if (d.body_b == "ground" && pair.IsScalar()) {
            ids[0] = p.integer(pair, ppath, at);
          } else {
            p.check(pair.IsSequence() && pair.size() == 2, ppath, at,
                    "expected a pair of node ids [node_a, node_b]" +
                        std::string(d.body_b == "ground" ? " or one node id" : "") + ", got " +
                        p.describe(pair));
            ids = {p.integer(pair[0], ppath, at), p.integer(pair[1], ppath, at)};
          }
          p.check(ids[0] > 0 && (ids[1] > 0 || (d.body_b == "ground" && ids[1] == 0)), ppath, at,
                  "node ids must be positive");
          p.check(d.body_a != d.body_b || ids[0] != ids[1], ppath, at,
                  "the pair joins node " + std::to_string(ids[0]) + " of body " + d.body_a +
                      " to itself");
          p.record(ppath + "[" + std::to_string(d.pairs.size()) + "]", at);
          d.pairs.push_back(ids);
        }
      } else {
        m.file("pairs_file", &d.pairs_file);
        std::vector<int> lines;
        d.pairs = with_key(m.full("pairs_file"), [&] {
          return read_pairs_csv(d.pairs_file, d.body_b == "ground", &lines);
        });
        for (size_t k = 0; k < lines.size(); ++k) {
          const std::string key = m.full("pairs") + "[" + std::to_string(k) + "]";
          p.out().locations[key] = {d.pairs_file, lines[k], key};
          if (d.body_a == d.body_b && d.pairs[k][0] == d.pairs[k][1]) {
            throw InvalidInput(p.out().locations[key], "the pair joins node " +
                                                           std::to_string(d.pairs[k][0]) +
                                                           " of body " + d.body_a + " to itself");
          }
        }
      }
    }

    // A cyclic sector's contact with its neighbour (docs/cyclic.md): the B ids are nodes of body
    // B (a body of the sector: checked by the model), the contact joins them in the next
    // (previous) sector.
    if (m.has("neighbour")) {
      m.forbid("between", "with 'neighbour' (list the pairs: 'bodies: [A, B]' and 'pairs' or "
                          "'pairs_file', B's ids being its nodes in this sector)");
      std::string side;
      m.choice("neighbour", &side, {"next", "previous"});
      d.neighbour = side == "next" ? 1 : -1;
      p.check(d.body_b != "ground", m.full("neighbour"), m.line("neighbour"),
              "a contact with the neighbour sector joins two bodies of the sector (B is in the "
              "next or previous sector), not the ground");
    }

    // A law registered both along a direction (1D) and in a frame (e.g. linear: one spring k
    // along direction, or springs kt, kt, kn in the frame normal/t1), decided by the keys given,
    // never keys of both. The parameter block is only looked at here (checked below, after the
    // frame, like every law's).
    const std::vector<const ContactLaw*> variants = find_contact_laws(d.law);
    d.uses_frame = variants.front()->uses_frame;
    if (variants.size() > 1) {
      // The parameter keys only one variant has.
      const ContactLaw& framed = contact_law(d.law, true);
      const ContactLaw& along = contact_law(d.law, false);
      std::vector<std::string> keys_3d, keys_1d;
      for (const std::string& key : framed.parameter_keys())
        if (!along.parameter(key)) keys_3d.push_back(key);
      for (const std::string& key : along.parameter_keys())
        if (!framed.parameter(key)) keys_1d.push_back(key);
      struct Given {
        std::string key, path;
        int line = 0;
      };
      const std::string block = m.has("per_pair")   ? "per_pair"
                                : m.has("total")    ? "total"
                                : m.has("per_area") ? "per_area"
                                                    : "";
      const auto find =
          [&](const std::vector<std::string>& frame_keys,
              const std::vector<std::string>& parameter_keys) -> std::optional<Given> {
        for (const std::string& key : frame_keys) {
          if (m.has(key)) return Given{key, m.full(key), m.line(key)};
        }
        if (block.empty() || !m.value(block).IsMap()) return std::nullopt;
        for (const std::string& key : parameter_keys) {
          for (auto it = m.value(block).begin(); it != m.value(block).end(); ++it) {
            if (it->first.IsScalar() && it->first.Scalar() == key) {
              const int at = line_of(it->first);
              return Given{key, m.full(block) + "." + key, at > 0 ? at : m.line(block)};
            }
          }
        }
        return std::nullopt;
      };
      const std::optional<Given> given_3d = find({"normal", "t1"}, keys_3d);
      const std::optional<Given> given_1d = find({"direction"}, keys_1d);
      d.uses_frame = given_3d.has_value();
      if (given_3d && given_1d) {
        const auto quoted = [](const std::vector<std::string>& keys) {
          std::string text;
          for (size_t i = 0; i < keys.size(); ++i) {
            text += (i == 0 ? "'" : "', '") + keys[i];
          }
          return text + "'";
        };
        p.fail(given_1d->path, given_1d->line,
               "law " + d.law + " is either " + (keys_1d.size() == 1 ? "one spring " : "") +
                   quoted(keys_1d) + " along 'direction' (1D) or " +
                   (keys_3d.size() > 1 ? "springs " : "") + quoted(keys_3d) +
                   " in the frame 'normal'/'t1' (3D), not both: '" + given_1d->key +
                   "' here, '" + given_3d->key + "' on line " + std::to_string(given_3d->line));
      }
    }

    // Frame.
    if (uses_frame(d)) {
      m.forbid("direction", "for law " + d.law + " (it uses 'normal' and 't1')");
      m.require("normal", "unit normal out of the first body into the second, e.g. [1, 0, 0]");
      d.normal = p.direction(m.value("normal"), m.full("normal"), m.line("normal"));
      if (m.has("t1")) {
        d.t1 = p.direction(m.value("t1"), m.full("t1"), m.line("t1"));
        const double c = d.t1[0] * d.normal[0] + d.t1[1] * d.normal[1] + d.t1[2] * d.normal[2];
        p.check(std::abs(c) < 1 - 1e-6, m.full("t1"), m.line("t1"),
                "must not be parallel to the normal");
      }
    } else {
      m.forbid("normal", "for law " + d.law + " (a 1D law acts along 'direction')");
      m.forbid("t1", "for law " + d.law + " (a 1D law acts along 'direction')");
      m.require("direction", "the axis the 1D element acts along: x | y | z or a vector");
      d.direction = p.direction(m.value("direction"), m.full("direction"), m.line("direction"));
    }

    // Parameters.
    m.exclusive("per_pair", "total");
    m.exclusive("per_pair", "per_area");
    m.exclusive("total", "per_area");
    if (!m.has("total") && !m.has("per_area")) m.require("per_pair", "or 'total' or 'per_area'");
    const std::string block = m.has("per_pair") ? "per_pair" : m.has("total") ? "total" : "per_area";
    d.parameters_given = block == "per_pair" ? ContactDefinition::Parameters::kPerPair
                         : block == "total"  ? ContactDefinition::Parameters::kTotal
                                             : ContactDefinition::Parameters::kPerArea;
    std::vector<std::string> known = law_name_keys(d.law);
    if (block == "total") known.push_back("split");
    MapView params(p, m.value(block), m.full(block), m.line(block), known, " for law " + d.law);
    const ContactLaw& law = law_of(d);
    for (const std::string& key : law.required_keys()) params.require(key);
    for (const std::string& key : parameter_keys(d)) {
      if (key == "preload" && params.has(key) && params.value(key).IsScalar() &&
          params.value(key).Scalar() == "computed") {
        std::string computing;
        for (const std::string& name : contact_law_names()) {
          for (const ContactLaw* l : find_contact_laws(name)) {
            if (l->can_compute_preload && computing.find(" " + name) == std::string::npos)
              computing += (computing.empty() ? " " : " and ") + name;
          }
        }
        p.check(law.can_compute_preload, params.full(key), params.line(key),
                "law " + d.law + " cannot compute its preload (laws" + computing + " only)");
        d.preload_computed = true;  // from the static contact problem under static_loads
        continue;
      }
      params.number(key, contact_parameter(d.parameters, key));
    }
    params.choice("split", &d.split);

    // Preload: uniform, per pair from a file, or a gap instead.
    if (m.has("preload_file")) {
      p.check(!params.has("preload"), params.full("preload"), params.line("preload"),
              "give either 'preload' or 'preload_file', not both");
      p.check(law.has_preload, m.full("preload_file"), m.line("preload_file"),
              "law " + d.law + " has no preload");
      m.file("preload_file", &d.preload_file);
      std::vector<int> lines;
      d.preloads = with_key(m.full("preload_file"),
                            [&] { return read_preloads_csv(d.preload_file, &lines); });
      for (size_t k = 0; k < lines.size(); ++k) {
        const std::string key = m.full("preloads") + "[" + std::to_string(k) + "]";
        p.out().locations[key] = {d.preload_file, lines[k], key};
      }
    }
    if (m.has("gap")) {
      p.check(law.has_gap, m.full("gap"), m.line("gap"), "law " + d.law + " has no gap");
      p.check(!params.has("preload") && !m.has("preload_file"), m.full("gap"), m.line("gap"),
              "give either a preload or a gap, not both");
      m.number("gap", &d.gap);
    }
    p.out().contacts.push_back(d);
  }
}

// `node` (an id or a list of ids, > 0) or `node_set` (a name or a list of names), exactly one,
// into *out; returns which key was given.
std::string parse_node_or_node_set(Parser& p, MapView& m, NodeSelection* out) {
  m.exclusive("node_set", "node");
  if (!m.has("node")) m.require("node_set", "or 'node'");
  if (m.has("node")) {
    const YAML::Node& v = m.value("node");
    if (v.IsSequence()) {
      p.check(v.size() > 0, m.full("node"), m.line("node"), "expected at least one node id");
      for (const YAML::Node& id : v) out->ids.push_back(p.integer(id, m.full("node"), m.line("node")));
    } else {
      out->ids.push_back(p.integer(v, m.full("node"), m.line("node")));
    }
    for (int id : out->ids) p.check(id > 0, m.full("node"), m.line("node"), "node ids are positive");
    return "node";
  }
  const YAML::Node& v = m.value("node_set");
  if (v.IsSequence()) {
    for (const YAML::Node& s : v) out->sets.push_back(p.text(s, m.full("node_set"), m.line("node_set")));
  } else {
    out->sets.push_back(p.text(v, m.full("node_set"), m.line("node_set")));
  }
  return "node_set";
}

void parse_excitation(Parser& p, const MapView& top) {
  if (!top.has("excitation")) return;
  const YAML::Node& list = top.value("excitation");
  p.sequence(list, "excitation", top.line("excitation"));
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = "excitation[" + std::to_string(i) + "]";
    MapView m(p, list[i], path, line_of(list[i]),
              case_keys_in("excitation[]"));
    p.record(path, m.line());
    ExcitationDefinition d;
    m.require("body");
    m.text("body", &d.body);
    check_body(p, d.body, m.full("body"), m.line("body"), false);
    const std::string where = parse_node_or_node_set(p, m, &d.nodes);
    if (where == "node_set") {
      check_selection_on_body(p, d.body, d.nodes, m.full("node_set"), m.line("node_set"));
    }
    m.integer("harmonic", &d.harmonic, 0);
    m.integer("engine_order", &d.engine_order, 0);  // a cyclic body's (checked by the model)

    m.exclusive("force", "direction");
    if (!m.has("force")) m.require("direction", "or 'force: [fx, fy, fz]'");
    if (m.has("direction")) {
      d.by_direction = true;
      d.direction = p.direction(m.value("direction"), m.full("direction"), m.line("direction"));
      m.exclusive("amplitude", "complex");
      if (!m.has("complex")) m.require("amplitude", "N, or 'complex: [re, im]'");
      std::complex<double> a;
      if (m.has("complex")) {
        m.forbid("phase_deg", "with 'complex' (the phase is in the complex amplitude)");
        const YAML::Node& c = m.value("complex");
        p.sequence(c, m.full("complex"), m.line("complex"));
        p.check(c.size() == 2, m.full("complex"), m.line("complex"), "expected [re, im]");
        a = {p.number(c[0], m.full("complex"), m.line("complex")),
             p.number(c[1], m.full("complex"), m.line("complex"))};
        d.amplitude = std::abs(a);
        d.phase_deg = std::arg(a) * 180.0 / kPi;
      } else {
        m.number("amplitude", &d.amplitude);
        m.number("phase_deg", &d.phase_deg);
        a = std::polar(1.0, d.phase_deg * kPi / 180.0) * d.amplitude;
      }
      for (size_t c = 0; c < 3; ++c) d.force[c] = a * d.direction[c];
    } else {
      d.by_direction = false;
      for (const char* key : {"amplitude", "phase_deg", "complex"})
        m.forbid(key, "with 'force' (give complex components as [re, im])");
      const YAML::Node& f = m.value("force");
      p.sequence(f, m.full("force"), m.line("force"));
      p.check(f.size() == 3, m.full("force"), m.line("force"),
              "expected [fx, fy, fz], each a number or [re, im]");
      for (size_t c = 0; c < 3; ++c) {
        if (f[c].IsSequence()) {
          p.check(f[c].size() == 2, m.full("force"), m.line("force"), "expected [re, im]");
          d.force[c] = {p.number(f[c][0], m.full("force"), m.line("force")),
                        p.number(f[c][1], m.full("force"), m.line("force"))};
        } else {
          d.force[c] = p.number(f[c], m.full("force"), m.line("force"));
        }
      }
    }
    p.out().excitation.push_back(d);
  }
}

void parse_static_loads(Parser& p, const MapView& top) {
  if (!top.has("static_loads")) return;
  const YAML::Node& list = top.value("static_loads");
  p.sequence(list, "static_loads", top.line("static_loads"));
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = "static_loads[" + std::to_string(i) + "]";
    MapView m(p, list[i], path, line_of(list[i]),
              case_keys_in("static_loads[]"));
    p.record(path, m.line());
    StaticLoadDefinition d;
    m.require("body");
    m.text("body", &d.body);
    check_body(p, d.body, m.full("body"), m.line("body"), false);
    const BodyDefinition& body = p.out().bodies.at(d.body);
    p.check(body.source == BodyDefinition::Source::kMesh, m.full("body"), m.line("body"),
            "body '" + d.body +
                "' is given by reduced matrices: static loads act on bodies given by a mesh "
                "(their full model is recovered with them)");
    parse_node_or_node_set(p, m, &d.nodes);
    const int kinds = int{m.has("force")} + int{m.has("total_force")} + int{m.has("pressure")};
    p.check(kinds == 1, path, m.line(),
            kinds == 0 ? "expected one of 'force: [fx, fy, fz]' (N on each node), "
                         "'total_force: [fx, fy, fz]' (N, split by area) or 'pressure' (Pa)"
                       : "give only one of 'force', 'total_force' and 'pressure'");
    if (m.has("pressure")) {
      d.kind = StaticLoadDefinition::Kind::kPressure;
      m.number("pressure", &d.pressure);
      p.check(d.pressure != 0.0, m.full("pressure"), m.line("pressure"), "must not be 0");
    } else {
      const std::string key = m.has("force") ? "force" : "total_force";
      d.kind = key == "force" ? StaticLoadDefinition::Kind::kForce
                              : StaticLoadDefinition::Kind::kTotalForce;
      const YAML::Node& f = m.value(key);
      p.sequence(f, m.full(key), m.line(key));
      p.check(f.size() == 3, m.full(key), m.line(key), "expected [fx, fy, fz] (N)");
      for (size_t c = 0; c < 3; ++c)
        d.force[c] = p.checked_number(f[c], m.full(key), key, m.line(key));
    }
    p.out().static_loads.push_back(d);
  }
}

// rotation: {speed_rpm, axis: {point, direction}, stress_stiffening, spin_softening,
// campbell: {speeds_rpm, engine_orders}}.
void parse_rotation(Parser& p, const MapView& top) {
  if (!top.has("rotation")) return;
  MapView m(p, top.value("rotation"), "rotation", top.line("rotation"), case_keys_in("rotation"));
  RotationDefinition d;
  m.require("speed_rpm", "the speed in revolutions per minute");
  m.number("speed_rpm", &d.speed_rpm);
  const CaseDefinition& c = p.out();
  const auto cyclic = std::find_if(c.bodies.begin(), c.bodies.end(),
                                   [](const auto& b) { return b.second.cyclic.has_value(); });
  if (m.has("axis")) {
    MapView axis(p, m.value("axis"), m.full("axis"), m.line("axis"),
                 case_keys_in("rotation.axis"));
    axis.require("point");
    axis.require("direction");
    d.axis_given = true;
    d.axis_point = p.vector3(axis.value("point"), axis.full("point"), axis.line("point"));
    d.axis_direction =
        p.direction(axis.value("direction"), axis.full("direction"), axis.line("direction"));
  } else {
    p.check(cyclic != c.bodies.end(), m.full("axis"), m.line(),
            "required key missing (the axis of rotation: {point, direction}; a case with a "
            "cyclic body spins about its cyclic axis by default)");
  }
  m.boolean("stress_stiffening", &d.stress_stiffening);
  m.boolean("spin_softening", &d.spin_softening);
  if (m.has("campbell")) {
    MapView cm(p, m.value("campbell"), m.full("campbell"), m.line("campbell"),
               case_keys_in("rotation.campbell"));
    cm.require("speeds_rpm", "the speeds of the Campbell diagram");
    const YAML::Node& v = cm.value("speeds_rpm");
    p.sequence(v, cm.full("speeds_rpm"), cm.line("speeds_rpm"));
    p.check(v.size() >= 2, cm.full("speeds_rpm"), cm.line("speeds_rpm"),
            "expected at least two speeds");
    for (const YAML::Node& x : v) {
      const double rpm = p.checked_number(x, cm.full("speeds_rpm"), "speed_rpm",
                                          Parser::here(x, cm.line("speeds_rpm")));
      p.check(d.campbell_speeds_rpm.empty() || rpm > d.campbell_speeds_rpm.back(),
              cm.full("speeds_rpm"), Parser::here(x, cm.line("speeds_rpm")),
              "the speeds must increase, got " + format_number(rpm) + " after " +
                  (d.campbell_speeds_rpm.empty() ? "" : format_number(d.campbell_speeds_rpm.back())));
      d.campbell_speeds_rpm.push_back(rpm);
    }
    if (cm.has("engine_orders")) {
      const YAML::Node& eo = cm.value("engine_orders");
      p.sequence(eo, cm.full("engine_orders"), cm.line("engine_orders"));
      for (const YAML::Node& x : eo) {
        const int line = Parser::here(x, cm.line("engine_orders"));
        const int k = p.integer(x, cm.full("engine_orders"), line);
        p.check(k >= 1 && k <= kMaxCyclicSectors, cm.full("engine_orders"), line,
                "an engine order is an integer in [1, " + std::to_string(kMaxCyclicSectors) +
                    "], got " + std::to_string(k));
        d.engine_orders.push_back(k);
      }
    }
  }
  // Every body spins: a body given by matrices has no coordinates to put its centrifugal load on.
  for (const auto& [name, b] : c.bodies) {
    p.check(b.source == BodyDefinition::Source::kMesh, "rotation", m.line(),
            "body '" + name +
                "' is given by reduced matrices: it has no node coordinates for its centrifugal "
                "load (rotation acts on bodies given by a mesh)");
  }
  p.out().rotation = d;
}

// `mode` and `amplitude` of a nonlinear mode, in `m`: analysis itself (method nonlinear_mode) or
// the analysis.nonlinear_mode block of a forced response (its prediction from the mode).
void parse_mode_and_amplitude(Parser& p, const MapView& m, AnalysisDefinition& a) {
  m.require("mode", "the mode of the stuck assembly to follow");
  m.integer("mode", &a.mode, 1);
  m.require("amplitude", "{start, stop}: the modal amplitudes");
  MapView am(p, m.value("amplitude"), m.full("amplitude"), m.line("amplitude"),
             case_keys_in("analysis.amplitude"));
  AmplitudeDefinition& r = a.amplitude;
  am.require("start");
  am.require("stop");
  r.start = p.number(am.value("start"), am.full("start"), am.line("start"));
  p.check(r.start > 0, am.full("start"), am.line("start"),
          "must be > 0 (a modal amplitude), got " + format_number(r.start));
  r.stop = p.number(am.value("stop"), am.full("stop"), am.line("stop"));
  p.check(r.stop > r.start, am.full("stop"), am.line("stop"),
          "the amplitude range is empty or inverted: stop = " + format_number(r.stop) +
              " must be > start = " + format_number(r.start));
  am.integer("points", &r.points, 2, kMaxFrequencyPoints, "amplitudes, each solved and written");
}

void parse_analysis(Parser& p, const MapView& top) {
  top.require("analysis");
  MapView m(p, top.value("analysis"), "analysis", top.line("analysis"),
            case_keys_in("analysis"));
  AnalysisDefinition& a = p.out().analysis;
  m.choice("method", &a.method);
  const bool nonlinear_mode = a.method == SweepMethod::kNonlinearMode;
  if (nonlinear_mode) {
    m.forbid("frequency", "with method nonlinear_mode (the frequency is an unknown of the mode)");
    m.forbid("nonlinear_mode",
             "with method nonlinear_mode (its mode and amplitude are keys of analysis itself)");
    parse_mode_and_amplitude(p, m, a);
  } else {
    m.forbid("mode", "without method nonlinear_mode (a forced response predicted from a "
                     "nonlinear mode takes it in analysis.nonlinear_mode)");
    m.forbid("amplitude", "without method nonlinear_mode (a forced response predicted from a "
                          "nonlinear mode takes it in analysis.nonlinear_mode)");
    if (m.has("nonlinear_mode")) {
      MapView nm(p, m.value("nonlinear_mode"), "analysis.nonlinear_mode",
                 m.line("nonlinear_mode"), case_keys_in("analysis.nonlinear_mode"));
      parse_mode_and_amplitude(p, nm, a);
      a.predict_from_mode = true;
    }
  }
  if (!nonlinear_mode) {
  m.require("frequency");
  MapView f(p, m.value("frequency"), "analysis.frequency", m.line("frequency"),
            case_keys_in("analysis.frequency"));
  FrequencyDefinition& fr = a.frequency;
  auto positive = [&](const char* key, double* dst) {
    if (!f.has(key)) return;
    *dst = p.number(f.value(key), f.full(key), f.line(key));
    p.check(*dst > 0, f.full(key), f.line(key), "must be > 0, got " + format_number(*dst));
  };
  if (f.has("around_mode")) {
    fr.kind = FrequencyDefinition::Kind::kAroundMode;
    for (const char* key : {"start_hz", "stop_hz"})
      f.forbid(key, "with 'around_mode' (the window is around_mode ± half_width_hz)");
    f.require("half_width_hz");
    f.integer("around_mode", &fr.around_mode, 1);
    positive("half_width_hz", &fr.half_width_hz);
  } else {
    fr.kind = FrequencyDefinition::Kind::kRange;
    f.forbid("half_width_hz", "without 'around_mode'");
    f.require("start_hz", "or 'around_mode'");
    f.require("stop_hz");
    positive("start_hz", &fr.start_hz);
    fr.stop_hz = p.number(f.value("stop_hz"), f.full("stop_hz"), f.line("stop_hz"));
    p.check(fr.stop_hz > fr.start_hz, f.full("stop_hz"), f.line("stop_hz"),
            "the frequency range is empty or inverted: stop_hz = " + format_number(fr.stop_hz) +
                " must be > start_hz = " + format_number(fr.start_hz));
  }
  std::string sweep = "up";
  f.choice("sweep", &sweep, {"up", "down"});
  fr.downward = sweep == "down";
  f.require("step_hz");
  fr.step_hz = p.number(f.value("step_hz"), f.full("step_hz"), f.line("step_hz"));
  p.check(fr.step_hz > 0, f.full("step_hz"), f.line("step_hz"),
          "must be > 0, got " + format_number(fr.step_hz));
  if (a.method != SweepMethod::kContinuation) {
    for (const char* key : {"min_step_hz", "max_step_hz"})
      f.forbid(key, "with method stepped (they bound the continuation step)");
  }
  positive("min_step_hz", &fr.min_step_hz);
  positive("max_step_hz", &fr.max_step_hz);
  if (fr.min_step_hz > 0)
    p.check(fr.min_step_hz <= fr.step_hz, f.full("min_step_hz"), f.line("min_step_hz"),
            "must be <= step_hz = " + format_number(fr.step_hz));
  if (fr.max_step_hz > 0)
    p.check(fr.max_step_hz >= fr.step_hz, f.full("max_step_hz"), f.line("max_step_hz"),
            "must be >= step_hz = " + format_number(fr.step_hz));
  if (a.method != SweepMethod::kContinuation) {
    // The points of the stepped sweep, window / step_hz + 1 (the window is known here for both
    // kinds of frequency definition), bounded as max_points is.
    const double window = fr.kind == FrequencyDefinition::Kind::kAroundMode
                              ? 2.0 * fr.half_width_hz
                              : fr.stop_hz - fr.start_hz;
    const double points = std::floor(window / fr.step_hz) + 1.0;
    p.check(points <= kMaxFrequencyPoints, f.full("step_hz"), f.line("step_hz"),
            "the stepped sweep would have " + format_number(points) + " points (window " +
                format_number(window) + " Hz / step_hz + 1): at most " +
                std::to_string(kMaxFrequencyPoints) + " are accepted");
  }
  }

  if (m.has("harmonics")) {
    const YAML::Node& h = m.value("harmonics");
    const std::string path = m.full("harmonics");
    a.harmonics.clear();
    if (h.IsSequence()) {
      p.check(h.size() > 0, path, m.line("harmonics"), "expected at least one harmonic");
      for (const YAML::Node& k : h) {
        const int v = p.integer(k, path, m.line("harmonics"));
        p.check(v >= 1, path, m.line("harmonics"),
                "harmonics in a list must be >= 1 (harmonic 0 is always kept), got " +
                    std::to_string(v));
        p.check(a.harmonics.empty() || v > a.harmonics.back(), path, m.line("harmonics"),
                "the list must be strictly increasing");
        p.check(v <= kMaxHarmonic, path, m.line("harmonics"),
                "harmonic " + std::to_string(v) + " is above the largest supported, " +
                    std::to_string(kMaxHarmonic));
        a.harmonics.push_back(v);
      }
    } else {
      const int H = p.integer(h, path, m.line("harmonics"));
      p.check(H >= 1, path, m.line("harmonics"), "must be >= 1, got " + std::to_string(H));
      // Checked before the list 1..H is built (harmonics: 2147483647 would take 8 GB).
      p.check(H <= kMaxHarmonic, path, m.line("harmonics"),
              "must be <= " + std::to_string(kMaxHarmonic) + ", got " + std::to_string(H));
      for (int k = 1; k <= H; ++k) a.harmonics.push_back(k);
    }
  }
  m.integer("time_samples", &a.time_samples, 1);
  const int needed = 2 * (2 * a.max_harmonic() + 1);
  p.check(a.time_samples >= needed, m.full("time_samples"), m.line("time_samples"),
          "must be >= 2(2H+1) = " + std::to_string(needed) + " for highest harmonic H = " +
              std::to_string(a.max_harmonic()) + ", got " + std::to_string(a.time_samples));
  // H <= kMaxHarmonic, so 64(2H+1) fits in an int.
  const int most =
      std::min(kMaxTimeSamples,
               std::max(kTimeSamplesFloor, kTimeSamplesPerHarmonic * (2 * a.max_harmonic() + 1)));
  p.check(a.time_samples <= most, m.full("time_samples"), m.line("time_samples"),
          "must be <= min(" + std::to_string(kMaxTimeSamples) + ", max(" +
              std::to_string(kTimeSamplesFloor) + ", " + std::to_string(kTimeSamplesPerHarmonic) +
              "(2H+1))) = " + std::to_string(most) + " for highest harmonic H = " +
              std::to_string(a.max_harmonic()) + ", got " + std::to_string(a.time_samples));
  a.aft_given = m.has("aft");
  m.choice("aft", &a.aft);
  m.choice("static", &a.static_coupling);
  m.integer("static_increments", &a.static_increments, 1, kMaxStaticIncrements,
            "load steps of the static problem, each a Newton solve");
  m.boolean("stability", &a.stability);
  if (m.has("tolerance")) {
    a.tolerance = p.number(m.value("tolerance"), m.full("tolerance"), m.line("tolerance"));
    p.check(a.tolerance > 0, m.full("tolerance"), m.line("tolerance"),
            "must be > 0, got " + format_number(a.tolerance));
  }
  m.integer("max_iterations", &a.max_iterations, 1);
  const std::string with_method = std::string("with method ") + case_name(a.method);
  if (a.method != SweepMethod::kContinuation) m.forbid("max_points", with_method);
  m.integer("max_points", &a.max_points, 2, kMaxFrequencyPoints,
            "points of one continuation, each solved and written");
  if (nonlinear_mode) {
    m.forbid("initial_guess", with_method + " (it starts from the linear mode)");
    m.forbid("stability", with_method + " (Hill's method is for forced responses)");
  }
  m.choice("initial_guess", &a.initial_guess);
  if (a.method != SweepMethod::kStepped) m.forbid("predictor", with_method);
  m.choice("predictor", &a.predictor);
}

void parse_recovery(Parser& p, const MapView& top) {
  if (!top.has("recovery")) return;
  MapView m(p, top.value("recovery"), "recovery", top.line("recovery"),
            case_keys_in("recovery"));
  RecoveryDefinition& r = p.out().recovery;
  if (m.has("points")) {
    const YAML::Node& v = m.value("points");
    if (v.IsSequence()) {
      r.points = RecoveryPoints::kList;
      p.check(v.size() > 0, m.full("points"), m.line("points"), "expected at least one frequency");
      for (const YAML::Node& hz : v) {
        const double f = p.number(hz, m.full("points"), m.line("points"));
        p.check(f > 0, m.full("points"), m.line("points"),
                "frequencies must be > 0 Hz, got " + format_number(f));
        r.frequencies_hz.push_back(f);
      }
    } else {
      const std::string name =
          p.choice(v, m.full("points"), m.line("points"), {"peak", "all", "none"});
      for (const auto& [n, value] : choices_of(RecoveryPoints{}))
        if (name == n) r.points = value;
    }
  }
  m.choice("method", &r.method);
  if (r.method != RecoveryMethod::kModal) m.forbid("modes", "unless method is modal");
  m.integer("modes", &r.modes, 1, kMaxRecoveryModes, "full-model modes of the modal recovery");
  if (m.has("fields")) {
    const YAML::Node& v = m.value("fields");
    p.sequence(v, m.full("fields"), m.line("fields"));
    r.fields.clear();
    for (const YAML::Node& f : v) {
      const std::string s =
          p.choice(f, m.full("fields"), m.line("fields"), {"displacement", "stress"});
      const RecoveryField field =
          s == "stress" ? RecoveryField::kStress : RecoveryField::kDisplacement;
      p.check(std::find(r.fields.begin(), r.fields.end(), field) == r.fields.end(),
              m.full("fields"), m.line("fields"), "'" + s + "' listed twice");
      r.fields.push_back(field);
    }
  }
  if (m.has("nodes")) {
    const YAML::Node& v = m.value("nodes");
    p.sequence(v, m.full("nodes"), m.line("nodes"));
    for (const YAML::Node& n : v) {
      const int id = p.integer(n, m.full("nodes"), m.line("nodes"));
      p.check(id > 0, m.full("nodes"), m.line("nodes"), "node ids are positive");
      p.record(m.full("nodes") + "[" + std::to_string(r.nodes.size()) + "]",
               Parser::here(n, m.line("nodes")));
      r.nodes.push_back(id);
    }
  }
  m.boolean("annulus", &r.annulus);
}

void parse_output(Parser& p, const MapView& top) {
  OutputDefinition& o = p.out().output;
  o.directory = p.resolve(o.directory);
  if (!top.has("output")) return;
  MapView m(
      p, top.value("output"), "output", top.line("output"),
      case_keys_in("output"));
  if (m.has("directory")) {
    m.text("directory", &o.directory);
    p.check(!o.directory.empty(), m.full("directory"), m.line("directory"), "empty directory");
    o.directory = p.resolve(o.directory);
  }
  m.boolean("vtu", &o.vtu);
  m.boolean("plots", &o.plots);
  m.boolean("log_amplitude", &o.log_amplitude);
  m.boolean("apdl_macro", &o.apdl_macro);
  m.boolean("calculix_deck", &o.calculix_deck);
  m.boolean("quiet", &o.quiet);
  if (m.has("histories")) {
    MapView h(
        p, m.value("histories"), "output.histories", m.line("histories"),
        [&] {
          std::vector<std::string> names;
          for (const ContactDefinition& c : p.out().contacts) names.push_back(c.name);
          return names;
        }(),
        " (histories are keyed by contact name)");
    for (const std::string& name : h.keys()) {
      const YAML::Node& v = h.value(name);
      std::vector<int>& dst = o.histories[name];
      if (v.IsSequence()) {
        for (const YAML::Node& k : v) dst.push_back(p.integer(k, h.full(name), h.line(name)));
      } else {
        dst.push_back(p.integer(v, h.full(name), h.line(name)));
      }
      for (int k : dst)
        p.check(k >= 0, h.full(name), h.line(name), "pair indices are 0-based, >= 0");
    }
  }
  if (m.has("frf")) {
    const YAML::Node& v = m.value("frf");
    p.sequence(v, m.full("frf"), m.line("frf"));
    for (size_t i = 0; i < v.size(); ++i) {
      MapView d(p, v[i], "output.frf[" + std::to_string(i) + "]",
                line_of(v[i]) > 0 ? line_of(v[i]) : m.line("frf"), case_keys_in("output.frf[]"));
      p.record(d.path(), d.line());
      ResponseDofDefinition r;
      for (const char* key : {"body", "node", "direction"}) d.require(key);
      d.text("body", &r.body);
      check_body(p, r.body, d.full("body"), d.line("body"), false);
      d.integer("node", &r.node, 1);
      std::string dir;
      d.choice("direction", &dir, {"x", "y", "z"});
      r.direction = dir[0] - 'x';
      o.frf.push_back(r);
    }
  }
}

// Checks across sections that need everything parsed.
void cross_check(Parser& p) {
  CaseDefinition& c = p.out();
  for (size_t i = 0; i < c.excitation.size(); ++i) {
    const ExcitationDefinition& e = c.excitation[i];
    const std::string path = "excitation[" + std::to_string(i) + "].harmonic";
    const auto& hs = c.analysis.harmonics;
    p.check(e.harmonic == 0 || std::find(hs.begin(), hs.end(), e.harmonic) != hs.end(), path,
            c.where(path).line,
            "harmonic " + std::to_string(e.harmonic) +
                " is not solved: analysis.harmonics has 1.." +
                std::to_string(c.analysis.max_harmonic()) + " (use 0 for a static force)");
  }
  for (const ContactDefinition& d : c.contacts) {
    if (!d.preload_computed) continue;
    const std::string path = "contacts." + d.name + "." + parameter_block(d) + ".preload";
    p.check(!c.static_loads.empty() || c.rotation.has_value(), path, c.where(path).line,
            "a computed preload needs 'static_loads' or 'rotation' (the loads that press the "
            "contact); none are given");
  }
  // A rotating case's hand-offs would need the centrifugal load and the spinning stiffness in
  // the other program's deck; they write the contact and excitation loads only.
  for (const auto& [key, on] : {std::pair<std::string, bool>{"output.apdl_macro",
                                                             c.output.apdl_macro},
                                {"output.calculix_deck", c.output.calculix_deck}}) {
    if (!c.rotation || !on) continue;
    p.check(false, key, c.where(key).line,
            "a rotating case cannot be handed to another program yet: the macro or deck would "
            "carry the contact and excitation loads without the centrifugal load and the "
            "spinning body's stiffness (stress stiffening, spin softening); stickslip's own "
            "recovery includes both");
  }
  if (!c.recovery.nodes.empty()) {
    const bool any_mesh_body = std::any_of(c.bodies.begin(), c.bodies.end(), [](const auto& b) {
      return b.second.source == BodyDefinition::Source::kMesh;
    });
    p.check(any_mesh_body, "recovery.nodes", c.where("recovery.nodes").line,
            "no body is given by a mesh: there is nothing to recover at these nodes");
  }
}

void parse_study(Parser& p, const MapView& top) {
  if (!top.has("study")) return;
  MapView m(p, top.value("study"), "study", top.line("study"), case_keys_in("study"));
  StudyDefinition& s = p.out().study;
  m.require("parameter", "the dotted key to vary, e.g. contacts.joint.per_pair.preload");
  m.require("values");
  m.text("parameter", &s.parameter);
  const YAML::Node& v = m.value("values");
  p.sequence(v, m.full("values"), m.line("values"));
  p.check(v.size() > 0, m.full("values"), m.line("values"), "expected at least one value");
  std::vector<int> lines;
  for (const YAML::Node& x : v) {
    lines.push_back(Parser::here(x, m.line("values")));
    s.values.push_back(p.number(x, m.full("values"), lines.back()));
  }
  // The path must name a numeric key; each value must be accepted by that key.
  with_parameter(p.out(), s.parameter, s.values.front(),
                 {p.file(), m.line("parameter"), "study.parameter"});
  for (size_t i = 0; i < s.values.size(); ++i)
    with_parameter(p.out(), s.parameter, s.values[i], {p.file(), lines[i], "study.values"});
  // Each value has a folder of its own: a value twice, or two values with the same folder name,
  // would write the second analysis over the first.
  std::map<double, size_t> seen;  // -0 and 0 are the same key
  std::map<std::string, size_t> folders;
  for (size_t i = 0; i < s.values.size(); ++i) {
    const auto [same, fresh] = seen.emplace(s.values[i], i);
    p.check(fresh, m.full("values"), lines[i],
            fmt::format("the value {} is listed twice (first on line {})",
                        format_number(s.values[i]), lines[same->second]));
    const std::string folder = study_folder_name(s.parameter, s.values[i]);
    const auto [it, inserted] = folders.emplace(folder, i);
    if (inserted) continue;
    const double first = s.values[it->second];
    p.fail(m.full("values"), lines[i],
           fmt::format("values {} and {} (line {}) would both write to the folder {}/ "
                       "(folder names keep 6 significant digits): make them differ within 6 "
                       "digits",
                       format_number(s.values[i]), format_number(first), lines[it->second],
                       folder));
  }
}

std::string case_file_size_message(std::uintmax_t bytes) {
  return fmt::format("the case file has {} bytes; a case file may have at most {} bytes ({} MiB): "
                     "long lists of pairs or preloads belong in pairs_file and preload_file",
                     bytes, kMaxCaseFileBytes, kMaxCaseFileBytes >> 20);
}

// yaml-cpp (0.7) ends a quoted scalar without its closing quote at the end of the file instead of
// reporting it: `title: "abc` swallowed the rest of the file and the error was a missing key at
// line 1. So every quoted scalar (tag "!") of the tree is checked against the text: from its
// opening quote, the closing one must come before the end (\" escapes in double quotes, '' in
// single quotes).
void check_quotes(const YAML::Node& node, const std::string& text,
                  const std::vector<size_t>& line_starts, const std::string& file) {
  if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      check_quotes(it->first, text, line_starts, file);
      check_quotes(it->second, text, line_starts, file);
    }
    return;
  }
  if (node.IsSequence()) {
    for (const YAML::Node& item : node) check_quotes(item, text, line_starts, file);
    return;
  }
  if (!node.IsScalar() || node.Tag() != "!") return;
  const YAML::Mark mark = node.Mark();
  if (mark.is_null() || mark.line < 0 || static_cast<size_t>(mark.line) >= line_starts.size())
    return;
  size_t i = line_starts[static_cast<size_t>(mark.line)] + static_cast<size_t>(mark.column);
  if (i >= text.size() || (text[i] != '"' && text[i] != '\'')) return;  // a block scalar
  const char quote = text[i];
  for (++i; i < text.size(); ++i) {
    if (quote == '"' && text[i] == '\\') {
      ++i;
    } else if (text[i] == quote) {
      if (quote == '\'' && i + 1 < text.size() && text[i + 1] == '\'') {
        ++i;
      } else {
        return;
      }
    }
  }
  throw InvalidInput(SourceLocation{file, mark.line + 1, ""},
                     fmt::format("the string quoted with {} at column {} is not closed: it runs "
                                 "to the end of the file",
                                 quote, mark.column + 1));
}

// A case file is UTF-8 text (an optional UTF-8 byte-order mark is allowed). yaml-cpp would take
// other bytes into names and titles unchecked, and they would reach file names, plots and logs.
void check_encoding(const std::string& text, const std::string& file) {
  const auto starts = [&](std::string_view bom) {
    return std::string_view(text).substr(0, bom.size()) == bom;
  };
  if (starts(std::string_view("\0\0\xFE\xFF", 4)) || starts(std::string_view("\xFF\xFE", 2)) ||
      starts(std::string_view("\xFE\xFF", 2))) {
    throw InvalidInput(SourceLocation{file, 1, ""},
                       "the case file is UTF-16 or UTF-32 (it starts with that byte-order mark): "
                       "save it as UTF-8");
  }
  const size_t bad = first_invalid_utf8(text);
  if (bad == std::string::npos) return;
  const size_t newline = bad == 0 ? std::string::npos : text.rfind('\n', bad - 1);
  const size_t line_start = newline == std::string::npos ? 0 : newline + 1;
  const int line = 1 + static_cast<int>(std::count(
                           text.begin(), text.begin() + static_cast<std::ptrdiff_t>(bad), '\n'));
  const size_t column = bad - line_start + 1;
  throw InvalidInput(SourceLocation{file, line, ""},
                     fmt::format("byte {} (column {}) is not UTF-8 text: a case file must be "
                                 "UTF-8 (save it as UTF-8 in the editor)",
                                 printable(std::string_view(text).substr(bad, 1)), column));
}

CaseDefinition parse_case_unguarded(const std::string& yaml_text,
                                    const std::string& name_for_messages,
                                    const std::string& base_dir) {
  CaseDefinition out;
  out.file = name_for_messages;
  out.base_dir = base_dir;
  check_encoding(yaml_text, name_for_messages);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InvalidInput(SourceLocation{name_for_messages, e.mark.line + 1, ""},
                       "YAML syntax error: " + e.msg);
  }
  std::vector<size_t> line_starts{0};
  for (size_t i = 0; i < yaml_text.size(); ++i) {
    if (yaml_text[i] == '\n') line_starts.push_back(i + 1);
  }
  check_quotes(root, yaml_text, line_starts, name_for_messages);
  Parser p(name_for_messages, base_dir, out);
  if (!root.IsDefined() || root.IsNull())
    throw InvalidInput(SourceLocation{name_for_messages, 0, ""}, "the case file is empty");
  MapView top(p, root, "", 1,
              case_keys_in(""));
  top.require("stickslip", "the format version: stickslip: 1");
  top.integer("stickslip", &out.version, 1);
  p.check(out.version == kCaseFormatVersion, "stickslip", top.line("stickslip"),
          "unsupported format version " + std::to_string(out.version) + " (this program reads " +
              std::to_string(kCaseFormatVersion) + ")");
  top.text("title", &out.title);
  parse_materials(p, top);
  parse_meshes(p, top);
  top.require("bodies");
  parse_bodies(p, top);
  p.check(!out.bodies.empty(), "bodies", top.line("bodies"), "expected at least one body");
  parse_contacts(p, top);
  parse_excitation(p, top);
  parse_static_loads(p, top);
  parse_rotation(p, top);
  if (top.has("damping")) {
    MapView d(p, top.value("damping"), "damping", top.line("damping"), case_keys_in("damping"));
    d.number("alpha", &out.damping.alpha);
    d.number("beta", &out.damping.beta);
  }
  parse_analysis(p, top);
  parse_recovery(p, top);
  parse_output(p, top);
  cross_check(p);
  parse_study(p, top);
  return out;
}

}  // namespace

CaseDefinition parse_case(const std::string& yaml_text, const std::string& name_for_messages,
                          const std::string& base_dir) {
  if (yaml_text.size() > kMaxCaseFileBytes) {
    throw InvalidInput(SourceLocation{name_for_messages, 0, ""},
                       case_file_size_message(yaml_text.size()));
  }
  try {
    return parse_case_unguarded(yaml_text, name_for_messages, base_dir);
  } catch (const YAML::Exception& e) {
    // Anything yaml-cpp throws besides syntax errors (e.g. its nesting-depth guard).
    throw InvalidInput(
        SourceLocation{name_for_messages, e.mark.is_null() ? 0 : e.mark.line + 1, ""},
        "YAML error: " + e.msg);
  }
}

std::string study_folder_name(const std::string& parameter, double value) {
  const std::string name = parameter.substr(parameter.rfind('.') + 1);
  return fmt::format("{}_{:g}", name, value);
}

CaseDefinition read_case_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput(SourceLocation{path, 0, ""}, "cannot open the case file");
  // The size first: the YAML tree takes several times the file's bytes (a 1 GB list took 5.8 GB).
  std::error_code ec;
  const std::uintmax_t bytes = fs::file_size(path, ec);
  if (!ec && bytes > kMaxCaseFileBytes) {
    throw InvalidInput(SourceLocation{path, 0, ""}, case_file_size_message(bytes));
  }
  std::stringstream text;
  text << in.rdbuf();
  std::string base = fs::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parse_case(text.str(), path, base);
}

std::vector<std::array<int, 2>> read_pairs_csv(const std::string& path, bool allow_ground,
                                               std::vector<int>* lines) {
  std::vector<std::array<int, 2>> pairs;
  std::set<std::array<int, 2>> seen;
  if (lines) lines->clear();
  for (const CsvRecord& r : read_csv_records(path)) {
    const size_t n = r.fields.size();
    if (n != 2 && !(allow_ground && n == 1))
      throw InvalidInput(SourceLocation{path, r.line, ""},
                         "expected node_a,node_b" +
                             std::string(allow_ground ? " (or node_a alone for the ground)" : "") +
                             ", got " + std::to_string(n) + " fields");
    const std::array<int, 2> pair{csv_id(path, r, 0, false),
                                  n == 2 ? csv_id(path, r, 1, allow_ground) : 0};
    if (!seen.insert(pair).second)
      throw InvalidInput(
          SourceLocation{path, r.line, ""},
          "pair " + std::to_string(pair[0]) + "," + std::to_string(pair[1]) + " listed twice");
    pairs.push_back(pair);
    if (lines) lines->push_back(r.line);
  }
  return pairs;
}

std::vector<std::pair<int, double>> read_preloads_csv(const std::string& path,
                                                      std::vector<int>* lines) {
  std::vector<std::pair<int, double>> preloads;
  std::set<int> seen;
  if (lines) lines->clear();
  for (const CsvRecord& r : read_csv_records(path)) {
    if (r.fields.size() != 2)
      throw InvalidInput(
          SourceLocation{path, r.line, ""},
          "expected node_a,preload, got " + std::to_string(r.fields.size()) + " fields");
    const int node = csv_id(path, r, 0, false);
    double preload = 0;
    if (!parse_double(r.fields[1], &preload) || !std::isfinite(preload) || preload < 0)
      throw InvalidInput(
          SourceLocation{path, r.line, ""},
          "field 2: the preload must be a number >= 0 (N), got '" + r.fields[1] + "'");
    if (const std::string range = magnitude_rule_violation(preload); !range.empty())
      throw InvalidInput(SourceLocation{path, r.line, ""}, "field 2: " + range);
    if (!seen.insert(node).second)
      throw InvalidInput(SourceLocation{path, r.line, ""},
                         "node " + std::to_string(node) + " listed twice");
    preloads.emplace_back(node, preload);
    if (lines) lines->push_back(r.line);
  }
  return preloads;
}

CaseDefinition with_parameter(const CaseDefinition& definition, const std::string& path,
                              double value, const SourceLocation& where) {
  CaseDefinition c = definition;
  auto fail = [&](const std::string& rule) {
    throw InvalidInput(where, "'" + path + "' = " + format_number(value) + ": " + rule);
  };
  std::vector<std::string> parts;
  {
    std::string part;
    std::stringstream ss(path);
    while (std::getline(ss, part, '.')) parts.push_back(part);
  }
  const std::string key = parts.empty() ? "" : parts.back();
  double* field = nullptr;
  double magnitude = 0.0;  // static_loads[i].force / total_force: the new magnitude (N)
  std::function<void()> after;
  const std::string supported = "supported: " + join(study_parameter_paths(), ", ");
  if (parts.size() == 3 && parts[0] == "materials") {
    auto it = c.materials.find(parts[1]);
    if (it == c.materials.end()) fail("no material '" + parts[1] + "'");
    if (key == "youngs_modulus") field = &it->second.youngs_modulus;
    if (key == "poisson_ratio") field = &it->second.poisson_ratio;
    if (key == "density") field = &it->second.density;
  } else if ((parts.size() == 3 || parts.size() == 4) && parts[0] == "contacts") {
    auto it = std::find_if(c.contacts.begin(), c.contacts.end(),
                           [&](const ContactDefinition& d) { return d.name == parts[1]; });
    if (it == c.contacts.end()) fail("no contact '" + parts[1] + "'");
    if (parts.size() == 3 && key == "gap") {
      if (!law_of(*it).has_gap) fail("law " + it->law + " has no gap");
      const std::string base = "contacts." + it->name + ".";
      if (c.locations.count(base + "per_pair.preload") ||
          c.locations.count(base + "per_area.preload") ||
          c.locations.count(base + "total.preload") || !it->preload_file.empty())
        fail("contact '" + it->name + "' gives a preload; give either a preload or a gap");
      field = &it->gap;
    } else if (parts.size() == 4 &&
               (parts[2] == "per_pair" || parts[2] == "total" || parts[2] == "per_area")) {
      if (parts[2] != parameter_block(*it))
        fail("contact '" + it->name + "' gives its parameters in '" + parameter_block(*it) + "'");
      const std::vector<std::string> allowed = parameter_keys(*it);
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
        fail("'" + key + "' is not a parameter of law " + it->law);
      if (key == "preload" && !it->preload_file.empty())
        fail("contact '" + it->name + "' takes its preload from preload_file");
      if (key == "preload" && it->preload_computed)
        fail("contact '" + it->name + "' computes its preload from static_loads");
      if (key == "preload" && c.locations.count("contacts." + it->name + ".gap"))
        fail("contact '" + it->name + "' gives a gap; give either a preload or a gap");
      field = contact_parameter(it->parameters, key);
    }
  } else if (parts.size() == 2 && parts[0] == "damping") {
    if (key == "alpha") field = &c.damping.alpha;
    if (key == "beta") field = &c.damping.beta;
  } else if (parts.size() == 3 && parts[0] == "bodies" && key == "modal_damping_ratio") {
    auto it = c.bodies.find(parts[1]);
    if (it == c.bodies.end()) fail("no body '" + parts[1] + "'");
    field = &it->second.modal_damping_ratio;
  } else if (parts.size() == 2 && key == "amplitude" && parts[0].rfind("excitation[", 0) == 0 &&
             parts[0].back() == ']') {
    const std::string index = parts[0].substr(11, parts[0].size() - 12);
    size_t i = c.excitation.size();
    if (!index.empty() && index.find_first_not_of("0123456789") == std::string::npos &&
        index.size() < 9)
      i = static_cast<size_t>(std::stoul(index));
    if (i >= c.excitation.size()) fail("no excitation entry " + index);
    ExcitationDefinition& e = c.excitation[i];
    if (!e.by_direction) fail("excitation " + index + " is a force vector, not an amplitude");
    field = &e.amplitude;
    after = [&e] {
      const std::complex<double> a = std::polar(1.0, e.phase_deg * kPi / 180.0) * e.amplitude;
      for (size_t k = 0; k < 3; ++k) e.force[k] = a * e.direction[k];
    };
  } else if (parts.size() == 2 && parts[0].rfind("static_loads[", 0) == 0 &&
             parts[0].back() == ']') {
    const std::string index = parts[0].substr(13, parts[0].size() - 14);
    size_t i = c.static_loads.size();
    if (!index.empty() && index.find_first_not_of("0123456789") == std::string::npos &&
        index.size() < 9)
      i = static_cast<size_t>(std::stoul(index));
    if (i >= c.static_loads.size()) fail("no static_loads entry " + index);
    StaticLoadDefinition& l = c.static_loads[i];
    const std::string given = l.kind == StaticLoadDefinition::Kind::kPressure ? "pressure"
                              : l.kind == StaticLoadDefinition::Kind::kForce  ? "force"
                                                                              : "total_force";
    if (key != given) fail("static_loads entry " + index + " gives '" + given + "'");
    if (key == "pressure") {
      if (value == 0.0) fail("must not be 0");
      field = &l.pressure;
    } else {
      // The force vector scaled to the magnitude `value` (N), its direction kept.
      const double norm = std::sqrt(l.force[0] * l.force[0] + l.force[1] * l.force[1] +
                                    l.force[2] * l.force[2]);
      if (!(norm > 0)) fail("the static load's force is zero: it has no direction to keep");
      if (!(value >= 0)) fail("a magnitude must be >= 0");
      field = &magnitude;  // written below, then applied by `after`
      after = [&l, &magnitude, norm] {
        for (double& f : l.force) f *= magnitude / norm;
      };
    }
  } else if (parts.size() == 2 && parts[0] == "rotation" && key == "speed_rpm") {
    if (!c.rotation) fail("the case has no 'rotation'");
    field = &c.rotation->speed_rpm;
  }
  if (!field) fail("not a numeric key that a study can vary; " + supported);
  const std::string rule = numeric_rule_violation(key, value);
  if (!rule.empty()) fail(rule);
  *field = value;
  if (after) after();
  return c;
}

CaseDefinition with_absolute_paths(const CaseDefinition& definition) {
  CaseDefinition c = definition;
  const auto absolute = [](std::string& path) {
    if (!path.empty()) path = std::filesystem::absolute(path).lexically_normal().string();
  };
  for (auto& [name, m] : c.meshes) absolute(m.file);
  for (auto& [name, b] : c.bodies) {
    absolute(b.reduced.stiffness);
    absolute(b.reduced.mass);
    absolute(b.reduced.mapping);
  }
  for (ContactDefinition& d : c.contacts) {
    absolute(d.pairs_file);
    absolute(d.preload_file);
  }
  absolute(c.output.directory);
  return c;
}

std::string describe_case(const CaseDefinition& c) {
  YAML::Emitter e;
  // Numbers in their shortest round-trip form (yaml-cpp would print 17 digits).
  auto num = [](double v) { return format_number(v); };
  auto vec = [&](const auto& v) {
    e << YAML::Flow << YAML::BeginSeq;
    for (const auto& x : v) {
      if constexpr (std::is_floating_point_v<std::decay_t<decltype(x)>>) {
        e << num(x);
      } else {
        e << x;
      }
    }
    e << YAML::EndSeq;
  };
  auto selection = [&](const NodeSelection& s) {
    e << YAML::Flow << YAML::BeginSeq;
    for (const std::string& x : s.sets) e << x;
    for (int x : s.ids) e << x;
    e << YAML::EndSeq;
  };
  // `node: [ids]` or `node_set: [names]`, as the parser of excitation and static_loads takes it.
  auto node_or_node_set = [&](const NodeSelection& s) {
    e << YAML::Key << (s.sets.empty() ? "node" : "node_set") << YAML::Value;
    if (s.sets.empty()) {
      vec(s.ids);
    } else {
      vec(s.sets);
    }
  };
  e << YAML::BeginMap;
  e << YAML::Key << "stickslip" << YAML::Value << c.version;
  e << YAML::Key << "title" << YAML::Value << c.title;
  e << YAML::Key << "materials" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, m] : c.materials) {
    e << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "youngs_modulus" << YAML::Value << num(m.youngs_modulus);
    e << YAML::Key << "poisson_ratio" << YAML::Value << num(m.poisson_ratio);
    e << YAML::Key << "density" << YAML::Value << num(m.density) << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "meshes" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, m] : c.meshes) {
    e << YAML::Key << name << YAML::Value << YAML::BeginMap;
    if (m.source == MeshDefinition::Source::kGenerate) {
      const TwoBeamDefinition& t = m.two_beam;
      e << YAML::Key << "generate" << YAML::Value << m.generate;
      e << YAML::Key << "arrangement" << YAML::Value << case_name(t.arrangement);
      e << YAML::Key << "element" << YAML::Value << element_type_name(t.element);
      e << YAML::Key << "coarse" << YAML::Value << t.coarse;
      e << YAML::Key << "box" << YAML::Value;
      vec(t.box);
      e << YAML::Key << "end_block" << YAML::Value;
      vec(t.end_block);
      if (t.beam2_box) {  // only when given: the default keeps earlier fingerprints
        e << YAML::Key << "beam2_box" << YAML::Value;
        vec(*t.beam2_box);
      }
      if (t.beam2_end_block) {
        e << YAML::Key << "beam2_end_block" << YAML::Value;
        vec(*t.beam2_end_block);
      }
      e << YAML::Key << "beam_length" << YAML::Value << num(t.beam_length);
      e << YAML::Key << "width" << YAML::Value << num(t.width);
      e << YAML::Key << "thickness" << YAML::Value << num(t.thickness);
      e << YAML::Key << "end_length" << YAML::Value << num(t.end_length);
    } else {
      e << YAML::Key << "file" << YAML::Value << m.file;
      e << YAML::Key << "format" << YAML::Value << case_name(m.format);
      if (m.format == MeshFileFormat::kMsh) {
        e << YAML::Key << "hexahedron8" << YAML::Value << element_type_name(m.hexahedron8);
        e << YAML::Key << "hexahedron20" << YAML::Value << element_type_name(m.hexahedron20);
      }
    }
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "bodies" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, b] : c.bodies) {
    e << YAML::Key << name << YAML::Value << YAML::BeginMap;
    if (b.source == BodyDefinition::Source::kMesh) {
      e << YAML::Key << "mesh" << YAML::Value << b.mesh;
      e << YAML::Key << "element_set" << YAML::Value << b.element_set;
      e << YAML::Key << "material" << YAML::Value << b.material;
      e << YAML::Key << "clamp" << YAML::Value;
      selection(b.clamp);
      if (!b.supports.empty()) {
        e << YAML::Key << "supports" << YAML::Value << YAML::BeginSeq;
        for (const SupportDefinition& sd : b.supports) {
          if (sd.from_mesh) {
            e << YAML::BeginMap << YAML::Key << "from_mesh" << YAML::Value << true
              << YAML::EndMap;
            continue;
          }
          e << YAML::BeginMap << YAML::Key << "nodes" << YAML::Value;
          selection(sd.nodes);
          e << YAML::Key << "directions" << YAML::Value << YAML::Flow << YAML::BeginSeq;
          for (int d : sd.directions) e << support_direction_name(d, sd.local_frame);
          e << YAML::EndSeq;
          if (sd.local_frame) {
            e << YAML::Key << "normal" << YAML::Value << YAML::Flow
              << std::vector<double>(sd.normal.begin(), sd.normal.end());
            e << YAML::Key << "t1" << YAML::Value << YAML::Flow
              << std::vector<double>(sd.t1.begin(), sd.t1.end());
          }
          e << YAML::EndMap;
        }
        e << YAML::EndSeq;
      }
      if (!b.masters.empty()) {  // empty: not given (the contact and forced nodes)
        e << YAML::Key << "masters" << YAML::Value;
        selection(b.masters);
      }
      e << YAML::Key << "modes" << YAML::Value << b.modes;
      if (b.mass_rule == MassIntegration::kStiffnessRule)  // exact (the default): not written
        e << YAML::Key << "mass_rule" << YAML::Value << "calculix";
      if (b.cyclic) {
        const CyclicDefinition& cd = *b.cyclic;
        e << YAML::Key << "cyclic" << YAML::Value << YAML::BeginMap;
        e << YAML::Key << "sectors" << YAML::Value << cd.sectors;
        e << YAML::Key << "axis" << YAML::Value << YAML::BeginMap;
        e << YAML::Key << "point" << YAML::Value << YAML::Flow
          << std::vector<double>(cd.axis_point.begin(), cd.axis_point.end());
        e << YAML::Key << "direction" << YAML::Value << YAML::Flow
          << std::vector<double>(cd.axis_direction.begin(), cd.axis_direction.end());
        e << YAML::EndMap;
        if (!cd.low.empty()) {
          e << YAML::Key << "low" << YAML::Value;
          selection(cd.low);
          e << YAML::Key << "high" << YAML::Value;
          selection(cd.high);
        }
        e << YAML::Key << "tolerance" << YAML::Value << num(cd.tolerance);
        e << YAML::EndMap;
      }
    } else {
      e << YAML::Key << "reduced" << YAML::Value << YAML::BeginMap;
      e << YAML::Key << "stiffness" << YAML::Value << b.reduced.stiffness;
      e << YAML::Key << "mass" << YAML::Value << b.reduced.mass;
      e << YAML::Key << "mapping" << YAML::Value << b.reduced.mapping;
      e << YAML::Key << "format" << YAML::Value << case_name(b.reduced.format) << YAML::EndMap;
    }
    e << YAML::Key << "modal_damping_ratio" << YAML::Value << num(b.modal_damping_ratio);
    e << YAML::EndMap;
  }
  e << YAML::EndMap;
  e << YAML::Key << "contacts" << YAML::Value << YAML::BeginSeq;
  for (const ContactDefinition& d : c.contacts) {
    e << YAML::BeginMap;
    e << YAML::Key << "name" << YAML::Value << d.name;
    e << YAML::Key << "law" << YAML::Value << d.law;
    if (!d.nodes_a.empty()) {  // `between` names the bodies (one body: to the ground)
      e << YAML::Key << "between" << YAML::Value << YAML::Flow << YAML::BeginMap;
      e << YAML::Key << d.body_a << YAML::Value;
      selection(d.nodes_a);
      if (d.body_b != "ground") {
        e << YAML::Key << d.body_b << YAML::Value;
        selection(d.nodes_b);
      }
      e << YAML::EndMap;
      // The default (auto) and its defaults are not written: earlier fingerprints stay.
      if (d.coupling != ContactCoupling::kAuto)
        e << YAML::Key << "coupling" << YAML::Value << case_name(d.coupling);
      const bool surfaces = d.coupling == ContactCoupling::kMortar ||
                            d.coupling == ContactCoupling::kNodeToSurface;
      if (!surfaces) e << YAML::Key << "tolerance" << YAML::Value << num(d.tolerance);
      if (surfaces || d.search_distance != 0.0)
        e << YAML::Key << "search_distance" << YAML::Value << num(d.search_distance);
      if (surfaces || d.unpaired != UnpairedChoice::kError)
        e << YAML::Key << "unpaired" << YAML::Value << case_name(d.unpaired);
    } else {
      e << YAML::Key << "bodies" << YAML::Value;
      vec(std::vector<std::string>{d.body_a, d.body_b});
      if (!d.pairs_file.empty()) {
        e << YAML::Key << "pairs_file" << YAML::Value << d.pairs_file;
      } else {
        e << YAML::Key << "pairs" << YAML::Value << YAML::Flow << YAML::BeginSeq;
        for (const auto& pr : d.pairs) vec(pr);
        e << YAML::EndSeq;
      }
      if (d.neighbour != 0)
        e << YAML::Key << "neighbour" << YAML::Value << (d.neighbour > 0 ? "next" : "previous");
    }
    e << YAML::Key << (uses_frame(d) ? "normal" : "direction") << YAML::Value;
    vec(uses_frame(d) ? d.normal : d.direction);
    if (uses_frame(d) && d.t1 != std::array<double, 3>{0, 0, 0}) {  // zero: not given
      e << YAML::Key << "t1" << YAML::Value;
      vec(d.t1);
    }
    const bool with_split = d.parameters_given == ContactDefinition::Parameters::kTotal;
    e << YAML::Key << parameter_block(d) << YAML::Value << YAML::Flow << YAML::BeginMap;
    ContactParametersDefinition params = d.parameters;
    // A preload from a file, or a gap, stands instead of the `preload` key (the parser takes one).
    const bool gap = law_of(d).has_gap && d.gap != 0;
    for (const std::string& key : parameter_keys(d)) {
      if (key == "preload" && !d.preload_computed && (gap || !d.preload_file.empty())) continue;
      e << YAML::Key << key << YAML::Value;
      if (key == "preload" && d.preload_computed) {
        e << "computed";
      } else {
        e << num(*contact_parameter(params, key));
      }
    }
    if (with_split) e << YAML::Key << "split" << YAML::Value << case_name(d.split);
    e << YAML::EndMap;
    if (!d.preload_file.empty()) e << YAML::Key << "preload_file" << YAML::Value << d.preload_file;
    if (gap) e << YAML::Key << "gap" << YAML::Value << num(d.gap);
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "excitation" << YAML::Value << YAML::BeginSeq;
  for (const ExcitationDefinition& x : c.excitation) {
    e << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "body" << YAML::Value << x.body;
    node_or_node_set(x.nodes);
    e << YAML::Key << "harmonic" << YAML::Value << x.harmonic;
    if (x.engine_order >= 0) e << YAML::Key << "engine_order" << YAML::Value << x.engine_order;
    if (x.by_direction) {  // as given, so that a study of its amplitude still applies
      e << YAML::Key << "direction" << YAML::Value;
      vec(x.direction);
      e << YAML::Key << "amplitude" << YAML::Value << num(x.amplitude);
      e << YAML::Key << "phase_deg" << YAML::Value << num(x.phase_deg);
    } else {
      e << YAML::Key << "force" << YAML::Value << YAML::BeginSeq;
      for (const auto& f : x.force) vec(std::array<double, 2>{f.real(), f.imag()});
      e << YAML::EndSeq;
    }
    e << YAML::EndMap;
  }
  e << YAML::EndSeq;
  if (!c.static_loads.empty()) {
    e << YAML::Key << "static_loads" << YAML::Value << YAML::BeginSeq;
    for (const StaticLoadDefinition& l : c.static_loads) {
      e << YAML::Flow << YAML::BeginMap;
      e << YAML::Key << "body" << YAML::Value << l.body;
      node_or_node_set(l.nodes);
      if (l.kind == StaticLoadDefinition::Kind::kPressure) {
        e << YAML::Key << "pressure" << YAML::Value << num(l.pressure);
      } else {
        e << YAML::Key
          << (l.kind == StaticLoadDefinition::Kind::kForce ? "force" : "total_force")
          << YAML::Value;
        vec(l.force);
      }
      e << YAML::EndMap;
    }
    e << YAML::EndSeq;
  }
  if (c.rotation) {
    const RotationDefinition& r = *c.rotation;
    e << YAML::Key << "rotation" << YAML::Value << YAML::BeginMap;
    e << YAML::Key << "speed_rpm" << YAML::Value << num(r.speed_rpm);
    if (r.axis_given) {
      e << YAML::Key << "axis" << YAML::Value << YAML::Flow << YAML::BeginMap;
      e << YAML::Key << "point" << YAML::Value;
      vec(r.axis_point);
      e << YAML::Key << "direction" << YAML::Value;
      vec(r.axis_direction);
      e << YAML::EndMap;
    }
    e << YAML::Key << "stress_stiffening" << YAML::Value << r.stress_stiffening;
    e << YAML::Key << "spin_softening" << YAML::Value << r.spin_softening;
    if (!r.campbell_speeds_rpm.empty()) {
      e << YAML::Key << "campbell" << YAML::Value << YAML::Flow << YAML::BeginMap;
      e << YAML::Key << "speeds_rpm" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (double v : r.campbell_speeds_rpm) e << num(v);
      e << YAML::EndSeq;
      if (!r.engine_orders.empty()) {
        e << YAML::Key << "engine_orders" << YAML::Value;
        vec(r.engine_orders);
      }
      e << YAML::EndMap;
    }
    e << YAML::EndMap;
  }
  e << YAML::Key << "damping" << YAML::Value << YAML::Flow << YAML::BeginMap;
  e << YAML::Key << "alpha" << YAML::Value << num(c.damping.alpha);
  e << YAML::Key << "beta" << YAML::Value << num(c.damping.beta) << YAML::EndMap;
  const AnalysisDefinition& a = c.analysis;
  e << YAML::Key << "analysis" << YAML::Value << YAML::BeginMap;
  const bool nonlinear_mode = a.method == SweepMethod::kNonlinearMode;
  if (nonlinear_mode) {
    e << YAML::Key << "mode" << YAML::Value << a.mode;
    e << YAML::Key << "amplitude" << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "start" << YAML::Value << num(a.amplitude.start);
    e << YAML::Key << "stop" << YAML::Value << num(a.amplitude.stop);
    e << YAML::Key << "points" << YAML::Value << a.amplitude.points << YAML::EndMap;
  } else {
  if (a.predict_from_mode) {
    e << YAML::Key << "nonlinear_mode" << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "mode" << YAML::Value << a.mode;
    e << YAML::Key << "amplitude" << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "start" << YAML::Value << num(a.amplitude.start);
    e << YAML::Key << "stop" << YAML::Value << num(a.amplitude.stop);
    e << YAML::Key << "points" << YAML::Value << a.amplitude.points << YAML::EndMap;
    e << YAML::EndMap;
  }
  e << YAML::Key << "frequency" << YAML::Value << YAML::Flow << YAML::BeginMap;
  if (a.frequency.kind == FrequencyDefinition::Kind::kRange) {
    e << YAML::Key << "start_hz" << YAML::Value << num(a.frequency.start_hz);
    e << YAML::Key << "stop_hz" << YAML::Value << num(a.frequency.stop_hz);
  } else {
    e << YAML::Key << "around_mode" << YAML::Value << a.frequency.around_mode;
    e << YAML::Key << "half_width_hz" << YAML::Value << num(a.frequency.half_width_hz);
  }
  e << YAML::Key << "step_hz" << YAML::Value << num(a.frequency.step_hz);
  e << YAML::Key << "sweep" << YAML::Value << (a.frequency.downward ? "down" : "up");
  if (a.method == SweepMethod::kContinuation) {
    // 0: not given (the continuation derives them from step_hz)
    if (a.frequency.min_step_hz > 0)
      e << YAML::Key << "min_step_hz" << YAML::Value << num(a.frequency.min_step_hz);
    if (a.frequency.max_step_hz > 0)
      e << YAML::Key << "max_step_hz" << YAML::Value << num(a.frequency.max_step_hz);
  }
  e << YAML::EndMap;
  }
  e << YAML::Key << "method" << YAML::Value << case_name(a.method);
  e << YAML::Key << "harmonics" << YAML::Value;
  vec(a.harmonics);
  e << YAML::Key << "time_samples" << YAML::Value << a.time_samples;
  if (a.aft_given) e << YAML::Key << "aft" << YAML::Value << case_name(a.aft);
  e << YAML::Key << "static" << YAML::Value << case_name(a.static_coupling);
  if (a.static_increments > 0) e << YAML::Key << "static_increments" << YAML::Value << a.static_increments;
  if (!nonlinear_mode) e << YAML::Key << "stability" << YAML::Value << a.stability;
  e << YAML::Key << "tolerance" << YAML::Value << num(a.tolerance);
  e << YAML::Key << "max_iterations" << YAML::Value << a.max_iterations;
  if (a.method == SweepMethod::kContinuation) e << YAML::Key << "max_points" << YAML::Value << a.max_points;
  if (!nonlinear_mode) e << YAML::Key << "initial_guess" << YAML::Value << case_name(a.initial_guess);
  if (a.method == SweepMethod::kStepped) e << YAML::Key << "predictor" << YAML::Value << case_name(a.predictor);
  e << YAML::EndMap;
  if (c.study.active()) {
    e << YAML::Key << "study" << YAML::Value << YAML::Flow << YAML::BeginMap;
    e << YAML::Key << "parameter" << YAML::Value << c.study.parameter;
    e << YAML::Key << "values" << YAML::Value;
    vec(c.study.values);
    e << YAML::EndMap;
  }
  const RecoveryDefinition& r = c.recovery;
  e << YAML::Key << "recovery" << YAML::Value << YAML::Flow << YAML::BeginMap;
  e << YAML::Key << "points" << YAML::Value;
  if (r.points == RecoveryPoints::kList) {
    vec(r.frequencies_hz);
  } else {
    e << case_name(r.points);
  }
  e << YAML::Key << "method" << YAML::Value << case_name(r.method);
  if (r.method == RecoveryMethod::kModal) e << YAML::Key << "modes" << YAML::Value << r.modes;
  e << YAML::Key << "fields" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (RecoveryField f : r.fields) e << case_name(f);
  e << YAML::EndSeq;
  e << YAML::Key << "nodes" << YAML::Value;
  vec(r.nodes);
  e << YAML::Key << "annulus" << YAML::Value << r.annulus;
  e << YAML::EndMap;
  const OutputDefinition& o = c.output;
  e << YAML::Key << "output" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "directory" << YAML::Value << o.directory;
  e << YAML::Key << "vtu" << YAML::Value << o.vtu;
  e << YAML::Key << "plots" << YAML::Value << o.plots;
  e << YAML::Key << "log_amplitude" << YAML::Value << o.log_amplitude;
  e << YAML::Key << "apdl_macro" << YAML::Value << o.apdl_macro;
  e << YAML::Key << "calculix_deck" << YAML::Value << o.calculix_deck;
  e << YAML::Key << "histories" << YAML::Value << YAML::Flow << YAML::BeginMap;
  for (const auto& [name, pairs] : o.histories) {
    e << YAML::Key << name << YAML::Value;
    vec(pairs);
  }
  e << YAML::EndMap;
  e << YAML::Key << "frf" << YAML::Value << YAML::BeginSeq;
  for (const ResponseDofDefinition& d : o.frf) {
    e << YAML::Flow << YAML::BeginMap << YAML::Key << "body" << YAML::Value << d.body;
    e << YAML::Key << "node" << YAML::Value << d.node;
    e << YAML::Key << "direction" << YAML::Value << std::string(1, char('x' + d.direction))
      << YAML::EndMap;
  }
  e << YAML::EndSeq;
  e << YAML::Key << "quiet" << YAML::Value << o.quiet;
  e << YAML::EndMap;
  e << YAML::EndMap;
  return e.c_str();
}

}  // namespace stickslip

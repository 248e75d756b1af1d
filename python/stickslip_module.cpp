// The Python module `stickslip` (docs/python.md is generated from the docstrings here): a case read
// from YAML or built from numpy arrays, changed from Python, solved by the model layer
// (model/case_model.h: prepare_model, solve_case) and recovered on the full bodies
// (model/body_recovery.h). One translation unit: pybind11 is heavy to compile.
//
// Contract:
//  - Bad input (a case file, a key path, an argument value) raises stickslip.InvalidInput, a
//    ValueError whose text is InvalidInput's "file:line: key: message"; a wrong argument type
//    raises TypeError (pybind11's conversion, or ours with the argument's name).
//  - solve() and recover() release the GIL while they compute; progress callbacks and the
//    warnings of model building run with the GIL re-acquired. A Case is copied when solve()
//    starts, so changing it from another thread does not affect a running solve. Cases made by
//    copy() share one cache of meshes and Craig–Bampton reductions (ModelCache), so a study over
//    contact, damping, excitation or analysis values reduces the bodies once; model building of
//    cases that share a cache is serialised, their solves run in parallel.
//  - Results are numpy arrays (copies; SI units, frequencies in Hz, complex harmonics
//    X_k = a_k − i b_k as in docs/conventions.md).
#include <pybind11/complex.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact_law.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/case_file.h"
#include "model/body_recovery.h"
#include "model/body_reduction.h"
#include "model/case_model.h"
#include "model/frf_peaks.h"
#include "model/recovery_loads.h"
#include "recovery/stress_envelope.h"
#include "reduction/reduced_body.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif

namespace py = pybind11;
using namespace pybind11::literals;

namespace stickslip {
namespace {

// The text Python users see for a value: "80", "4.467e+09".
std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

[[noreturn]] void value_error(const std::string& text) { throw py::value_error(text); }
[[noreturn]] void type_error(const std::string& text) { throw py::type_error(text); }

// ------------------------------------------------------------------------------------------
// Arguments from Python.

// A number (int, float, numpy scalar; not text), or TypeError naming `what`.
double number_argument(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::str>(value) || py::isinstance<py::bytes>(value) || value.is_none())
    type_error(what + ": expected a number");
  const double v = PyFloat_AsDouble(value.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    type_error(what + ": expected a number");
  }
  return v;
}

// An integer (int or numpy integer; not float or text), or TypeError naming `what`.
long long integer_argument(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr()))
    type_error(what + ": expected an integer");
  const long long v =
      PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())).ptr());
  if (v == -1 && PyErr_Occurred()) {
    PyErr_Clear();
    value_error(what + ": integer out of range");
  }
  return v;
}

// A direction: "x", "-z", ... or three numbers (normalised; not zero).
std::array<double, 3> direction_argument(const py::handle& value, const std::string& what) {
  std::array<double, 3> d{0, 0, 0};
  if (py::isinstance<py::str>(value)) {
    std::string s = value.cast<std::string>();
    double sign = 1;
    if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
      sign = s[0] == '-' ? -1 : 1;
      s = s.substr(1);
    }
    if (s != "x" && s != "y" && s != "z")
      value_error(what + " = '" + value.cast<std::string>() +
                  "': give x, y, z, -x, -y, -z or "
                  "three numbers");
    d[static_cast<size_t>(s[0] - 'x')] = sign;
    return d;
  }
  if (!py::isinstance<py::sequence>(value) || py::len(value) != 3)
    type_error(what + ": expected 'x', 'y', 'z' (optionally signed) or a sequence of 3 numbers");
  double norm = 0;
  for (size_t i = 0; i < 3; ++i) {
    d[i] = number_argument(py::object(value[py::int_(i)]), what);
    norm += d[i] * d[i];
  }
  norm = std::sqrt(norm);
  if (!(norm > 0) || !std::isfinite(norm)) value_error(what + ": the vector is zero or not finite");
  for (double& x : d) x /= norm;
  return d;
}

int axis_argument(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::str>(value)) {
    const std::string s = value.cast<std::string>();
    if (s == "x" || s == "y" || s == "z") return s[0] - 'x';
    value_error(what + " = '" + s + "': give x, y, z or 0, 1, 2");
  }
  const long long d = integer_argument(value, what + " (x, y, z or 0, 1, 2)");
  if (d < 0 || d > 2) value_error(what + " = " + std::to_string(d) + ": give x, y, z or 0, 1, 2");
  return static_cast<int>(d);
}

// A square matrix of finite numbers from a numpy array, anything numpy converts, or a
// scipy.sparse matrix (densified: reduced matrices are small and dense).
Eigen::MatrixXd matrix_argument(const py::object& value, const std::string& what) {
  py::object dense = value;
  if (py::hasattr(value, "toarray") && !py::isinstance<py::array>(value))
    dense = value.attr("toarray")();
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(dense);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a) {
    PyErr_Clear();
    type_error(what + ": expected a 2-D array of numbers (numpy or scipy.sparse)");
  }
  if (a.ndim() != 2 || a.shape(0) != a.shape(1) || a.shape(0) == 0)
    value_error(what + ": expected a non-empty square matrix");
  const auto n = static_cast<Eigen::Index>(a.shape(0));
  Eigen::MatrixXd m(n, n);
  auto r = a.unchecked<2>();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      m(i, j) = r(i, j);
      if (!std::isfinite(m(i, j)))
        value_error(what + ": entry (" + std::to_string(i) + ", " + std::to_string(j) +
                    ") is not finite");
    }
  }
  return m;
}

// The DOFs of a body given by matrices: per row, (node id, direction) of a physical DOF or None
// for a modal (generalised) DOF.
std::vector<ReducedDof> dofs_argument(const py::object& value, Eigen::Index size) {
  if (!py::isinstance<py::sequence>(value) && !py::isinstance<py::array>(value))
    type_error("dofs: expected a sequence of (node_id, direction) pairs or None (modal DOF)");
  py::sequence rows = py::isinstance<py::array>(value)
                          ? py::sequence(value.attr("tolist")())
                          : py::reinterpret_borrow<py::sequence>(value);
  if (static_cast<Eigen::Index>(py::len(rows)) != size)
    value_error("dofs: " + std::to_string(py::len(rows)) + " entries for matrices of size " +
                std::to_string(size));
  std::vector<ReducedDof> dofs;
  int mode = 0;
  std::map<std::pair<int, int>, size_t> seen;
  for (size_t i = 0; i < py::len(rows); ++i) {
    const py::object row = rows[i];
    ReducedDof dof;
    if (row.is_none()) {
      dof.kind = ReducedDof::Kind::kModal;
      dof.mode = mode++;
    } else {
      if (!py::isinstance<py::sequence>(row) || py::isinstance<py::str>(row) || py::len(row) != 2)
        type_error("dofs[" + std::to_string(i) + "]: expected (node_id, direction) or None");
      const py::sequence pair = py::reinterpret_borrow<py::sequence>(row);
      const long long id = integer_argument(pair[0], "dofs[" + std::to_string(i) + "] node id");
      dof.kind = ReducedDof::Kind::kPhysical;
      dof.node_id = id > 0 && id < (1LL << 31) ? static_cast<int>(id) : 0;
      dof.direction = axis_argument(pair[1], "dofs[" + std::to_string(i) + "] direction");
      if (dof.node_id <= 0)
        value_error("dofs[" + std::to_string(i) + "]: node id " + std::to_string(dof.node_id) +
                    " (node ids are positive)");
      if (!seen.emplace(std::make_pair(dof.node_id, dof.direction), i).second)
        value_error("dofs[" + std::to_string(i) + "]: node " + std::to_string(dof.node_id) +
                    " direction " + "xyz"[dof.direction] + " given twice");
    }
    dofs.push_back(dof);
  }
  return dofs;
}

// ------------------------------------------------------------------------------------------
// The case: its definition, the bodies given as matrices, the shared model cache.

struct SharedCache {
  std::mutex mutex;
  ModelCache cache;
};

struct PyCase {
  CaseDefinition definition;
  std::map<std::string, std::shared_ptr<const ReducedBody>> given;  // bodies from arrays
  std::shared_ptr<SharedCache> cache = std::make_shared<SharedCache>();
};

const char* const kBlockNames[] = {"per_pair", "total", "per_area"};
std::string parameter_block(const ContactDefinition& c) {
  return kBlockNames[static_cast<int>(c.parameters_given)];
}

const ContactDefinition& find_contact(const CaseDefinition& def, const std::string& name,
                                      const std::string& path) {
  for (const ContactDefinition& c : def.contacts) {
    if (c.name == name) return c;
  }
  std::string names;
  for (const ContactDefinition& c : def.contacts) names += (names.empty() ? "" : ", ") + c.name;
  throw InvalidInput({def.file, 0, path}, "no contact '" + name + "' (contacts: " +
                                              (names.empty() ? "none" : names) + ")");
}

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  std::stringstream ss(path);
  while (std::getline(ss, part, '.')) parts.push_back(part);
  return parts;
}

// A key path in its canonical form (the study's, io/case_file.h with_parameter):
// "contacts[0]" -> "contacts.<name>", and a law parameter without its block
// ("contacts.joint.preload") gets the contact's block ("contacts.joint.per_pair.preload").
std::string canonical_path(const CaseDefinition& def, const std::string& path) {
  std::vector<std::string> parts = split_path(path);
  if (!parts.empty() && parts[0].rfind("contacts[", 0) == 0 && parts[0].back() == ']') {
    const std::string index = parts[0].substr(9, parts[0].size() - 10);
    size_t i = def.contacts.size();
    if (!index.empty() && index.size() < 9 &&
        index.find_first_not_of("0123456789") == std::string::npos)
      i = std::stoul(index);
    if (i >= def.contacts.size())
      throw InvalidInput({def.file, 0, path}, "no contact " + index + " (the case has " +
                                                  std::to_string(def.contacts.size()) + ")");
    parts[0] = def.contacts[i].name;
    parts.insert(parts.begin(), "contacts");
  }
  if (parts.size() == 3 && parts[0] == "contacts" && parts[2] != "gap") {
    parts.insert(parts.begin() + 2, parameter_block(find_contact(def, parts[1], path)));
  }
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : ".") + p;
  return out;
}

// The analysis keys set() and get() know (docs/python.md), besides the study's paths.
const std::vector<std::string> kAnalysisKeys = {
    "start_hz",    "stop_hz",   "step_hz",      "around_mode", "half_width_hz",  "min_step_hz",
    "max_step_hz", "harmonics", "time_samples", "tolerance",   "max_iterations", "max_points"};

std::string analysis_key(const std::vector<std::string>& parts) {
  if (parts.size() == 3 && parts[0] == "analysis" && parts[1] == "frequency") return parts[2];
  if (parts.size() == 2 && parts[0] == "analysis" && parts[1] != "frequency") return parts[1];
  return "";
}

bool is_integer(double v) { return std::isfinite(v) && v == std::floor(v) && std::abs(v) < 1e9; }

// Sets one analysis value, checking the rule the case file would check.
void set_analysis_value(CaseDefinition& def, const std::string& key, double v,
                        const std::string& path) {
  const auto fail = [&](const std::string& rule) {
    throw InvalidInput({def.file, 0, path}, number_text(v) + ": " + rule);
  };
  FrequencyDefinition& f = def.analysis.frequency;
  AnalysisDefinition& a = def.analysis;
  if (!std::isfinite(v)) fail("not a finite number");
  if (key == "start_hz" || key == "stop_hz") {
    if (v < 0) fail("frequencies are >= 0 Hz");
    f.kind = FrequencyDefinition::Kind::kRange;
    (key == "start_hz" ? f.start_hz : f.stop_hz) = v;
  } else if (key == "step_hz") {
    if (!(v > 0)) fail("must be > 0");
    f.step_hz = v;
  } else if (key == "min_step_hz" || key == "max_step_hz") {
    if (v < 0) fail("must be >= 0 (0: automatic)");
    (key == "min_step_hz" ? f.min_step_hz : f.max_step_hz) = v;
  } else if (key == "around_mode") {
    if (!is_integer(v) || v < 1) fail("a mode number >= 1");
    f.kind = FrequencyDefinition::Kind::kAroundMode;
    f.around_mode = static_cast<int>(v);
  } else if (key == "half_width_hz") {
    if (!(v > 0)) fail("must be > 0");
    f.half_width_hz = v;
  } else if (key == "harmonics") {
    if (!is_integer(v) || v < 1 || v > kMaxHarmonic)
      fail("H, an integer in [1, " + std::to_string(kMaxHarmonic) + "] (harmonics 1..H)");
    a.harmonics.clear();
    for (int k = 1; k <= static_cast<int>(v); ++k) a.harmonics.push_back(k);
  } else if (key == "time_samples") {
    if (!is_integer(v) || v < 2 || v > kMaxTimeSamples)
      fail("an integer in [2, " + std::to_string(kMaxTimeSamples) + "]");
    a.time_samples = static_cast<int>(v);
  } else if (key == "tolerance") {
    if (!(v > 0)) fail("must be > 0");
    a.tolerance = v;
  } else if (key == "max_iterations") {
    if (!is_integer(v) || v < 1) fail("an integer >= 1");
    a.max_iterations = static_cast<int>(v);
  } else if (key == "max_points") {
    if (!is_integer(v) || v < 2 || v > kMaxFrequencyPoints)
      fail("an integer in [2, " + std::to_string(kMaxFrequencyPoints) + "]");
    a.max_points = static_cast<int>(v);
  } else {
    std::string keys;
    for (const std::string& k : kAnalysisKeys) keys += (keys.empty() ? "" : ", ") + k;
    throw InvalidInput({def.file, 0, path}, "not a numeric analysis key (" + keys + ")");
  }
}

double get_analysis_value(const CaseDefinition& def, const std::string& key,
                          const std::string& path) {
  const FrequencyDefinition& f = def.analysis.frequency;
  const AnalysisDefinition& a = def.analysis;
  if (key == "start_hz") return f.start_hz;
  if (key == "stop_hz") return f.stop_hz;
  if (key == "step_hz") return f.step_hz;
  if (key == "min_step_hz") return f.min_step_hz;
  if (key == "max_step_hz") return f.max_step_hz;
  if (key == "around_mode") return f.around_mode;
  if (key == "half_width_hz") return f.half_width_hz;
  if (key == "harmonics") return a.max_harmonic();
  if (key == "time_samples") return a.time_samples;
  if (key == "tolerance") return a.tolerance;
  if (key == "max_iterations") return a.max_iterations;
  if (key == "max_points") return a.max_points;
  throw InvalidInput({def.file, 0, path}, "not a numeric analysis key");
}

// The value at a study path (with_parameter's paths; static_loads: the magnitude).
double get_value(const CaseDefinition& def, const std::string& raw_path) {
  const std::string path = canonical_path(def, raw_path);
  const std::vector<std::string> parts = split_path(path);
  const auto fail = [&](const std::string& rule) -> double {
    throw InvalidInput({def.file, 0, raw_path}, rule);
  };
  if (const std::string key = analysis_key(parts); !key.empty())
    return get_analysis_value(def, key, raw_path);
  const std::string key = parts.empty() ? "" : parts.back();
  if (parts.size() == 3 && parts[0] == "materials") {
    const auto it = def.materials.find(parts[1]);
    if (it == def.materials.end()) return fail("no material '" + parts[1] + "'");
    if (key == "youngs_modulus") return it->second.youngs_modulus;
    if (key == "poisson_ratio") return it->second.poisson_ratio;
    if (key == "density") return it->second.density;
  } else if (parts.size() == 3 && parts[0] == "contacts" && key == "gap") {
    return find_contact(def, parts[1], raw_path).gap;
  } else if (parts.size() == 4 && parts[0] == "contacts") {
    const ContactDefinition& c = find_contact(def, parts[1], raw_path);
    if (parts[2] != parameter_block(c))
      return fail("contact '" + c.name + "' gives its parameters in '" + parameter_block(c) + "'");
    const auto keys = contact_law(c.law, c.uses_frame).parameter_keys();
    if (std::find(keys.begin(), keys.end(), key) == keys.end())
      return fail("'" + key + "' is not a parameter of law " + c.law);
    return c.parameters.value(key);
  } else if (parts.size() == 2 && parts[0] == "damping") {
    if (key == "alpha") return def.damping.alpha;
    if (key == "beta") return def.damping.beta;
  } else if (parts.size() == 3 && parts[0] == "bodies" && key == "modal_damping_ratio") {
    const auto it = def.bodies.find(parts[1]);
    if (it == def.bodies.end()) return fail("no body '" + parts[1] + "'");
    return it->second.modal_damping_ratio;
  } else if (parts.size() == 2 && parts[0].rfind("excitation[", 0) == 0 && key == "amplitude") {
    const std::string index = parts[0].substr(11, parts[0].size() - 12);
    if (index.empty() || index.size() > 8 ||
        index.find_first_not_of("0123456789") != std::string::npos ||
        std::stoul(index) >= def.excitation.size())
      return fail("no excitation entry " + index);
    const ExcitationDefinition& e = def.excitation[std::stoul(index)];
    if (!e.by_direction)
      return fail("excitation " + index + " is a force vector, not an amplitude");
    return e.amplitude;
  } else if (parts.size() == 2 && parts[0].rfind("static_loads[", 0) == 0) {
    const std::string index = parts[0].substr(13, parts[0].size() - 14);
    if (index.empty() || index.size() > 8 ||
        index.find_first_not_of("0123456789") != std::string::npos ||
        std::stoul(index) >= def.static_loads.size())
      return fail("no static_loads entry " + index);
    const StaticLoadDefinition& l = def.static_loads[std::stoul(index)];
    if (key == "pressure" && l.kind == StaticLoadDefinition::Kind::kPressure) return l.pressure;
    if ((key == "force" && l.kind == StaticLoadDefinition::Kind::kForce) ||
        (key == "total_force" && l.kind == StaticLoadDefinition::Kind::kTotalForce))
      return std::sqrt(l.force[0] * l.force[0] + l.force[1] * l.force[1] + l.force[2] * l.force[2]);
    return fail("static_loads entry " + index + " has no '" + key + "'");
  }
  return fail(
      "not a key path set() and get() know: the study's paths (stickslip keys, "
      "docs/case-file.md `study`) and analysis." +
      std::string("{start_hz, ...}"));
}

void set_value(CaseDefinition& def, const std::string& raw_path, double value) {
  const std::string path = canonical_path(def, raw_path);
  const std::vector<std::string> parts = split_path(path);
  if (const std::string key = analysis_key(parts); !key.empty()) {
    set_analysis_value(def, key, value, raw_path);
    return;
  }
  if (!std::isfinite(value))
    throw InvalidInput({def.file, 0, raw_path}, number_text(value) + ": not a finite number");
  def = with_parameter(def, path, value, {def.file, 0, raw_path});
}

// What the solve needs that a case built from Python may lack (a case file's parser checks the
// same at its keys).
void check_solvable(const PyCase& c) {
  const CaseDefinition& def = c.definition;
  const AnalysisDefinition& a = def.analysis;
  const FrequencyDefinition& f = a.frequency;
  const auto fail = [&](const std::string& key, const std::string& rule) {
    throw InvalidInput(def.where(key), rule);
  };
  if (def.bodies.empty()) fail("bodies", "the case has no bodies (add_body)");
  for (const auto& [name, body] : def.bodies) {
    if (body.source == BodyDefinition::Source::kReduced && body.reduced.stiffness.empty() &&
        !c.given.count(name))
      fail("bodies." + name, "body '" + name + "' has no matrices");
  }
  if (f.kind == FrequencyDefinition::Kind::kRange && !(f.start_hz < f.stop_hz))
    fail("analysis.frequency", "the frequency range " + number_text(f.start_hz) + " to " +
                                   number_text(f.stop_hz) +
                                   " Hz is empty: set_analysis(start_hz=..., stop_hz=...)");
  if (f.kind == FrequencyDefinition::Kind::kAroundMode && !(f.half_width_hz > 0))
    fail("analysis.frequency.half_width_hz", "around_mode needs half_width_hz > 0");
  if (a.method == SweepMethod::kStepped && !(f.step_hz > 0))
    fail("analysis.frequency.step_hz", "a stepped sweep needs step_hz > 0");
  if (a.method == SweepMethod::kStepped && f.kind == FrequencyDefinition::Kind::kRange &&
      (f.stop_hz - f.start_hz) / f.step_hz + 1 > kMaxFrequencyPoints)
    fail("analysis.frequency.step_hz",
         "more than " + std::to_string(kMaxFrequencyPoints) + " frequency points");
  if (a.harmonics.empty()) fail("analysis.harmonics", "no harmonics");
  const long long needed = 2LL * (2LL * a.max_harmonic() + 1);
  if (a.time_samples < needed)
    fail("analysis.time_samples", "time_samples = " + std::to_string(a.time_samples) +
                                      " < 2(2H+1) = " + std::to_string(needed) +
                                      " for H = " + std::to_string(a.max_harmonic()));
  for (size_t i = 0; i < def.excitation.size(); ++i) {
    const int k = def.excitation[i].harmonic;
    if (k != 0 && std::find(a.harmonics.begin(), a.harmonics.end(), k) == a.harmonics.end())
      fail("excitation[" + std::to_string(i) + "].harmonic",
           "harmonic " + std::to_string(k) + " is not an analysis harmonic");
  }
}

// ------------------------------------------------------------------------------------------
// Progress and warnings into Python.

// Calls the Python callback (GIL re-acquired) with (text, fraction or None). An exception it
// raises is kept, further calls are skipped, and it is re-raised when the solve returns (the
// solve itself runs to its end: the library's callbacks must not throw).
class ProgressRelay {
 public:
  explicit ProgressRelay(const py::object* callback) : callback_(callback) {}
  void operator()(const std::string& text, std::optional<double> fraction) {
    if (callback_ == nullptr) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_) return;
    py::gil_scoped_acquire acquire;
    try {
      if (fraction)
        (*callback_)(text, *fraction);
      else
        (*callback_)(text, py::none());
    } catch (...) {
      error_ = std::current_exception();
    }
  }
  ProgressFn stage() {
    if (callback_ == nullptr) return nullptr;
    return [this](const std::string& line) { (*this)(line, std::nullopt); };
  }
  void rethrow() {
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }

 private:
  const py::object* callback_;
  std::mutex mutex_;
  std::exception_ptr error_;
};

// The model of a case (prepare_model): bodies given by arrays through GivenReduction, the others
// reduced by Craig–Bampton with the shared cache (serialised: ModelCache is not thread-safe).
// Called without the GIL.
std::shared_ptr<const PreparedModel> build_model(
    const CaseDefinition& def,
    const std::map<std::string, std::shared_ptr<const ReducedBody>>& given, SharedCache& cache,
    const ProgressFn& stage) {
  std::lock_guard<std::mutex> lock(cache.mutex);
  if (given.empty())
    return std::make_shared<PreparedModel>(prepare_model(def, stage, &cache.cache));
  return std::make_shared<PreparedModel>(prepare_model(
      def, resolve_case_bodies(def, stage, &cache.cache), GivenReduction(given), stage));
}

// ------------------------------------------------------------------------------------------
// The solution.

struct PySolution {
  std::shared_ptr<const CaseDefinition> definition;
  std::shared_ptr<const PreparedModel> model;
  std::shared_ptr<const SolvedCase> solved;
  // Physical master DOFs in the order of `master`: (body index, node id, direction, global DOF).
  struct Dof {
    int body, node, direction, global;
  };
  std::vector<Dof> dofs;
  std::vector<int> pair_in_contact;  // per pair: its index within its contact

  const std::vector<FrequencyPoint>& points() const { return solved->response.points; }
  size_t num_points() const { return points().size(); }
  size_t num_harmonics() const { return solved->response.harmonics.size(); }

  size_t point_index(long long point) const {
    const auto n = static_cast<long long>(num_points());
    if (point < -n || point >= n)
      throw py::index_error("point " + std::to_string(point) + " out of range (" +
                            std::to_string(n) + " points)");
    return static_cast<size_t>(point < 0 ? point + n : point);
  }
  int global_dof(const std::string& body, int node, const py::handle& direction) const {
    const int b = model->body_index(body);
    if (b < 0) value_error("no body '" + body + "'");
    const int d = axis_argument(direction, "direction");
    const int g = model->bodies[static_cast<size_t>(b)].global_dof(node, d);
    if (g < 0)
      value_error("node " + std::to_string(node) + " direction " + "xyz"[d] +
                  " is not a master DOF of body '" + body + "'");
    return g;
  }
  int harmonic_column(int harmonic) const {
    const auto& h = solved->response.harmonics;
    const auto it = std::find(h.begin(), h.end(), harmonic);
    if (it == h.end()) value_error("harmonic " + std::to_string(harmonic) + " was not solved");
    return static_cast<int>(it - h.begin());
  }
};

PySolution make_solution(std::shared_ptr<const CaseDefinition> def,
                         std::shared_ptr<const PreparedModel> model,
                         std::shared_ptr<const SolvedCase> solved) {
  PySolution s{std::move(def), std::move(model), std::move(solved), {}, {}};
  for (size_t b = 0; b < s.model->bodies.size(); ++b) {
    for (const auto& [key, g] : s.model->bodies[b].master_dof)
      s.dofs.push_back({static_cast<int>(b), key.first, key.second, g});
  }
  std::map<int, int> count;
  for (const PreparedPair& p : s.model->pair_info) s.pair_in_contact.push_back(count[p.contact]++);
  return s;
}

template <typename T>
py::array_t<T> array1(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

void require_stability(const PySolution& s, const std::string& what) {
  if (!s.definition->analysis.stability)
    value_error(what + ": the case was solved without analysis.stability (set_analysis(" +
                "stability=True) before solve())");
}

py::array_t<double> per_point(const PySolution& s, double (*f)(const FrequencyPoint&)) {
  std::vector<double> v;
  for (const FrequencyPoint& p : s.points()) v.push_back(f(p));
  return array1(v);
}

// (points, pairs) array of a cycle statistic.
py::array_t<double> per_pair(const PySolution& s, double CycleStatistics::*field) {
  const size_t np = s.num_points(), nq = s.model->pairs.size();
  py::array_t<double> a({np, nq});
  auto r = a.mutable_unchecked<2>();
  for (size_t i = 0; i < np; ++i) {
    for (size_t q = 0; q < nq; ++q) {
      const auto& pairs = s.points()[i].pairs;
      r(i, q) = q < pairs.size() ? pairs[q].cycle.*field : std::nan("");
    }
  }
  return a;
}

// (points, pairs, 3, harmonics) complex contact forces; rows a pair does not have are NaN.
py::array_t<std::complex<double>> pair_forces(const PySolution& s, bool global) {
  const size_t np = s.num_points(), nq = s.model->pairs.size(), nh = s.num_harmonics();
  py::array_t<std::complex<double>> a({np, nq, size_t{3}, nh});
  auto r = a.mutable_unchecked<4>();
  const std::complex<double> nan(std::nan(""), std::nan(""));
  for (size_t i = 0; i < np; ++i) {
    for (size_t q = 0; q < nq; ++q) {
      const auto& pairs = s.points()[i].pairs;
      const Eigen::MatrixXcd* f = nullptr;
      if (q < pairs.size()) f = global ? &pairs[q].force_global : &pairs[q].force_local;
      for (Eigen::Index row = 0; row < 3; ++row) {
        for (size_t h = 0; h < nh; ++h) {
          const bool have =
              f != nullptr && row < f->rows() && static_cast<Eigen::Index>(h) < f->cols();
          r(i, q, row, h) = have ? (*f)(row, static_cast<Eigen::Index>(h)) : nan;
        }
      }
    }
  }
  return a;
}

double point_energy(const FrequencyPoint& p) {
  double e = 0;
  for (const PairResponse& r : p.pairs) e += r.cycle.dissipated_energy;
  return e;
}

// ------------------------------------------------------------------------------------------
// Docstrings (docs/python.md is made from them: scripts in docs/python.md say how).

constexpr const char* kModuleDoc = R"(stickslip: friction-damped structures from Python.

A case (read from a YAML case file, or built from numpy/scipy matrices) is changed from
Python, solved by multi-harmonic balance with friction contact (solve), and recovered on the
full finite-element bodies (Solution.recover). SI units; frequencies in Hz; complex harmonics
X_k = a_k - i b_k, so x(t) = Re sum_k X_k exp(i k Omega t) (docs/conventions.md).

Errors: bad input raises stickslip.InvalidInput (a ValueError) whose text names the file, the
line and the key ("case.yaml:31: contacts.joint.per_pair.kt: ..."); wrong argument types raise
TypeError. solve() and recover() release the GIL, so a thread pool runs a study in parallel.)";

constexpr const char* kReadCaseDoc = R"(read_case(path) -> Case

Reads and checks a case file (docs/case-file.md); relative paths inside it are resolved against
its folder. Raises InvalidInput (ValueError) naming the file, line and key of a problem.)";

constexpr const char* kCaseDoc =
    R"(A case: what a case file says, as data that Python can read and change.

Case(title="") makes an empty case to fill with add_body, add_contact, add_excitation,
set_damping and set_analysis; read_case(path) reads one from YAML. Values are read and changed
by key path:
  case.get("contacts.joint.per_pair.preload")  case.set("contacts.joint.per_pair.preload", 80.0)
Key paths are those of a case file's `study` (docs/case-file.md), plus shorthands and the
analysis keys:
  contacts.<name>.<block>.<key>   kt, kn, mu, preload, k, k1, k3 (block: per_pair, total or
                                  per_area, as the contact gives them); contacts.<name>.<key> and
                                  contacts[<i>].<key> take the contact's block; contacts.<name>.gap
  excitation[<i>].amplitude       N
  damping.alpha, damping.beta     C = alpha M + beta K
  materials.<name>.youngs_modulus | poisson_ratio | density
  bodies.<name>.modal_damping_ratio
  static_loads[<i>].force | total_force | pressure
  analysis.frequency.start_hz | stop_hz | step_hz | around_mode | half_width_hz | min_step_hz |
  max_step_hz, analysis.harmonics (H: harmonics 1..H), analysis.time_samples,
  analysis.tolerance, analysis.max_iterations, analysis.max_points
set() checks the key's rule (kt > 0, mu >= 0, ...) and raises InvalidInput otherwise.)";

constexpr const char* kSolutionDoc = R"(The frequency response of a solved case.

Arrays are numpy copies, one row per frequency point (P points, Q contact pairs, H output
harmonics in `harmonics`, harmonic 0 first):
  frequencies_hz (P), omega (P, rad/s), converged (P, bool), iterations (P),
  residual (P, m: ||R||), residual_relative (P: ||R|| / the point's scale; Newton stops below
  analysis.tolerance), dissipated_energy (P, J per cycle, all pairs),
  master (P, D, H complex, m: the physical master DOFs listed by master_dofs),
  contact_forces (P, Q, 3, H complex, N: force on node B, global x, y, z; A gets the negative),
  contact_forces_local (P, Q, 3, H complex: rows t1, t2, n of each pair's frame; a 1D law
  fills row 0, NaN elsewhere), stick, slip, separation (P, Q: fractions of the cycle),
  pair_energy (P, Q, J per cycle; raw: a stuck pair's round-off of about 1e-21 J is kept,
  which the program's CSV files write as 0), static_mismatch, static_warning and
  aft_fallback_pairs (P: as points.csv), and with analysis.stability stable (P, bool) and
  floquet_multiplier (P).
pairs lists each pair's contact, pair (index within its contact), node_a, node_b.
to_dict() gives the per-point columns as a dict of 1-D arrays (pandas.DataFrame(s.to_dict())).)";

}  // namespace
}  // namespace stickslip

PYBIND11_MODULE(stickslip, m) {
  using namespace stickslip;
  m.doc() = kModuleDoc;
  m.attr("__version__") = STICKSLIP_VERSION;

  // InvalidInput -> stickslip.InvalidInput, a ValueError with what(): "file:line: key: message".
  py::register_exception<InvalidInput>(m, "InvalidInput", PyExc_ValueError);
  // Leaked on purpose: the warning sink below may run until the interpreter ends.
  auto* stickslip_warning = new py::object(py::reinterpret_steal<py::object>(
      PyErr_NewExceptionWithDoc("stickslip.StickslipWarning",
                                "A warning of model building (input the model does not use, ...).",
                                PyExc_UserWarning, nullptr)));
  m.attr("StickslipWarning") = *stickslip_warning;
  // Warnings of model building reach Python's warnings module (GIL re-acquired: they come from
  // solves running without it). An error raised by a warnings filter is reported as unraisable.
  set_model_warning_sink([stickslip_warning](const std::string& text) {
    if (!Py_IsInitialized()) return;
    py::gil_scoped_acquire acquire;
    if (PyErr_WarnEx(stickslip_warning->ptr(), text.c_str(), 1) != 0) {
      py::error_already_set e;
      e.discard_as_unraisable("stickslip warning");
    }
  });
  py::module_::import("atexit").attr("register")(
      py::cpp_function([]() { set_model_warning_sink(nullptr); }));

  m.def(
      "read_case",
      [](const std::string& path) {
        PyCase c;
        c.definition = read_case_file(path);
        return c;
      },
      "path"_a, kReadCaseDoc);

  m.def("contact_laws", &contact_law_names,
        "contact_laws() -> list of str\n\nThe contact laws a contact may use (friction, jenkins, "
        "gap, cubic, linear, ...).");

  py::class_<PyCase>(m, "Case", kCaseDoc)
      .def(py::init([](const std::string& title) {
             PyCase c;
             c.definition.file = "<python case>";
             c.definition.title = title;
             return c;
           }),
           "title"_a = "")
      .def_property_readonly(
          "file", [](const PyCase& c) { return c.definition.file; },
          "The case file read (or '<python case>').")
      .def_property(
          "title", [](const PyCase& c) { return c.definition.title; },
          [](PyCase& c, const std::string& t) { c.definition.title = t; }, "The case's title.")
      .def_property_readonly(
          "bodies",
          [](const PyCase& c) {
            std::vector<std::string> names;
            for (const auto& [name, body] : c.definition.bodies) names.push_back(name);
            return names;
          },
          "Names of the bodies.")
      .def_property_readonly(
          "contacts",
          [](const PyCase& c) {
            std::vector<std::string> names;
            for (const ContactDefinition& d : c.definition.contacts) names.push_back(d.name);
            return names;
          },
          "Names of the contacts, in order (contacts[i] in key paths).")
      .def_property_readonly(
          "analysis",
          [](const PyCase& c) {
            py::dict d;
            const AnalysisDefinition& a = c.definition.analysis;
            const FrequencyDefinition& f = a.frequency;
            if (f.kind == FrequencyDefinition::Kind::kRange) {
              d["start_hz"] = f.start_hz;
              d["stop_hz"] = f.stop_hz;
            } else {
              d["around_mode"] = f.around_mode;
              d["half_width_hz"] = f.half_width_hz;
            }
            d["step_hz"] = f.step_hz;
            d["sweep"] = f.downward ? "down" : "up";
            d["method"] = case_name(a.method);
            d["harmonics"] = a.harmonics;
            d["time_samples"] = a.time_samples;
            d["aft"] = case_name(a.aft);
            d["static"] = case_name(a.static_coupling);
            d["tolerance"] = a.tolerance;
            d["max_iterations"] = a.max_iterations;
            d["max_points"] = a.max_points;
            d["initial_guess"] = case_name(a.initial_guess);
            d["predictor"] = case_name(a.predictor);
            d["stability"] = a.stability;
            return d;
          },
          "The analysis settings as a dict (a copy: change them with set_analysis or set).")
      .def_property_readonly(
          "frf",
          [](const PyCase& c) {
            py::list out;
            for (const ResponseDofDefinition& r : c.definition.output.frf)
              out.append(py::make_tuple(r.body, r.node, std::string(1, "xyz"[r.direction])));
            return out;
          },
          "The case's output.frf DOFs, (body, node id, axis): the responses its plots show.")
      .def_property_readonly(
          "study",
          [](const PyCase& c) -> py::object {
            if (!c.definition.study.active()) return py::none();
            return py::dict("parameter"_a = c.definition.study.parameter,
                            "values"_a = c.definition.study.values);
          },
          "The case file's study block, {parameter, values}, or None. solve() solves the case's "
          "own values and does not run the study: loop over it in Python (set, solve).")
      .def(
          "get",
          [](const PyCase& c, const std::string& path) { return get_value(c.definition, path); },
          "path"_a,
          "get(path) -> float\n\nThe value at a key path (see Case). InvalidInput for a path the "
          "case does not have.")
      .def(
          "set",
          [](PyCase& c, const std::string& path, double value) {
            set_value(c.definition, path, value);
          },
          "path"_a, "value"_a,
          "set(path, value)\n\nSets the value at a key path (see Case), checking its rule "
          "(InvalidInput otherwise).")
      .def(
          "copy", [](const PyCase& c) { return PyCase(c); },
          "copy() -> Case\n\nAn independent copy of the values; it shares this case's cache of "
          "meshes and reductions (a study changes the copies and solves them, the bodies are "
          "reduced once).")
      .def("__repr__",
           [](const PyCase& c) {
             return "<stickslip.Case '" + c.definition.title + "' (" + c.definition.file +
                    "): " + std::to_string(c.definition.bodies.size()) + " bodies, " +
                    std::to_string(c.definition.contacts.size()) + " contacts>";
           })
      .def("__copy__", [](const PyCase& c) { return PyCase(c); })
      .def(
          "__deepcopy__", [](const PyCase& c, py::dict) { return PyCase(c); }, "memo"_a)
      .def(
          "describe", [](const PyCase& c) { return describe_case(c.definition); },
          "describe() -> str\n\nThe case as canonical YAML with every default filled in (bodies "
          "given by arrays appear without their matrices).")
      .def(
          "set_analysis",
          [](PyCase& c, py::kwargs kwargs) {
            CaseDefinition def = c.definition;  // all or nothing
            AnalysisDefinition& a = def.analysis;
            for (const auto& [k, v] : kwargs) {
              const std::string key = k.cast<std::string>();
              const std::string path = "set_analysis(" + key + ")";
              const auto text = [&](const std::vector<std::string>& allowed) {
                if (!py::isinstance<py::str>(v)) type_error(path + ": expected a string");
                const std::string s = v.cast<std::string>();
                if (std::find(allowed.begin(), allowed.end(), s) == allowed.end()) {
                  std::string list;
                  for (const std::string& x : allowed) list += (list.empty() ? "" : ", ") + x;
                  throw InvalidInput({def.file, 0, path}, "'" + s + "': give one of " + list);
                }
                return s;
              };
              if (key == "method") {
                a.method = text({"stepped", "continuation"}) == "stepped"
                               ? SweepMethod::kStepped
                               : SweepMethod::kContinuation;
              } else if (key == "aft") {
                const std::string s = text({"event", "sampled", "event_planar"});
                a.aft = s == "event"     ? AftChoice::kEvent
                        : s == "sampled" ? AftChoice::kSampled
                                         : AftChoice::kEventPlanar;
                a.aft_given = true;
              } else if (key == "static") {
                a.static_coupling = text({"uncoupled", "coupled"}) == "coupled"
                                        ? StaticChoice::kCoupled
                                        : StaticChoice::kUncoupled;
              } else if (key == "initial_guess") {
                a.initial_guess = text({"stuck", "free"}) == "free" ? InitialGuessChoice::kFree
                                                                    : InitialGuessChoice::kStuck;
              } else if (key == "predictor") {
                a.predictor = text({"secant", "previous"}) == "previous"
                                  ? PredictorChoice::kPrevious
                                  : PredictorChoice::kSecant;
              } else if (key == "sweep") {
                a.frequency.downward = text({"up", "down"}) == "down";
              } else if (key == "stability") {
                if (!py::isinstance<py::bool_>(v)) type_error(path + ": expected True or False");
                a.stability = v.cast<bool>();
              } else if (key == "harmonics" && py::isinstance<py::sequence>(v)) {
                std::vector<int> h;
                for (const py::handle x : v) {
                  const long long k = integer_argument(x, path);
                  h.push_back(k < 0 || k > kMaxHarmonic ? -1 : static_cast<int>(k));
                }
                for (size_t i = 0; i < h.size(); ++i) {
                  if (h[i] < 1 || h[i] > kMaxHarmonic || (i > 0 && h[i] <= h[i - 1]))
                    throw InvalidInput({def.file, 0, path},
                                       "harmonics are increasing integers in [1, " +
                                           std::to_string(kMaxHarmonic) + "]");
                }
                if (h.empty()) throw InvalidInput({def.file, 0, path}, "no harmonics");
                a.harmonics = h;
              } else if (std::find(kAnalysisKeys.begin(), kAnalysisKeys.end(), key) !=
                         kAnalysisKeys.end()) {
                set_analysis_value(def, key, number_argument(v, path), path);
              } else {
                std::string keys =
                    "method, aft, static, initial_guess, predictor, sweep, stability";
                for (const std::string& x : kAnalysisKeys) keys += ", " + x;
                type_error("set_analysis() got an unexpected keyword argument '" + key +
                           "' (keywords: " + keys + ")");
              }
            }
            c.definition = std::move(def);
          },
          R"(set_analysis(**settings)

Changes the analysis settings (docs/case-file.md `analysis`): start_hz, stop_hz, step_hz
(or around_mode, half_width_hz: a window around a mode of the stuck assembly), sweep ('up' |
'down'), method ('stepped' | 'continuation'), min_step_hz, max_step_hz, max_points
(continuation), harmonics (H: 1..H, or a list of increasing harmonics), time_samples (>= 2(2H+1)),
aft ('event' | 'sampled' | 'event_planar'), static ('uncoupled' | 'coupled'), tolerance,
max_iterations, initial_guess ('stuck' | 'free'), predictor ('secant' | 'previous'),
stability (True: Hill's method at every converged point, Solution.stable and
floquet_multiplier). All or nothing: a bad value raises and leaves the case unchanged.)")
      .def(
          "set_damping",
          [](PyCase& c, double alpha, double beta) {
            if (!(alpha >= 0) || !(beta >= 0) || !std::isfinite(alpha) || !std::isfinite(beta))
              throw InvalidInput({c.definition.file, 0, "set_damping"},
                                 "alpha = " + number_text(alpha) + ", beta = " + number_text(beta) +
                                     ": both finite and >= 0");
            c.definition.damping.alpha = alpha;
            c.definition.damping.beta = beta;
          },
          "alpha"_a = 0.0, "beta"_a = 0.0,
          "set_damping(alpha=0, beta=0)\n\nDamping C = alpha M + beta K (alpha in 1/s, beta in s).")
      .def(
          "add_body",
          [](PyCase& c, const std::string& name, const py::object& K, const py::object& M,
             const py::object& dofs, double modal_damping_ratio) {
            if (name.empty() || name == "ground" || name.find('/') != std::string::npos)
              value_error("add_body: name '" + name + "' (not empty, not 'ground', no '/')");
            if (!(modal_damping_ratio >= 0 && modal_damping_ratio < 1))
              value_error("add_body: modal_damping_ratio = " + number_text(modal_damping_ratio) +
                          ": in [0, 1)");
            auto body = std::make_shared<ReducedBody>();
            body->K = matrix_argument(K, "add_body: K");
            body->M = matrix_argument(M, "add_body: M");
            if (body->K.rows() != body->M.rows())
              value_error("add_body: K is " + std::to_string(body->K.rows()) + " x " +
                          std::to_string(body->K.rows()) + ", M " + std::to_string(body->M.rows()) +
                          " x " + std::to_string(body->M.rows()));
            body->dofs = dofs_argument(dofs, body->K.rows());
            const auto it = c.definition.bodies.find(name);
            if (it == c.definition.bodies.end()) {
              BodyDefinition b;
              b.source = BodyDefinition::Source::kReduced;
              b.modal_damping_ratio = modal_damping_ratio;
              c.definition.bodies[name] = b;
            } else {
              it->second.modal_damping_ratio = modal_damping_ratio;
            }
            c.given[name] = body;
          },
          "name"_a, "K"_a, "M"_a, "dofs"_a, "modal_damping_ratio"_a = 0.0,
          R"(add_body(name, K, M, dofs, modal_damping_ratio=0)

A body given by its reduced stiffness K and mass M (n x n; numpy arrays or scipy.sparse
matrices; SI units), e.g. exported by another FE code. dofs: n entries, (node_id, direction)
for a physical DOF (direction 'x', 'y', 'z' or 0, 1, 2; node ids positive, as contacts and
excitation name them) or None for a modal (generalised) DOF. K must be symmetric positive
semi-definite and M positive definite (checked when the model is built). Naming a body of a
case file given by a mesh replaces its Craig-Bampton reduction (its mesh is kept for the
recovery: physical DOFs then name its mesh's node ids).)")
      .def(
          "add_contact",
          [](PyCase& c, const std::string& name, const std::string& law, const std::string& body_a,
             const std::string& body_b, const std::vector<std::vector<int>>& pairs,
             const py::object& normal, const py::object& t1, const py::object& direction,
             std::optional<double> kt, std::optional<double> kn, std::optional<double> mu,
             std::optional<double> preload, std::optional<double> k, std::optional<double> k1,
             std::optional<double> k3, std::optional<double> gap, bool total) {
            CaseDefinition& def = c.definition;
            const std::string where = "add_contact(" + name + ")";
            const auto fail = [&](const std::string& rule) {
              throw InvalidInput({def.file, 0, where}, rule);
            };
            if (name.empty()) fail("a contact needs a name");
            for (const ContactDefinition& d : def.contacts) {
              if (d.name == name) fail("contact '" + name + "' exists already");
            }
            if (!def.bodies.count(body_a)) fail("no body '" + body_a + "' (body_a)");
            if (body_b != "ground" && !def.bodies.count(body_b))
              fail("no body '" + body_b + "' (body_b; or 'ground')");
            if (find_contact_laws(law).empty()) {
              std::string names;
              for (const std::string& n : contact_law_names())
                names += (names.empty() ? "" : ", ") + n;
              fail("unknown law '" + law + "' (laws: " + names + ")");
            }
            ContactDefinition d;
            d.name = name;
            d.law = law;
            d.body_a = body_a;
            d.body_b = body_b;
            d.uses_frame = !normal.is_none();
            if (d.uses_frame == !direction.is_none())
              fail(
                  "give `normal` (a law in a frame: friction, 3D linear) or `direction` (a 1D "
                  "law), "
                  "one of them");
            bool frame_law = false, line_law = false;
            for (const ContactLaw* l : find_contact_laws(law))
              (l->uses_frame ? frame_law : line_law) = true;
            if (d.uses_frame && !frame_law)
              fail("law " + law + " acts along a `direction`, not in a frame");
            if (!d.uses_frame && !line_law) fail("law " + law + " acts in a frame: give `normal`");
            if (d.uses_frame) {
              d.normal = direction_argument(normal, where + " normal");
              if (!t1.is_none()) d.t1 = direction_argument(t1, where + " t1");
            } else {
              d.direction = direction_argument(direction, where + " direction");
            }
            if (pairs.empty()) fail("no pairs");
            for (const std::vector<int>& p : pairs) {
              if (p.size() != 2 || p[0] <= 0 || p[1] < 0 || (p[1] == 0) != (body_b == "ground"))
                fail("pairs are (node id on A, node id on B), ids > 0; node B = 0 for the ground");
              d.pairs.push_back({p[0], p[1]});
            }
            const ContactLaw& l = contact_law(law, d.uses_frame);
            d.parameters_given = total ? ContactDefinition::Parameters::kTotal
                                       : ContactDefinition::Parameters::kPerPair;
            const std::map<std::string, std::optional<double>> given = {
                {"kt", kt}, {"kn", kn}, {"mu", mu}, {"preload", preload},
                {"k", k},   {"k1", k1}, {"k3", k3}};
            for (const auto& [key, value] : given) {
              if (!value) continue;
              const LawParameter* p = l.parameter(key);
              if (p == nullptr) fail("'" + key + "' is not a parameter of law " + law);
              const double v = *value;
              const bool ok =
                  std::isfinite(v) && (p->rule == LawParameter::Rule::kAny ||
                                       (p->rule == LawParameter::Rule::kPositive ? v > 0 : v >= 0));
              if (!ok)
                fail(key + " = " + number_text(v) + ": must be " +
                     (p->rule == LawParameter::Rule::kPositive ? "> 0" : ">= 0"));
              *d.parameters.field(key) = v;
            }
            if (gap) {
              if (!l.has_gap) fail("law " + law + " has no gap");
              if (preload) fail("give either a preload or a gap");
              if (!(*gap >= 0) || !std::isfinite(*gap))
                fail("gap = " + number_text(*gap) + ": must be >= 0");
              d.gap = *gap;
            }
            for (const std::string& key : l.required_keys()) {
              if (key == "preload" && gap) continue;
              if (!given.count(key) || !given.at(key)) fail("law " + law + " needs '" + key + "'");
            }
            def.contacts.push_back(d);
          },
          "name"_a, "law"_a, "body_a"_a, "body_b"_a = "ground", "pairs"_a, "normal"_a = py::none(),
          "t1"_a = py::none(), "direction"_a = py::none(), "kt"_a = py::none(), "kn"_a = py::none(),
          "mu"_a = py::none(), "preload"_a = py::none(), "k"_a = py::none(), "k1"_a = py::none(),
          "k3"_a = py::none(), "gap"_a = py::none(), "total"_a = false,
          R"(add_contact(name, law, body_a, body_b="ground", pairs, normal=None, t1=None,
            direction=None, kt=None, kn=None, mu=None, preload=None, k=None, k1=None, k3=None,
            gap=None, total=False)

A contact between listed node pairs: pairs = [(node on A, node on B), ...] (node B = 0 for the
ground). law: one of contact_laws() (friction: kt, kn, mu, preload or gap; jenkins: kt, mu,
preload; gap: kn, preload or gap; cubic: k1, k3; linear: k, or kt, kn in a frame). A law in a
frame takes normal (out of A into B; 'x', '-z' or 3 numbers) and optionally t1; a 1D law takes
direction. Values are per pair (N/m, N, m), or totals split equally over the pairs with
total=True (mu and gap are not split). docs/case-file.md `contacts` has the laws.)")
      .def(
          "add_excitation",
          [](PyCase& c, const std::string& body, int node, const py::object& direction,
             double amplitude, double phase_deg, int harmonic) {
            CaseDefinition& def = c.definition;
            const std::string where = "add_excitation(" + body + ")";
            const auto fail = [&](const std::string& rule) {
              throw InvalidInput({def.file, 0, where}, rule);
            };
            if (!def.bodies.count(body)) fail("no body '" + body + "'");
            if (node <= 0) fail("node " + std::to_string(node) + ": node ids are positive");
            if (!std::isfinite(amplitude) || amplitude < 0)
              fail("amplitude = " + number_text(amplitude) + ": finite and >= 0 (N)");
            if (!std::isfinite(phase_deg)) fail("phase_deg is not finite");
            if (harmonic < 0 || harmonic > kMaxHarmonic)
              fail("harmonic " + std::to_string(harmonic));
            ExcitationDefinition e;
            e.body = body;
            e.nodes.ids = {node};
            e.harmonic = harmonic;
            e.by_direction = true;
            e.direction = direction_argument(direction, where + " direction");
            e.amplitude = amplitude;
            e.phase_deg = phase_deg;
            const std::complex<double> a = std::polar(amplitude, phase_deg * kPi / 180.0);
            for (size_t i = 0; i < 3; ++i) e.force[i] = a * e.direction[i];
            def.excitation.push_back(e);
          },
          "body"_a, "node"_a, "direction"_a, "amplitude"_a, "phase_deg"_a = 0.0, "harmonic"_a = 1,
          R"(add_excitation(body, node, direction, amplitude, phase_deg=0, harmonic=1)

A harmonic force amplitude*cos(k Omega t + phase) (N) along direction ('x', '-z' or 3 numbers)
on one node; harmonic k = 0 is a static force. It becomes excitation[i] in key paths.)")
      .def(
          "stuck_frequencies_hz",
          [](const PyCase& c) {
            const CaseDefinition def = c.definition;
            if (def.bodies.empty())
              throw InvalidInput(def.where("bodies"), "the case has no bodies (add_body)");
            const auto given = c.given;
            Eigen::VectorXd f;
            {
              py::gil_scoped_release release;
              const auto model = build_model(def, given, *c.cache, nullptr);
              f = stuck_frequencies_hz(*model, def);
            }
            return array1(std::vector<double>(f.data(), f.data() + f.size()));
          },
          "stuck_frequencies_hz() -> array\n\nNatural frequencies (Hz, ascending) of the "
          "assembled reduced model with every contact stuck (friction pairs as springs kt, kt, "
          "kn), "
          "as `stickslip modes` lists them and around_mode counts them. Builds the model (cached); "
          "the GIL is released.")
      .def(
          "solve",
          [](const PyCase& c, const py::object& progress) {
            if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
              type_error("solve: progress must be callable (text, fraction) or None");
            check_solvable(c);
            auto def = std::make_shared<const CaseDefinition>(c.definition);
            const auto given = c.given;
            const std::shared_ptr<SharedCache> cache = c.cache;
            ProgressRelay relay(progress.is_none() ? nullptr : &progress);
            std::shared_ptr<const PreparedModel> model;
            std::shared_ptr<const SolvedCase> solved;
            {
              py::gil_scoped_release release;
              const ProgressFn stage = relay.stage();
              model = build_model(*def, given, *cache, stage);
              SweepProgress sweep;
              sweep.start = [&relay](const std::string& label, int points) {
                relay(label + (points > 0 ? ": " + std::to_string(points) + " points" : ""), 0.0);
              };
              sweep.on_point = [&relay](const ContinuationProgress& p) {
                relay("point " + std::to_string(p.points) + " at " +
                          number_text(p.lambda / (2 * kPi)) + " Hz" +
                          (p.converged ? "" : " (not converged)"),
                      p.fraction);
              };
              solved = std::make_shared<SolvedCase>(solve_case(*model, *def, stage, &sweep));
            }
            relay.rethrow();
            return make_solution(def, model, solved);
          },
          "progress"_a = py::none(),
          R"(solve(progress=None) -> Solution

Builds the model (bodies reduced by Craig-Bampton, or taken from add_body's matrices; reductions
are cached and shared with copies of this case) and computes the frequency response by
harmonic balance. The GIL is released meanwhile. progress, when given, is called as
progress(text, fraction) with the GIL held: fraction None for a stage line ("reduce beam1 ..."),
a number in [0, 1] after each frequency point. An exception raised by progress is re-raised when
the solve returns. Points that do not converge are kept with converged False (check
Solution.converged); bad input raises InvalidInput.)");

  py::class_<PySolution>(m, "Solution", kSolutionDoc)
      .def_property_readonly(
          "frequencies_hz",
          [](const PySolution& s) {
            return per_point(s, [](const FrequencyPoint& p) { return p.omega / (2 * kPi); });
          },
          "Frequency of each point, Hz (P).")
      .def_property_readonly(
          "omega",
          [](const PySolution& s) {
            return per_point(s, [](const FrequencyPoint& p) { return p.omega; });
          },
          "Angular frequency of each point, rad/s (P).")
      .def_property_readonly(
          "converged",
          [](const PySolution& s) {
            std::vector<bool> v;
            for (const FrequencyPoint& p : s.points()) v.push_back(p.converged);
            py::array_t<bool> a(static_cast<py::ssize_t>(v.size()));
            std::copy(v.begin(), v.end(), a.mutable_data());
            return a;
          },
          "Whether each point converged (P, bool).")
      .def_property_readonly(
          "iterations",
          [](const PySolution& s) {
            std::vector<int> v;
            for (const FrequencyPoint& p : s.points()) v.push_back(p.iterations);
            return array1(v);
          },
          "Newton iterations of each point (P, int).")
      .def_property_readonly(
          "residual",
          [](const PySolution& s) {
            return per_point(s, [](const FrequencyPoint& p) { return p.residual_norm; });
          },
          "||R|| of the harmonic-balance equations at each point, m (P).")
      .def_property_readonly(
          "residual_relative",
          [](const PySolution& s) {
            return per_point(
                s, [](const FrequencyPoint& p) { return p.residual_norm / p.residual_scale; });
          },
          "||R|| over the point's residual scale (P): below analysis.tolerance when converged.")
      .def_property_readonly(
          "stable",
          [](const PySolution& s) {
            require_stability(s, "stable");
            std::vector<bool> v;
            for (const FrequencyPoint& p : s.points())
              v.push_back(p.stability_computed && p.floquet.stable);
            py::array_t<bool> a(static_cast<py::ssize_t>(v.size()));
            std::copy(v.begin(), v.end(), a.mutable_data());
            return a;
          },
          "Whether Hill's method finds each point stable, every Floquet exponent's real part <= "
          "1e-7 Omega (P, bool; False at points that did not converge: see floquet_multiplier). "
          "Needs analysis.stability (set_analysis(stability=True)), else raises ValueError.")
      .def_property_readonly(
          "floquet_multiplier",
          [](const PySolution& s) {
            require_stability(s, "floquet_multiplier");
            return per_point(s, [](const FrequencyPoint& p) {
              return p.stability_computed ? p.floquet.max_multiplier
                                          : std::numeric_limits<double>::quiet_NaN();
            });
          },
          "The largest Floquet multiplier's modulus exp(max Re mu 2 pi/Omega) at each point (P; "
          "> 1: a perturbation grows each period; NaN at points that did not converge), as "
          "points.csv. Needs analysis.stability, else raises ValueError.")
      .def_property_readonly(
          "floquet_unplaced",
          [](const PySolution& s) {
            require_stability(s, "floquet_unplaced");
            return per_point(s, [](const FrequencyPoint& p) {
              return p.stability_computed ? static_cast<double>(p.floquet.unplaced_exponents)
                                          : std::numeric_limits<double>::quiet_NaN();
            });
          },
          "The number of exponent families Hill's selection found no centred member for at each "
          "point (P; 0 normally; > 0: the modes kept for Hill do not resolve them, see "
          "docs/conventions.md Stability; NaN at points that did not converge), as points.csv "
          "floquet_unplaced. Needs analysis.stability, else raises ValueError.")
      .def_property_readonly(
          "dissipated_energy", [](const PySolution& s) { return per_point(s, &point_energy); },
          "Friction energy per cycle summed over the pairs, J (P).")
      .def_property_readonly(
          "static_mismatch",
          [](const PySolution& s) {
            return per_point(s, [](const FrequencyPoint& p) { return p.static_mismatch; });
          },
          "static: uncoupled: the largest pair mismatch ||mean f - f0|| / scale of each point "
          "(P; 0 with static: coupled; docs/output-files.md points.csv).")
      .def_property_readonly(
          "static_warning",
          [](const PySolution& s) {
            std::vector<bool> v;
            for (const FrequencyPoint& p : s.points()) v.push_back(p.static_warning);
            py::array_t<bool> a(static_cast<py::ssize_t>(v.size()));
            std::copy(v.begin(), v.end(), a.mutable_data());
            return a;
          },
          "Whether the frozen static state is flagged wrong at each point (P, bool; static: "
          "uncoupled; use static: coupled then).")
      .def_property_readonly(
          "aft_fallback_pairs",
          [](const PySolution& s) {
            std::vector<int> v;
            for (const FrequencyPoint& p : s.points()) {
              int n = 0;
              for (const PairResponse& r : p.pairs) n += r.cycle.aft_fallback ? 1 : 0;
              v.push_back(n);
            }
            return array1(v);
          },
          "Pairs whose cycle the event AFT left to the sampled AFT at each point (P, int).")
      .def_property_readonly(
          "harmonics", [](const PySolution& s) { return array1(s.solved->response.harmonics); },
          "The output harmonics, 0 first: the last axis of master and the force arrays.")
      .def_property_readonly(
          "completed", [](const PySolution& s) { return s.solved->response.completed; },
          "Whether the sweep covered the whole window.")
      .def_property_readonly(
          "message", [](const PySolution& s) { return s.solved->response.message; },
          "How the sweep ended, which points failed.")
      .def_property_readonly(
          "window",
          [](const PySolution& s) {
            const SweepWindow& w = s.solved->window;
            return py::dict("start_hz"_a = w.start_hz, "stop_hz"_a = w.stop_hz,
                            "stuck_mode"_a = w.stuck_mode, "stuck_mode_hz"_a = w.stuck_mode_hz);
          },
          "The swept window: start_hz, stop_hz; stuck_mode (1-based, 0 when given in Hz) and "
          "stuck_mode_hz with around_mode.")
      .def_property_readonly(
          "seconds",
          [](const PySolution& s) {
            return py::dict("prepare"_a = s.model->seconds_prepare,
                            "solve"_a = s.solved->seconds_solve);
          },
          "Wall-clock seconds of model building and of the sweep.")
      .def_property_readonly(
          "master_dofs",
          [](const PySolution& s) {
            py::list out;
            for (const PySolution::Dof& d : s.dofs)
              out.append(py::make_tuple(s.model->bodies[static_cast<size_t>(d.body)].name, d.node,
                                        std::string(1, "xyz"[d.direction])));
            return out;
          },
          "The physical master DOFs, (body, node id, axis), in the order of master's 2nd axis.")
      .def_property_readonly(
          "master",
          [](const PySolution& s) {
            const size_t np = s.num_points(), nd = s.dofs.size(), nh = s.num_harmonics();
            py::array_t<std::complex<double>> a({np, nd, nh});
            auto r = a.mutable_unchecked<3>();
            for (size_t i = 0; i < np; ++i) {
              const Eigen::MatrixXcd& x = s.points()[i].master;
              for (size_t j = 0; j < nd; ++j) {
                for (size_t h = 0; h < nh; ++h) {
                  const bool have =
                      x.rows() > s.dofs[j].global && static_cast<size_t>(x.cols()) > h;
                  r(i, j, h) = have ? x(s.dofs[j].global, static_cast<Eigen::Index>(h))
                                    : std::complex<double>(std::nan(""), std::nan(""));
                }
              }
            }
            return a;
          },
          "Harmonics of the physical master DOFs, m (P, D, H complex; D as master_dofs).")
      .def(
          "response",
          [](const PySolution& s, const std::string& body, int node, const py::object& direction,
             std::optional<int> harmonic) -> py::array {
            const int g = s.global_dof(body, node, direction);
            const size_t np = s.num_points(), nh = s.num_harmonics();
            if (harmonic) {
              const int h = s.harmonic_column(*harmonic);
              py::array_t<std::complex<double>> a(static_cast<py::ssize_t>(np));
              for (size_t i = 0; i < np; ++i) a.mutable_at(i) = s.points()[i].master(g, h);
              return a;
            }
            py::array_t<std::complex<double>> a({np, nh});
            auto r = a.mutable_unchecked<2>();
            for (size_t i = 0; i < np; ++i) {
              for (size_t h = 0; h < nh; ++h)
                r(i, h) = s.points()[i].master(g, static_cast<Eigen::Index>(h));
            }
            return a;
          },
          "body"_a, "node"_a, "direction"_a, "harmonic"_a = py::none(),
          "response(body, node, direction, harmonic=None) -> complex array\n\nThe harmonics of "
          "one master DOF: shape (P, H), or (P,) for one harmonic (harmonic=1: the first "
          "harmonic's complex amplitude, m).")
      .def_property_readonly(
          "pairs",
          [](const PySolution& s) {
            py::list out;
            for (size_t q = 0; q < s.model->pair_info.size(); ++q) {
              const PreparedPair& p = s.model->pair_info[q];
              out.append(py::dict(
                  "contact"_a = s.definition->contacts[static_cast<size_t>(p.contact)].name,
                  "pair"_a = s.pair_in_contact[q], "node_a"_a = p.node_a_id,
                  "node_b"_a = p.node_b_id));
            }
            return out;
          },
          "Per contact pair: contact, pair (0-based within its contact), node_a, node_b.")
      .def_property_readonly(
          "contact_forces", [](const PySolution& s) { return pair_forces(s, true); },
          "Force on node B of each pair, global x, y, z, N (P, Q, 3, H complex); A receives the "
          "negative.")
      .def_property_readonly(
          "contact_forces_local", [](const PySolution& s) { return pair_forces(s, false); },
          "Force on node B in each pair's frame t1, t2, n, N (P, Q, 3, H complex); a 1D law fills "
          "row 0, NaN elsewhere.")
      .def_property_readonly(
          "stick",
          [](const PySolution& s) { return per_pair(s, &CycleStatistics::stick_fraction); },
          "Fraction of the cycle each pair sticks (P, Q).")
      .def_property_readonly(
          "slip", [](const PySolution& s) { return per_pair(s, &CycleStatistics::slip_fraction); },
          "Fraction of the cycle each pair slips (P, Q).")
      .def_property_readonly(
          "separation",
          [](const PySolution& s) { return per_pair(s, &CycleStatistics::separation_fraction); },
          "Fraction of the cycle each pair is open (P, Q).")
      .def_property_readonly(
          "pair_energy",
          [](const PySolution& s) { return per_pair(s, &CycleStatistics::dissipated_energy); },
          "Friction energy per cycle of each pair, J (P, Q).")
      .def(
          "peak",
          [](const PySolution& s, const std::string& body, int node, const py::object& direction,
             int harmonic) {
            const int g = s.global_dof(body, node, direction);
            const int h = s.harmonic_column(harmonic);
            int best = -1;
            double amplitude = 0;
            for (size_t i = 0; i < s.num_points(); ++i) {
              const FrequencyPoint& p = s.points()[i];
              if (!p.converged) continue;
              const double a = std::abs(p.master(g, h));
              if (best < 0 || a > amplitude) {
                best = static_cast<int>(i);
                amplitude = a;
              }
            }
            if (best < 0)
              return py::dict("point"_a = py::none(), "frequency_hz"_a = py::none(),
                              "amplitude"_a = py::none());
            return py::dict(
                "point"_a = best,
                "frequency_hz"_a = s.points()[static_cast<size_t>(best)].omega / (2 * kPi),
                "amplitude"_a = amplitude);
          },
          "body"_a, "node"_a, "direction"_a, "harmonic"_a = 1,
          "peak(body, node, direction, harmonic=1) -> dict\n\nThe largest amplitude |X_k| of one "
          "master DOF over the converged points: point, frequency_hz, amplitude (m); None values "
          "when no point converged.")
      .def(
          "frf_peaks",
          [](const PySolution& s) {
            py::list out;
            for (const FrfPeak& p : frf_peaks(*s.definition, *s.model, s.solved->response)) {
              py::dict d("body"_a = p.dof.body, "node"_a = p.dof.node,
                         "axis"_a = std::string(1, "xyz"[p.dof.direction]));
              d["point"] = p.point < 0 ? py::object(py::none()) : py::object(py::int_(p.point));
              d["frequency_hz"] = p.frequency_hz;
              d["amplitude"] = p.amplitude_m;
              d["at_edge"] = p.at_edge;
              d["located"] = p.located;
              out.append(d);
            }
            return out;
          },
          "frf_peaks() -> list of dict\n\nPer output.frf DOF of the case (as the program's FRF "
          "plots and summary.json): body, node, axis, point (None: no converged point), "
          "frequency_hz, amplitude (|X| of the first dynamic harmonic, m), at_edge (the peak is "
          "the first or last converged point: the true peak may lie outside the window), located "
          "(a continuation located the maximum between its points: frequency_hz and amplitude "
          "are the located maximum's, point the largest sampled one).")
      .def(
          "recovery_points",
          [](const PySolution& s) {
            return recovery_points(*s.definition, *s.model, s.solved->response);
          },
          "recovery_points() -> list of int\n\nThe points the case's recovery.points selects "
          "(peak | all | none | frequencies), as the program recovers them.")
      .def(
          "to_dict",
          [](const PySolution& s) {
            py::dict d;
            const py::object self = py::cast(s);
            for (const char* key : {"frequencies_hz", "converged", "iterations", "residual",
                                    "residual_relative", "dissipated_energy"})
              d[key] = self.attr(key);
            if (s.definition->analysis.stability) {
              for (const char* key : {"stable", "floquet_multiplier", "floquet_unplaced"}) {
                d[key] = self.attr(key);
              }
            }
            const size_t nq = s.model->pairs.size();
            for (const char* key : {"stick", "slip", "separation"}) {
              const py::object a = self.attr(key);
              d[(std::string("mean_") + key).c_str()] =
                  nq > 0 ? py::object(a.attr("mean")("axis"_a = 1))
                         : py::object(py::module_::import("numpy").attr("full")(s.num_points(),
                                                                                std::nan("")));
            }
            for (const ResponseDofDefinition& r : s.definition->output.frf) {
              if (s.model->body_index(r.body) < 0) continue;
              const int g =
                  s.model->bodies[static_cast<size_t>(s.model->body_index(r.body))].global_dof(
                      r.node, r.direction);
              if (g < 0 || s.num_harmonics() < 2) continue;
              std::vector<double> v;
              for (const FrequencyPoint& p : s.points()) v.push_back(std::abs(p.master(g, 1)));
              d[("amplitude_" + r.body + "_" + std::to_string(r.node) + "_" + "xyz"[r.direction])
                    .c_str()] = array1(v);
            }
            return d;
          },
          "to_dict() -> dict\n\nThe per-point columns as 1-D arrays of equal length, for "
          "pandas.DataFrame: frequencies_hz, converged, iterations, residual, residual_relative, "
          "dissipated_energy, stable, floquet_multiplier and floquet_unplaced (with "
          "analysis.stability), "
          "mean_stick, mean_slip, mean_separation (over the pairs), and "
          "amplitude_<body>_<node>_<axis> (|X_1|, m) of each output.frf DOF of the case.")
      .def(
          "recover",
          [](const PySolution& s, long long point, const std::string& body, bool stresses) {
            const size_t i = s.point_index(point);
            const int b = s.model->body_index(body);
            if (b < 0) value_error("recover: no body '" + body + "'");
            const PreparedBody& pb = s.model->bodies[static_cast<size_t>(b)];
            if (!pb.from_mesh)
              value_error("recover: body '" + body +
                          "' is given by matrices: no full model to recover");
            const FrequencyPoint& p = s.points()[i];
            if (!p.converged)
              value_error("recover: point " + std::to_string(i) + " did not converge");
            RecoveredPoint r;
            std::vector<ComplexStressMatrix> sigma;
            StressEnvelope envelope;
            {
              py::gil_scoped_release release;
              BodyRecovery recovery(*s.definition, *s.model, b, {.stresses = stresses});
              r = recovery.recover(p, s.solved->response.harmonics);
              if (stresses) {
                sigma = recovery.stresses(r.displacement, s.solved->response.harmonics);
                envelope = stress_envelope(sigma, s.solved->response.harmonics);
              }
            }
            const size_t nn = static_cast<size_t>(pb.mesh.coordinates.cols());
            const size_t nh = s.num_harmonics();
            py::array_t<std::complex<double>> u({nh, nn, size_t{3}});
            auto ur = u.mutable_unchecked<3>();
            for (size_t h = 0; h < nh; ++h) {
              for (size_t n = 0; n < nn; ++n) {
                for (size_t d = 0; d < 3; ++d)
                  ur(h, n, d) = r.displacement(static_cast<Eigen::Index>(3 * n + d),
                                               static_cast<Eigen::Index>(h));
              }
            }
            py::array_t<double> xyz({nn, size_t{3}});
            auto xr = xyz.mutable_unchecked<2>();
            for (size_t n = 0; n < nn; ++n) {
              for (size_t d = 0; d < 3; ++d)
                xr(n, d) =
                    pb.mesh.coordinates(static_cast<Eigen::Index>(d), static_cast<Eigen::Index>(n));
            }
            py::dict out("body"_a = body, "point"_a = i, "frequency_hz"_a = p.omega / (2 * kPi),
                         "harmonics"_a = array1(s.solved->response.harmonics),
                         "node_ids"_a = array1(pb.mesh.node_ids), "coordinates"_a = xyz,
                         "displacement"_a = u,
                         "check_max_relative"_a = array1(r.check.max_relative),
                         "check_max_absolute"_a = array1(r.check.max_absolute),
                         "failed_harmonics"_a = r.summary.failed_harmonics);
            if (stresses) {
              py::array_t<std::complex<double>> st({nh, nn, size_t{6}});
              auto sr = st.mutable_unchecked<3>();
              for (size_t h = 0; h < nh; ++h) {
                for (size_t n = 0; n < nn; ++n) {
                  for (size_t c = 0; c < 6; ++c)
                    sr(h, n, c) =
                        sigma[h](static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(n));
                }
              }
              out["stress"] = st;
              const auto vec = [](const Eigen::VectorXd& v) {
                return array1(std::vector<double>(v.data(), v.data() + v.size()));
              };
              out["von_mises_max"] = vec(envelope.von_mises_max);
              out["von_mises_alternating"] = vec(envelope.von_mises_alternating);
              out["von_mises_mean"] = vec(envelope.von_mises_mean);
              out["max_principal_max"] = vec(envelope.max_principal_max);
            }
            return out;
          },
          "point"_a, "body"_a, "stresses"_a = true,
          R"(recover(point, body, stresses=True) -> dict

The full-model recovery of one body given by a mesh at one converged point (index into the
points; negative counts from the end), with the case's recovery.method (direct, modal,
expansion): the excitation and the harmonic contact forces applied to the full body, solved as
a linear harmonic problem (docs/conventions.md "Full-model recovery"). The GIL is released.
Returns: body, point, frequency_hz, harmonics (H), node_ids (N), coordinates (N, 3, m),
displacement (H, N, 3 complex, m), check_max_relative / check_max_absolute (H: the full-model
response at the master DOFs against the reduced nonlinear one), failed_harmonics; with
stresses also stress (H, N, 6 complex, Pa: xx, yy, zz, xy, xz, yz, nodal averages),
von_mises_max, von_mises_alternating, von_mises_mean, max_principal_max (N, Pa, over the
period).)")
      .def("__len__", &PySolution::num_points)
      .def("__repr__", [](const PySolution& s) {
        int converged = 0;
        for (const FrequencyPoint& p : s.points()) converged += p.converged ? 1 : 0;
        return "<stickslip.Solution: " + std::to_string(s.num_points()) + " points (" +
               std::to_string(converged) + " converged), " + std::to_string(s.model->pairs.size()) +
               " contact pairs>";
      });

  m.attr("__all__") = py::make_tuple("read_case", "Case", "Solution", "InvalidInput",
                                     "StickslipWarning", "contact_laws");
}

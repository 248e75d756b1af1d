#include "cli/results_files.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>

#include <fmt/core.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cli/progress.h"
#include "cli/summary_file.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

// A CSV file of ours (no quoting, ',' separated, one header line) read row by row; every error
// names the file and the line.
class CsvReader {
 public:
  CsvReader(const fs::path& path, const std::vector<std::string>& required, const std::string& hint)
      : path_(path.string()) {
    require_stage_file(path, hint);
    in_.open(path);
    if (!in_) throw InvalidInput({path_, 0, ""}, "cannot open the file");
    std::string header;
    if (!std::getline(in_, header)) fail("empty file (no header line)");
    line_ = 1;
    const std::vector<std::string> names = split(header);
    for (size_t i = 0; i < names.size(); ++i) columns_[names[i]] = static_cast<int>(i);
    for (const std::string& name : required) {
      if (!columns_.count(name)) fail("no column '" + name + "' in the header");
    }
    width_ = names.size();
  }

  bool has(const std::string& name) const { return columns_.count(name) > 0; }
  int column(const std::string& name) const { return columns_.at(name); }
  // The column `name`, or in a file of an earlier version its former name `old` (with a
  // warning naming the file); neither: fail.
  int column(const std::string& name, const std::string& old) const {
    if (has(name)) return column(name);
    if (!has(old)) fail("no column '" + name + "' in the header");
    stderr_warning(
        fmt::format("{}: column '{}' is read as '{}' (a file of an earlier version; "
                    "run the command that wrote it again to update it)",
                    path_, old, name));
    return column(old);
  }

  bool next() {
    std::string text;
    while (std::getline(in_, text)) {
      ++line_;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      if (text.empty()) continue;
      cells_ = split(text);
      if (cells_.size() != width_) {
        fail(fmt::format("{} fields, the header has {}", cells_.size(), width_));
      }
      return true;
    }
    return false;
  }

  const std::string& text(int col) const { return cells_[col]; }
  double number(int col) const {
    const std::string& s = cells_[col];
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE) {
      fail("'" + s + "' is not a number");
    }
    return v;
  }
  int integer(int col) const {
    const std::string& s = cells_[col];
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size() || errno == ERANGE || v < -2147483647L ||
        v > 2147483647L) {
      fail("'" + s + "' is not an integer");
    }
    return static_cast<int>(v);
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InvalidInput({path_, line_, ""}, message);
  }
  int line() const { return line_; }

 private:
  static std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    size_t start = 0;
    while (true) {
      const size_t comma = s.find(',', start);
      out.push_back(
          s.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return out;
  }

  std::string path_;
  std::ifstream in_;
  int line_ = 0;
  size_t width_ = 0;
  std::map<std::string, int> columns_;
  std::vector<std::string> cells_;
};

int axis_row(const std::string& axis, bool global) {
  if (global) {
    if (axis == "x") return 0;
    if (axis == "y") return 1;
    if (axis == "z") return 2;
    return -1;
  }
  if (axis == "t1" || axis == "u") return 0;
  if (axis == "t2") return 1;
  if (axis == "n") return 2;
  return -1;
}

}  // namespace

StudyColumns study_columns(const CaseDefinition& definition, double value) {
  if (!definition.study.active()) return {};
  return {",parameter,value", fmt::format(",{},{}", definition.study.parameter, value)};
}

double dissipated_energy(const FrequencyPoint& point) {
  double e = 0;
  for (const PairResponse& r : point.pairs) e += r.cycle.dissipated_energy;
  return e;
}

void require_stage_file(const fs::path& path, const std::string& hint) {
  if (!fs::exists(path)) {
    throw InvalidInput({path.string(), 0, ""}, "missing: run `" + hint + "` first");
  }
}

SolveResults read_solve_results(const fs::path& dir, const std::string& hint) {
  SolveResults out;
  FrequencyResponse& fr = out.response;

  // summary.json: title, fingerprint, frf DOFs (any JSON layout: cli/summary_file.h).
  {
    const fs::path path = dir / "summary.json";
    const nlohmann::ordered_json summary = read_summary(path, hint);
    std::string text;  // for the line of a faulty key
    const auto fail = [&](const std::string& key, const std::string& message) {
      std::ifstream in(path, std::ios::binary);
      text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      throw InvalidInput({path.string(), summary_key_line(text, key), key}, message);
    };
    const auto string_of = [&](const char* key, std::string* value) {
      if (!summary.contains(key)) return;
      if (!summary[key].is_string()) fail(key, "expected a string");
      *value = summary[key].get<std::string>();
    };
    string_of("title", &out.title);
    string_of("fingerprint", &out.fingerprint);
    // {"parameter": "contacts.j.per_pair.preload", "value": v, ...}, or null without a study.
    if (summary.contains("study") && !summary["study"].is_null()) {
      const auto& study = summary["study"];
      if (!study.is_object() || !study.contains("parameter") || !study["parameter"].is_string() ||
          !study.contains("value") || !study["value"].is_number()) {
        fail("study", "expected {\"parameter\": <key>, \"value\": <number>}");
      }
      out.study_parameter = study["parameter"].get<std::string>();
      out.study_value = study["value"].get<double>();
    }
    // {"log_amplitude": bool}; absent in files of earlier versions (linear plots).
    if (summary.contains("plots") && !summary["plots"].is_null()) {
      const auto& plots = summary["plots"];
      if (!plots.is_object() ||
          (plots.contains("log_amplitude") && !plots["log_amplitude"].is_boolean())) {
        fail("plots", "expected {\"log_amplitude\": true|false}");
      }
      out.log_amplitude = plots.value("log_amplitude", false);
    }
    // [{"type": ..., "point": i, "frequency_hz": f, "amplitude_m": [a or null, ...], ...}];
    // absent in files of earlier versions.
    if (summary.contains("bifurcations") && !summary["bifurcations"].is_null()) {
      const auto& list = summary["bifurcations"];
      if (!list.is_array()) fail("bifurcations", "expected a list");
      for (const auto& v : list) {
        if (!(v.is_object() && v.contains("type") && v["type"].is_string() && v.contains("point") &&
              v["point"].is_number_integer() && v.contains("frequency_hz") &&
              v["frequency_hz"].is_number() && v.contains("amplitude_m") &&
              v["amplitude_m"].is_array())) {
          fail("bifurcations",
               "'" + v.dump() + "' has no type, point, frequency_hz and amplitude_m list");
        }
        SolvedBifurcation b;
        b.type = v["type"].get<std::string>();
        b.point = v["point"].get<int>();
        b.frequency_hz = v["frequency_hz"].get<double>();
        for (const auto& a : v["amplitude_m"]) {
          if (!a.is_null() && !a.is_number()) fail("bifurcations", "amplitude_m: not a number");
          b.amplitude_m.push_back(a.is_null() ? std::numeric_limits<double>::quiet_NaN()
                                              : a.get<double>());
        }
        out.bifurcations.push_back(std::move(b));
      }
    }
    if (summary.contains("frf")) {
      const auto& frf = summary["frf"];
      if (!frf.is_array()) fail("frf", "expected a list of DOFs");
      for (const auto& v : frf) {
        ResponseDofDefinition r;
        int direction = -1;
        if (v.is_object()) {  // {"body": b, "node": n, "direction": "x", ...}
          if (!(v.contains("body") && v["body"].is_string() && v.contains("node") &&
                v["node"].is_number_integer() && v.contains("direction") &&
                v["direction"].is_string())) {
            fail("frf", "'" + v.dump() + "' has no body, node and direction");
          }
          r.body = v["body"].get<std::string>();
          r.node = v["node"].get<int>();
          direction = axis_row(v["direction"].get<std::string>(), /*global=*/true);
        } else if (v.is_string()) {  // "body:node:direction" (earlier versions)
          const std::string t = v.get<std::string>();
          const size_t c2 = t.rfind(':');  // the body name may itself contain ':'
          const size_t c1 =
              c2 == std::string::npos || c2 == 0 ? std::string::npos : t.rfind(':', c2 - 1);
          if (c1 != std::string::npos) {
            r.body = t.substr(0, c1);
            r.node = std::atoi(t.substr(c1 + 1, c2 - c1 - 1).c_str());
            direction = axis_row(t.substr(c2 + 1), /*global=*/true);
          }
        }
        if (direction < 0) fail("frf", "'" + v.dump() + "' is not body:node:direction");
        r.direction = direction;
        out.frf.push_back(r);
      }
    }
  }

  // points.csv
  {
    CsvReader csv(dir / "points.csv", {"point", "frequency_hz", "converged", "iterations"}, hint);
    const int c_point = csv.column("point"), c_f = csv.column("frequency_hz"),
              c_conv = csv.column("converged"), c_it = csv.column("iterations"),
              c_res = csv.column("residual_m", "residual");
    // analysis.stability: stable (0/1) and floquet_multiplier, empty where not computed.
    const int c_stable = csv.has("stable") ? csv.column("stable") : -1;
    const int c_multiplier = csv.has("floquet_multiplier") ? csv.column("floquet_multiplier") : -1;
    while (csv.next()) {
      const int i = csv.integer(c_point);
      if (i != static_cast<int>(fr.points.size())) {
        csv.fail(fmt::format("point {} where point {} was expected", i, fr.points.size()));
      }
      FrequencyPoint p;
      p.omega = hz_to_rad_s(csv.number(c_f));
      if (!(std::isfinite(p.omega) && p.omega > 0)) csv.fail("the frequency must be > 0 Hz");
      const int converged = csv.integer(c_conv);
      if (converged != 0 && converged != 1) csv.fail("converged must be 0 or 1");
      p.converged = converged == 1;
      p.iterations = csv.integer(c_it);
      p.residual_norm = csv.number(c_res);
      if (c_stable >= 0 && !csv.text(c_stable).empty()) {
        const int stable = csv.integer(c_stable);
        if (stable != 0 && stable != 1) csv.fail("stable must be 0, 1 or empty");
        p.stability_computed = true;
        p.floquet.stable = stable == 1;
        if (c_multiplier >= 0 && !csv.text(c_multiplier).empty()) {
          p.floquet.max_multiplier = csv.number(c_multiplier);
        }
      }
      fr.points.push_back(std::move(p));
    }
    if (fr.points.empty()) csv.fail("no frequency points");
  }
  const int np = static_cast<int>(fr.points.size());
  const auto point_of = [np](const CsvReader& csv, int col) {
    const int i = csv.integer(col);
    if (i < 0 || i >= np) csv.fail(fmt::format("point {} is not in points.csv (0..{})", i, np - 1));
    return i;
  };

  // contact_forces.csv: pairs in order of first appearance, harmonics sorted.
  struct ForceRow {
    int point, pair, row, harmonic;
    bool global;
    std::complex<double> value;
    int line;
  };
  std::vector<ForceRow> rows;
  std::map<std::pair<std::string, int>, int> pair_index;
  std::set<int> harmonic_set;
  const fs::path forces_path = dir / "contact_forces.csv";
  {
    CsvReader csv(forces_path,
                  {"point", "contact", "pair", "node_a", "node_b", "frame", "axis", "harmonic"},
                  hint);
    const int c_point = csv.column("point"), c_contact = csv.column("contact"),
              c_pair = csv.column("pair"), c_a = csv.column("node_a"), c_b = csv.column("node_b"),
              c_frame = csv.column("frame"), c_axis = csv.column("axis"),
              c_h = csv.column("harmonic"), c_re = csv.column("real_n", "real"),
              c_im = csv.column("imag_n", "imag");
    while (csv.next()) {
      ForceRow r;
      r.point = point_of(csv, c_point);
      const std::pair<std::string, int> id{csv.text(c_contact), csv.integer(c_pair)};
      auto [it, inserted] = pair_index.try_emplace(id, static_cast<int>(out.pairs.size()));
      if (inserted) {
        out.pairs.push_back({id.first, id.second, csv.integer(c_a), csv.integer(c_b), 0});
      } else if (out.pairs[it->second].node_a != csv.integer(c_a) ||
                 out.pairs[it->second].node_b != csv.integer(c_b)) {
        csv.fail(fmt::format("pair {} of contact {} changes its nodes", id.second, id.first));
      }
      r.pair = it->second;
      const std::string& frame = csv.text(c_frame);
      if (frame != "local" && frame != "global") csv.fail("frame must be local or global");
      r.global = frame == "global";
      r.row = axis_row(csv.text(c_axis), r.global);
      if (r.row < 0) csv.fail("unknown axis '" + csv.text(c_axis) + "' for frame " + frame);
      if (!r.global) {
        SolvedPairId& pid = out.pairs[r.pair];
        const int m = csv.text(c_axis) == "u" ? 1 : 3;
        if (pid.local_rows != 0 && pid.local_rows != m) csv.fail("mixed 1D and 3D axes of a pair");
        pid.local_rows = m;
      }
      r.harmonic = csv.integer(c_h);
      if (r.harmonic < 0) csv.fail("negative harmonic");
      harmonic_set.insert(r.harmonic);
      r.value = {csv.number(c_re), csv.number(c_im)};
      // The solve writes finite forces for every converged point (the only ones recovered): a
      // NaN or an infinity there is a damaged file, and would be recovered into NaN fields.
      if (fr.points[r.point].converged &&
          !(std::isfinite(r.value.real()) && std::isfinite(r.value.imag()))) {
        csv.fail(fmt::format("the force of converged point {} is not a finite number", r.point));
      }
      r.line = csv.line();
      rows.push_back(r);
    }
  }
  // master_response.csv
  struct MasterRow {
    int point;
    MasterDofKey key;
    int harmonic;
    std::complex<double> value;
  };
  std::vector<MasterRow> master_rows;
  {
    CsvReader csv(dir / "master_response.csv", {"point", "body", "node", "harmonic"}, hint);
    const int c_point = csv.column("point"), c_body = csv.column("body"),
              c_node = csv.column("node"), c_dof = csv.column("axis", "dof"),
              c_h = csv.column("harmonic"), c_re = csv.column("real_m", "real"),
              c_im = csv.column("imag_m", "imag");
    while (csv.next()) {
      MasterRow r;
      r.point = point_of(csv, c_point);
      const int d = axis_row(csv.text(c_dof), true);
      if (d < 0) csv.fail("axis must be x, y or z");
      r.key = MasterDofKey{csv.text(c_body), csv.integer(c_node), d};
      r.harmonic = csv.integer(c_h);
      if (r.harmonic < 0) csv.fail("negative harmonic");
      r.value = {csv.number(c_re), csv.number(c_im)};
      master_rows.push_back(std::move(r));
    }
  }
  std::set<int> master_harmonics;
  for (const MasterRow& r : master_rows) master_harmonics.insert(r.harmonic);
  if (!harmonic_set.empty() && !std::includes(harmonic_set.begin(), harmonic_set.end(),
                                              master_harmonics.begin(), master_harmonics.end())) {
    throw InvalidInput({(dir / "master_response.csv").string(), 0, "harmonic"},
                       "not the harmonics of contact_forces.csv: run `" + hint + "` again");
  }
  harmonic_set.insert(master_harmonics.begin(), master_harmonics.end());
  fr.harmonics.assign(harmonic_set.begin(), harmonic_set.end());
  const int nh = static_cast<int>(fr.harmonics.size());
  const int npairs = static_cast<int>(out.pairs.size());
  std::map<int, int> column_of_harmonic;
  for (int h = 0; h < nh; ++h) column_of_harmonic[fr.harmonics[h]] = h;
  for (SolvedPairId& pid : out.pairs) {
    if (pid.local_rows == 0) pid.local_rows = 3;
  }
  // Fill, checking every entry is given exactly once.
  std::vector<Eigen::MatrixXi> seen(static_cast<size_t>(np) * npairs);
  for (FrequencyPoint& p : fr.points) {
    p.pairs.resize(npairs);
    for (int q = 0; q < npairs; ++q) {
      p.pairs[q].force_local = Eigen::MatrixXcd::Zero(out.pairs[q].local_rows, nh);
      p.pairs[q].force_global = Eigen::MatrixXcd::Zero(3, nh);
    }
  }
  for (size_t i = 0; i < seen.size(); ++i) seen[i] = Eigen::MatrixXi::Zero(6, nh);
  for (const ForceRow& r : rows) {
    PairResponse& pr = fr.points[r.point].pairs[r.pair];
    const int h = column_of_harmonic.at(r.harmonic);
    Eigen::MatrixXcd& target = r.global ? pr.force_global : pr.force_local;
    if (r.row >= target.rows()) {
      throw InvalidInput({forces_path.string(), r.line, ""}, "axis out of the pair's frame");
    }
    int& count =
        seen[static_cast<size_t>(r.point) * npairs + r.pair](r.row + (r.global ? 3 : 0), h);
    if (count++ > 0) {
      throw InvalidInput({forces_path.string(), r.line, ""},
                         "this point, pair, frame, axis and harmonic is given twice");
    }
    target(r.row, h) = r.value;
  }
  const size_t expected_rows = [&] {
    size_t n = 0;
    for (const SolvedPairId& pid : out.pairs) n += static_cast<size_t>(pid.local_rows + 3) * nh;
    return n * np;
  }();
  if (rows.size() != expected_rows) {
    throw InvalidInput({forces_path.string(), 0, ""},
                       fmt::format("{} force rows where {} points x {} pairs x {} harmonics need "
                                   "{}: the file is incomplete; run `{}` again",
                                   rows.size(), np, npairs, nh, expected_rows, hint));
  }

  // contact_state.csv
  {
    CsvReader csv(dir / "contact_state.csv",
                  {"point", "contact", "pair", "stick", "slip", "separation"}, hint);
    const int c_point = csv.column("point"), c_contact = csv.column("contact"),
              c_pair = csv.column("pair"), c_stick = csv.column("stick"),
              c_slip = csv.column("slip"), c_sep = csv.column("separation"),
              c_e = csv.column("dissipated_energy_j", "dissipated_energy");
    size_t count = 0;
    while (csv.next()) {
      const int i = point_of(csv, c_point);
      const auto it = pair_index.find({csv.text(c_contact), csv.integer(c_pair)});
      if (it == pair_index.end()) csv.fail("pair not in contact_forces.csv");
      CycleStatistics& c = fr.points[i].pairs[it->second].cycle;
      c.stick_fraction = csv.number(c_stick);
      c.slip_fraction = csv.number(c_slip);
      c.separation_fraction = csv.number(c_sep);
      c.dissipated_energy = csv.number(c_e);
      ++count;
    }
    if (count != static_cast<size_t>(np) * npairs) {
      csv.fail(fmt::format("{} rows where {} points x {} pairs are needed", count, np, npairs));
    }
  }

  // histories.csv (optional): one row per point, pair, sample, axis.
  if (fs::exists(dir / "histories.csv")) {
    CsvReader csv(dir / "histories.csv", {"point", "contact", "pair", "sample", "axis"}, hint);
    const int c_point = csv.column("point"), c_contact = csv.column("contact"),
              c_pair = csv.column("pair"), c_sample = csv.column("sample"),
              c_axis = csv.column("axis"), c_u = csv.column("displacement_m", "displacement"),
              c_f = csv.column("force_n", "force");
    while (csv.next()) {
      const int i = point_of(csv, c_point);
      const auto it = pair_index.find({csv.text(c_contact), csv.integer(c_pair)});
      if (it == pair_index.end()) csv.fail("pair not in contact_forces.csv");
      const int j = csv.integer(c_sample);
      const int row = axis_row(csv.text(c_axis), false);
      const int m = out.pairs[it->second].local_rows;
      if (row < 0 || row >= m) csv.fail("unknown axis '" + csv.text(c_axis) + "'");
      if (j < 0 || j > 1000000) csv.fail("sample out of range");
      AftSamples& s = fr.points[i].pairs[it->second].history;
      if (s.u.cols() <= j) {
        const Eigen::Index old = s.u.cols();
        s.u.conservativeResize(m, j + 1);
        s.f.conservativeResize(m, j + 1);
        s.u.rightCols(j + 1 - old).setZero();
        s.f.rightCols(j + 1 - old).setZero();
      }
      s.u(row, j) = csv.number(c_u);
      s.f(row, j) = csv.number(c_f);
    }
  }

  // master_response.csv (rows read before the harmonics are fixed: a case without contact pairs
  // has its harmonics only here).
  for (const MasterRow& r : master_rows) {
    auto [it, inserted] = out.master.try_emplace(r.key, Eigen::MatrixXcd());
    if (inserted) it->second = Eigen::MatrixXcd::Zero(np, nh);
    it->second(r.point, column_of_harmonic.at(r.harmonic)) = r.value;
  }
  fr.completed = true;
  if (fs::exists(dir / "snmt.csv")) {
    SolveResults::Prediction& pr = out.prediction;
    CsvReader csv(dir / "snmt.csv", {"row", "frequency_hz", "mode_frequency_hz"}, hint);
    const int c_row = csv.column("row"), c_f = csv.column("frequency_hz"),
              c_mode = csv.column("mode_frequency_hz");
    while (csv.next()) {
      if (csv.integer(c_row) != static_cast<int>(pr.frequency_hz.size())) {
        csv.fail("rows must be numbered 0, 1, 2, ... in order");
      }
      pr.frequency_hz.push_back(csv.number(c_f));
      pr.mode_frequency_hz.push_back(csv.number(c_mode));
    }
    const int rows = static_cast<int>(pr.frequency_hz.size());
    CsvReader response(dir / "snmt_response.csv",
                       {"row", "body", "node", "axis", "harmonic", "real_m", "imag_m"}, hint);
    const int r_row = response.column("row"), r_body = response.column("body"),
              r_node = response.column("node"), r_axis = response.column("axis"),
              r_h = response.column("harmonic"), r_re = response.column("real_m"),
              r_im = response.column("imag_m");
    while (response.next()) {
      if (response.integer(r_h) != 1) continue;
      const int row = response.integer(r_row);
      if (row < 0 || row >= rows) response.fail("row not in snmt.csv");
      const int d = axis_row(response.text(r_axis), true);
      if (d < 0) response.fail("axis must be x, y or z");
      auto& v = pr.master[MasterDofKey{response.text(r_body), response.integer(r_node), d}];
      if (v.empty()) v.assign(rows, std::complex<double>(std::nan(""), 0.0));
      v[row] = {response.number(r_re), response.number(r_im)};
    }
  }
  return out;
}

void write_reduce_manifest(const fs::path& path, const ReduceManifest& manifest) {
  write_file_atomically(path.string(), [&](std::ostream& out) {
    out << "# stickslip reduce: what the matrices of this folder were made from. A body's\n"
           "# fingerprint hashes its mesh, element set, material, clamps, master nodes and\n"
           "# modes; solve, recover, export and modes reuse the files only if it still matches.\n";
    fmt::print(out, "case {}\n", manifest.case_file);
    for (const auto& [body, hash] : manifest.body_fingerprint) {
      fmt::print(out, "body {} {}\n", body, hash);
    }
  });
}

ReduceManifest read_reduce_manifest(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InvalidInput({path.string(), 0, ""}, "cannot read the manifest");
  ReduceManifest m;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "case") {
      std::getline(ss >> std::ws, m.case_file);
    } else if (key == "body") {
      std::string name, hash;
      if (!(ss >> name >> hash)) {
        throw InvalidInput({path.string(), number, "body"}, "expected: body <name> <fingerprint>");
      }
      m.body_fingerprint[name] = hash;
    } else {
      throw InvalidInput({path.string(), number, key}, "unknown manifest key");
    }
  }
  return m;
}

void write_dense_matrix(const fs::path& path, const Eigen::MatrixXd& matrix) {
  static_assert(sizeof(double) == 8);
  write_file_atomically(path.string(), [&](std::ostream& out) {
    fmt::print(out, "stickslip-dense-matrix 1 {} {}\n", matrix.rows(), matrix.cols());
    out.write(reinterpret_cast<const char*>(matrix.data()),
              static_cast<std::streamsize>(matrix.size() * sizeof(double)));
  });
}

Eigen::MatrixXd read_dense_matrix(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path.string(), 0, ""}, "cannot read the matrix file");
  std::string header;
  std::getline(in, header);
  std::istringstream ss(header);
  std::string magic;
  int version = 0;
  long rows = -1, cols = -1;
  ss >> magic >> version >> rows >> cols;
  if (magic != "stickslip-dense-matrix" || version != 1 || rows < 0 || cols < 0 ||
      rows > std::numeric_limits<int>::max() || cols > std::numeric_limits<int>::max()) {
    throw InvalidInput({path.string(), 1, ""}, "not a stickslip dense matrix file");
  }
  // The values present are counted before the matrix is allocated: a damaged header announcing
  // a huge matrix stops here instead of in the allocator (rows * cols < 2^62 fits).
  const std::istream::pos_type here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::istream::pos_type end = in.tellg();
  in.seekg(here);
  const unsigned long long announced =
      static_cast<unsigned long long>(rows) * static_cast<unsigned long long>(cols);
  const unsigned long long present =
      here == std::istream::pos_type(-1) || end < here
          ? 0
          : static_cast<unsigned long long>(end - here) / sizeof(double);
  if (present < announced) {
    throw InvalidInput({path.string(), 1, ""},
                       fmt::format("the matrix file is truncated: {} x {} values announced, the "
                                   "file holds {}",
                                   rows, cols, present));
  }
  Eigen::MatrixXd m(rows, cols);
  in.read(reinterpret_cast<char*>(m.data()),
          static_cast<std::streamsize>(m.size() * sizeof(double)));
  if (in.gcount() != static_cast<std::streamsize>(m.size() * sizeof(double))) {
    throw InvalidInput({path.string(), 0, ""}, "the matrix file is truncated");
  }
  return m;
}

}  // namespace stickslip

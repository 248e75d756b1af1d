#include "cli/summary_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "model/case_model.h"

#ifndef STICKSLIP_VERSION
#define STICKSLIP_VERSION "unknown"
#endif

namespace stickslip {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// 1-based line of byte offset `byte` of `text`.
int line_at(const std::string& text, size_t byte) {
  byte = std::min(byte, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + byte, '\n'));
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InvalidInput({path.string(), 0, ""}, "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

int summary_key_line(const std::string& text, const std::string& key) {
  const std::string quoted = "\"" + key + "\"";
  for (size_t at = text.find(quoted); at != std::string::npos; at = text.find(quoted, at + 1)) {
    const size_t colon = text.find_first_not_of(" \t\r\n", at + quoted.size());
    if (colon != std::string::npos && text[colon] == ':') return line_at(text, at);
  }
  return 0;
}

Json read_summary(const fs::path& path, const std::string& hint) {
  require_stage_file(path, hint);
  const std::string text = slurp(path);
  Json summary;
  try {
    summary = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // e.byte: 1-based position of the character where parsing stopped.
    throw InvalidInput({path.string(), line_at(text, e.byte > 0 ? e.byte - 1 : 0), ""},
                       "not valid JSON (" + std::string(e.what()) + "): run `" + hint +
                           "` again");
  }
  if (!summary.is_object()) {
    throw InvalidInput({path.string(), 1, ""}, "expected a JSON object: run `" + hint + "` again");
  }
  return summary;
}

void write_summary(const fs::path& dir, const Json& summary) {
  write_file_atomically((dir / "summary.json").string(), [&](std::ostream& out) {
    // Invalid UTF-8 in names from users' files is replaced rather than refused.
    out << summary.dump(2, ' ', false, Json::error_handler_t::replace) << "\n";
  });
}

void complete_summary(const fs::path& dir, const SummaryTimings& timings) {
  Json summary = read_summary(dir / "summary.json", "stickslip run");
  Json& t = summary["timings"];
  const auto ms = [](double s) { return std::round(s * 1000) / 1000; };
  t["recovery_s"] = ms(timings.recovery_s);
  t["plots_s"] = ms(timings.plots_s);
  t["total_s"] = ms(timings.total_s);
  std::vector<std::string> files;
  for (const fs::path& f : published_files_under(dir)) files.push_back(f.generic_string());
  if (std::find(files.begin(), files.end(), "summary.json") == files.end())
    files.push_back("summary.json");
  summary["files"] = files;
  if (summary.contains("removed_stale") && summary["removed_stale"].is_array()) {
    // Files of an earlier run removed by the solve and written again since are not stale.
    Json removed = Json::array();
    for (const auto& f : summary["removed_stale"]) {
      if (std::find(files.begin(), files.end(), f.get<std::string>()) == files.end())
        removed.push_back(f);
    }
    summary["removed_stale"] = removed;
  }
  write_summary(dir, summary);
}

nlohmann::ordered_json start_summary(const StageRun& run) {
  const CaseDefinition& def = run.definition;
  nlohmann::ordered_json summary;
  summary["program"] = "stickslip";
  summary["version"] = STICKSLIP_VERSION;
  summary["case_file"] = def.file;
  summary["title"] = def.title;
  summary["fingerprint"] = solve_fingerprint(def);
  const std::filesystem::path& dir = run.reported_dir.empty() ? run.dir : run.reported_dir;
  summary["output_directory"] = std::filesystem::absolute(dir).lexically_normal().string();
  if (def.study.active()) {
    summary["study"] = {
        {"parameter", def.study.parameter}, {"value", run.value}, {"folder", run.folder}};
  } else {
    summary["study"] = nullptr;
  }
  return summary;
}

void finish_summary(nlohmann::ordered_json& summary, const StageRun& run,
                    const PreparedModel& model, double seconds_solve, double seconds_total,
                    const std::vector<std::string>& removed) {
  using Json = nlohmann::ordered_json;
  const auto milliseconds = [](double seconds) { return std::round(seconds * 1000) / 1000; };
  summary["bodies"] = Json::array();
  for (const PreparedBody& body : model.bodies) {
    summary["bodies"].push_back({{"name", body.name},
                                 {"full_dofs", body.from_mesh ? body.mesh.num_dofs() : 0},
                                 {"reduced_dofs", body.reduced.size()},
                                 {"masters", body.master_dof.size() / 3},
                                 {"seconds_reduction", milliseconds(body.seconds_reduction)}});
  }
  summary["timings"] = {{"prepare_s", milliseconds(model.seconds_prepare)},
                        {"solve_s", milliseconds(seconds_solve)},
                        {"recovery_s", 0.0},
                        {"plots_s", 0.0},
                        {"total_s", milliseconds(seconds_total)}};
  std::vector<std::string> files;
  for (const std::filesystem::path& f : published_files_under(run.dir))
    files.push_back(f.generic_string());
  files.push_back("summary.json");
  summary["files"] = files;
  summary["removed_stale"] = removed;
  CaseDefinition inputs = with_absolute_paths(run.definition);
  inputs.study = StudyDefinition{};
  inputs.output.directory = summary["output_directory"].get<std::string>();
  summary["inputs"] = describe_case(inputs);
}

}  // namespace stickslip

// summary.json of an output folder (docs/output-files.md), written and read as JSON (nlohmann-json):
// any valid JSON layout of it reads back (reindented, keys reordered, one line), so a user or a
// tool may reformat it.
//
// The solve writes it (write_solve_results); `run` completes it once the recovery and the plots
// are written (complete_summary: their timings, the total, and every file the run wrote in the
// folder). Keys that readers use: `title`, `fingerprint`, `frf` (objects with body, node,
// direction; the strings "body:node:axis" of earlier versions are read too).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace stickslip {

struct PreparedModel;  // model/case_model.h
struct StageRun;       // cli/commands.h

// The parsed file. InvalidInput naming the file and the line of the fault when it is not JSON or
// not an object; a missing file names `hint` (the command that writes it).
nlohmann::ordered_json read_summary(const std::filesystem::path& path, const std::string& hint);

// dir/summary.json, atomically, indented by two spaces, keys in the order `summary` holds them.
void write_summary(const std::filesystem::path& dir, const nlohmann::ordered_json& summary);

// The line (1-based) of the first `"key":` in `text`, or 0: for messages about a key's value.
int summary_key_line(const std::string& text, const std::string& key);

// Times of the stages after the solve, seconds (`run`).
struct SummaryTimings {
  double recovery_s = 0.0;
  double plots_s = 0.0;
  double total_s = 0.0;  // the whole analysis of this folder: preparation to the last plot
};

// Rewrites dir/summary.json with timings.recovery_s, plots_s and total_s set and `files` = every
// file this process published under dir (io/atomic_file.h), summary.json included, as paths
// relative to dir with '/' separators.
void complete_summary(const std::filesystem::path& dir, const SummaryTimings& timings);

// The keys every analysis's summary.json starts with, written alike by the forced response and the
// nonlinear mode: program, version, case_file, title, fingerprint, output_directory (absolute) and
// study (parameter, value, folder; null without a study).
nlohmann::ordered_json start_summary(const StageRun& run);

// The keys it ends with: `bodies` (name, full_dofs, reduced_dofs, masters, seconds_reduction),
// `timings` (prepare_s, solve_s, recovery_s and plots_s 0 until complete_summary, total_s; seconds
// rounded to the millisecond), `files` (every file published under run.dir, then summary.json),
// `removed_stale` and `inputs`: this folder's analysis as a case file (one study value, no study,
// absolute file paths, the output folder used), from which `stickslip run` makes these results
// again.
void finish_summary(nlohmann::ordered_json& summary, const StageRun& run,
                    const PreparedModel& model, double seconds_solve, double seconds_total,
                    const std::vector<std::string>& removed);

}  // namespace stickslip

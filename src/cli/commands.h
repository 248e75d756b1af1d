// The subcommands of the stickslip program (docs/command-line.md). Each returns the process exit
// code (0 success, 1 numerical failure reported to the user, kExitPlotsMissing = 4 when pictures
// could not be drawn); bad input, missing or stale files of an earlier stage and file-system
// refusals throw InvalidInput naming the file (and the command to run first, or the reason).
//
// Stages and the files they share, in an output folder DIR (docs/output-files.md):
//   mesh     DIR/mesh/<body>.inp, .vtu          the bodies' meshes as the case builds them
//   reduce   DIR/reduced/<body>_K.hb, _M.hb, .mapping, [<body>_T.bin], manifest.txt
//   modes    DIR/modes/frequencies.csv, modes.vtm + <body>/shapes.vtu (stuck assembly)
//   solve    DIR/points.csv, master_response.csv, contact_forces.csv, contact_state.csv,
//            histories.csv, contact_coupling.csv (mortar contacts), summary.json
//   recover  the recovery files of run (reads the solve files)
//   export   DIR/loads_p<N>_<body>.mac | recovery_p<N>_<body>.inp (reads the solve files)
//   plot     the pictures, from the CSV files
//   run      all of the above in sequence (without reusing earlier files)
// With a study, solve/recover/export/plot work per study folder DIR/<parameter>_<value>/.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cli/pipeline.h"
#include "cli/results_files.h"
#include "io/case_file.h"
#include "model/frf_peaks.h"

namespace stickslip {

struct ModesCommand {
  std::string case_file;  // empty: the reference two-beam joint (options below)
  std::string arrangement = "butt";
  int num_modes = 8;
  bool thesis_coarse = false;
  std::string element = "C3D8I";
  double k_t = 4.467e9;    // N/m per pair (the thesis)
  double k_n = 5.6309e9;   // N/m per pair (the thesis)
  std::string output_dir;  // empty: "." (no case) or the case's output.directory
  bool quiet = false;
};
int run_modes(const ModesCommand& command);

// Options shared by run and the stage commands that read a case.
struct StageCommand {
  std::string case_file;
  std::string output_dir;  // empty: the case file's output.directory
  bool quiet = false;
};

// Exit code 1 when some frequency points did not converge (they are still written).
int run_case(const StageCommand& command);

// Writes DIR/mesh/<body>.inp (sets included) and <body>.vtu (with clamped / master markers).
int run_mesh(const StageCommand& command);

// Reduces every mesh body of the case (Craig–Bampton onto its master nodes, as `run` would) and
// writes DIR/reduced/<body>_K.hb, <body>_M.hb (Harwell–Boeing RSA, as ANSYS HBMAT) with their
// .mapping files, the basis T (<body>_T.bin) when recovery.method is expansion or `basis` is
// set (mode shapes of `modes CASE`), and manifest.txt.
struct ReduceCommand {
  StageCommand stage;
  bool basis = false;
};
int run_reduce(const ReduceCommand& command);

// The harmonic balance; writes the CSV/JSON files of run (no recovery, no plots).
int run_solve(const StageCommand& command);

struct RecoverCommand {
  StageCommand stage;
  std::string point;  // empty: recovery.points of the case; "peak", "all" or a point index
};
int run_recover(const RecoverCommand& command);

struct ExportCommand {
  StageCommand stage;
  std::string points;   // --point: N, N,M,..., peak or all (points_from_option)
  std::string format;  // apdl | calculix
};
int run_export(const ExportCommand& command);

struct PlotCommand {
  std::string dir;
  bool quiet = false;
  bool log = false;  // amplitude plots on a logarithmic axis (else as summary.json's plots says)
};
int run_plot(const PlotCommand& command);

struct KeysCommand {
  std::string section;  // a key or section path ("analysis", "contacts[]"); empty: every key
};
// Prints the case file's keys (io/case_keys.h): path, type and rule, unit, default, whether a
// study may vary it, and a line of help. InvalidInput for a section with no key.
int run_keys(const KeysCommand& command);

// --- plumbing shared by the stage commands -------------------------------------------------------

// One analysis of a case: the case itself, or one value of its study (folder "<param>_<value>").
struct StageRun {
  std::string folder;  // empty without a study
  CaseDefinition definition;
  std::filesystem::path dir;  // output folder of this analysis
  double value = 0.0;         // with a study: the studied parameter's value
  // Where the files end up when `dir` is a private copy of a process other than rank 0, which
  // writes them (cli/distributed_run.h): the folder summary.json names. Empty: `dir`.
  std::filesystem::path reported_dir{};
};
std::vector<StageRun> stage_runs(const CaseDefinition& base, const std::filesystem::path& out_dir);
// The output folder (output_dir, or the case's output.directory), created and checked writable
// (InvalidInput with the reason otherwise; temporaries of killed runs in it removed); the case's
// input files are protected from being replaced by a result (protect_input_file).
std::filesystem::path stage_output_dir(const CaseDefinition& base, const std::string& output_dir);
// "stickslip <stage> <case> -o <dir>", for messages that say what to run first.
std::string stage_hint(const std::string& stage, const CaseDefinition& base,
                       const std::filesystem::path& out_dir);

// Fingerprint of everything the harmonic balance depends on (the case without its recovery and
// output-format settings and without the study block, whose value `definition` holds, plus the
// bytes of the mesh and matrix files it reads). Written to
// summary.json by the solve; recover and export refuse solve files with another fingerprint.
std::string solve_fingerprint(const CaseDefinition& definition);

// The reduced model of `run` (cli/pipeline.h), reusing the reduced matrices of `reduce` when
// DIR/<folder>/reduced/ or DIR/reduced/ holds a manifest: their fingerprints must match this
// case's bodies (InvalidInput naming the manifest and `reduce` otherwise). Without reduced files
// the bodies are reduced again. Reused mesh bodies get their mesh, material and clamps back;
// `full_matrices` also assembles their full K and M (for the recovery) and loads T (required for
// recovery.method: expansion); `load_basis_if_present` loads T whenever reduce wrote it.
// `cache` (may be null): what the analyses of one study share (ModelCache, cli/pipeline.h): the
// meshes are loaded once, a body reduced here (no reduced files) is reduced again only when its
// reduction fingerprint changes, and a body read from reduced files gets the full K, M and T
// made for an earlier analysis with the same fingerprint.
PreparedModel prepare_stage_model(const StageRun& run, const std::filesystem::path& out_dir,
                                  const std::string& case_file, bool full_matrices,
                                  const ProgressFn& progress, bool load_basis_if_present = false,
                                  ModelCache* cache = nullptr);

// The solve files of `run` (read_solve_results), refused (InvalidInput naming summary.json and
// the solve command) if their fingerprint is not the case's.
SolveResults read_stage_solve(const StageRun& run, const CaseDefinition& base,
                              const std::filesystem::path& out_dir);
// Refuses solve files whose contact pairs (contact, nodes, order) or harmonics are not those of
// the prepared model.
// The master-DOF response of every point (points[i].master) rebuilt from the contact forces of
// the solve files exactly as the solve made it (HarmonicBalanceSystem::master_response); refuses
// files whose master_response.csv does not follow from their contact_forces.csv (edited or mixed
// solves), naming the file and `hint` (the command that makes them again).
void rebuild_master_response(SolveResults& results, const PreparedModel& model,
                             const StageRun& run, const std::string& hint);
void check_solve_matches_model(const SolveResults& results, const PreparedModel& model,
                               const CaseDefinition& definition, const StageRun& run,
                               const std::string& hint);

// What run and solve report at their end: frequency points that did not converge, and analyses
// that stopped before the end of their frequency range (a continuation that could not go on:
// its points all converged, but the range is not covered).
struct SolveOutcome {
  int failed_points = 0;
  int incomplete_analyses = 0;
  SolveOutcome& operator+=(const SolveOutcome& o) {
    failed_points += o.failed_points;
    incomplete_analyses += o.incomplete_analyses;
    return *this;
  }
};

// The lines ending one analysis of run and solve ("<n> points (<m> not converged) in <s> s;
// results in DIR") through `progress`, and on stderr (also with --quiet) where the analysis
// stopped short of its range and why.
SolveOutcome report_solved(const SolvedCase& solved, const std::filesystem::path& dir,
                           const ProgressFn& progress);
// The end of run and solve: "done in <seconds> s", then exit code 0, or 1 with a line on stderr
// when points did not converge or an analysis stopped short of its range.
int solve_exit_code(double seconds, const SolveOutcome& outcome, const ProgressFn& progress);

// Writes points.csv, master_response.csv, contact_forces.csv, contact_state.csv, histories.csv,
// contact_coupling.csv (mortar contacts) and summary.json (docs/output-files.md) atomically into run.dir, after removing the result
// files of an earlier run there (cli/stale_results.h: everything derived from a solve that this
// process has not written). Returns the removed files (also in summary.json's removed_stale).
std::vector<std::string> write_solve_results(const StageRun& run, const PreparedModel& model,
                                             const SolvedCase& solved, double seconds_total);
// A warning (stderr, also when quiet) per output.frf DOF whose response peak is the first or the
// last converged point of the sweep (frf_peaks: the true peak may lie outside the window).
void warn_peak_at_window_edge(const StageRun& run, const PreparedModel& model,
                              const SolvedCase& solved);
// The log line about files write_solve_results removed ("" when none).
std::string describe_removed(const std::vector<std::string>& removed);

// FrfPeak, frf_peaks: model/frf_peaks.h.

}  // namespace stickslip

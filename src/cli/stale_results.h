// Output folders that hold one run (docs/output-files.md, "One run per folder"): the files of an
// earlier run that this command did not write again are removed, so that a folder never mixes two
// runs (an old recovery_p17.vtm beside a new sweep, an old histories.csv after a case that no
// longer asks for one).
//
// Only files whose names stickslip gives its own results are considered, by the stages that make
// them; any other file in the folder (a user's notes, a case file, another program's output) is
// never touched, and neither are the stage folders mesh/, reduced/, modes/ nor study folders.
// The keep list is the set of files this process published in the folder
// (io/atomic_file.h: published_files_under).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace stickslip {

// The families of result files, by the command that (re)writes all of them.
enum class ResultFamily {
  kRecovery,  // recover: recovery_check.csv, recovered_nodes.csv, recovery.pvd,
              // recovery_p<N>.vtm, recovery_envelope.vtm, recovery/<body>/{p<N>,envelope}.vtu,
              // frf_full_vs_reduced.{png,svg,dat,gp}, and the per-point .vtu files of earlier
              // versions (recovery_p<N>_<body>.vtu, recovery_envelope_<body>.vtu)
  kEverything,  // solve and run: the solve files (points.csv, master_response.csv,
                // contact_forces.csv, contact_state.csv, histories.csv, summary.json), the
                // recovery family, the plots (frf, contact_state, hysteresis .png/.svg/.dat/.gp)
                // and the exported loads (loads_p<N>_<body>.mac, recovery_p<N>_<body>.inp): all
                // of them derive from one solve
};

// True when `relative` (a path under an output folder, '/' separated) is a name stickslip gives
// a result of `family`.
bool is_result_name(const std::string& relative, ResultFamily family);

// Removes from `dir` the result files of `family` that this process has not published there, and
// the recovery/<body>/ folders left empty. Returns the removed files (relative paths, sorted).
// A file that cannot be removed is kept and left out of the list (the next run tries again).
std::vector<std::string> remove_stale_results(const std::filesystem::path& dir,
                                              ResultFamily family);

}  // namespace stickslip

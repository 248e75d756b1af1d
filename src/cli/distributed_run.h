// `mpirun -n P stickslip run CASE` (docs/command-line.md, "Several processes"): the work of one
// run spread over the processes of cli/processes.h, rank 0 alone writing files and printing.
//
// A study: value i is analysed by process i mod P. Rank 0 analyses its values into their folders
// as a run alone does; another process analyses its values into a private scratch folder (run.dir
// there, run.reported_dir the real folder, named in summary.json), capturing what it prints, and
// sends rank 0 the folder's files, its log and its tally. Rank 0 takes the values in the study's
// order: it writes each received file atomically where the run alone writes it (the same bytes:
// nothing in them depends on the folder they were made in), removes the results of an earlier
// run there, prints the log with the scratch folder's name replaced by the real one and adds the
// tally. The first value that fails (in the study's order) ends the run as it ends a run alone:
// rank 0 prints the error (of whichever process) and stops the others; the values after it are
// not written.
//
// One stepped sweep (no study): its frequencies are cut into P contiguous segments, one per
// process; each process sweeps its own segment from a start of its own (the linear solution at
// the segment's first frequency, hbm/frequency_response.h), then sends the points (Ω, unknowns,
// Newton's outcome, Floquet summary) to rank 0, which evaluates their outputs (evaluate_point)
// and writes the files of the whole sweep. The first segment is the serial sweep's, to the bit;
// the points of the others are the same frequencies solved to the Newton tolerance from other
// starts (not the same bits, and on a response with several branches possibly another branch).
// A continuation and a nonlinear mode are one curve each: rank 0 computes them alone.
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cli/commands.h"
#include "cli/nonlinear_mode_stage.h"
#include "cli/plots.h"
#include "cli/processes.h"
#include "cli/progress.h"
#include "model/case_model.h"

namespace stickslip {

// What the analyses of one run add up to: the outcome, the study overlays and the pictures that
// could not be drawn.
struct RunTally {
  SolveOutcome outcome;
  std::vector<std::pair<double, std::vector<PlotSeries>>> overlay;  // (studied value, FRF curves)
  NonlinearModeOverlay mode_overlay;
  PlotLog plots;
};

// Analyses one study value into run.dir: as the loop of `run` does.
using AnalyseFn = std::function<void(const StageRun& run, const ProgressFn& progress,
                                     ProgressReporter* reporter, RunTally& tally)>;

// Every process calls it with the same runs (real folders); `quiet` as the command's. Rank 0
// returns with the tally of every value; the others return when rank 0 lets them go. Errors:
// rank 0 throws the first value's error (PeerError for another process's); the others return.
void analyse_study_on_processes(Processes& processes, const std::vector<StageRun>& runs, bool quiet,
                                const AnalyseFn& analyse, RunTally* tally);

// Thrown on a rank other than 0 once it has sent its segment of the sweep: it has nothing left
// to do in this run.
class SegmentSent : public std::runtime_error {
 public:
  SegmentSent() : std::runtime_error("segment sent to rank 0") {}
};

// A SweepRunner (model/case_model.h) spreading a stepped sweep over the processes as above.
// Every process must call solve_case with it; on rank 0 it returns the whole response, on the
// others it throws SegmentSent. Before sweeping it calls checkpoint(nullptr): a process that
// fails before it must call checkpoint(error) instead (`*reached` says whether it was called).
SweepRunner segment_runner(Processes& processes, bool* reached);

// Redirects this process's stderr (descriptor 2) to /dev/null for good: the ranks other than 0
// print nothing themselves (their errors reach rank 0 by message).
void silence_stderr();

}  // namespace stickslip

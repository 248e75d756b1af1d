// Progress of a long stage (the frequency sweep or continuation of `stickslip run`) on a text
// stream, normally stderr:
//   terminal:      one bar redrawn in place ('\r', no newline until finish()), at most once per
//                  redraw_interval seconds (the last point always), e.g.
//     stickslip: harmonic balance [####----]  50% 20/40 points 3.1 points/s 0:06 left
//   not terminal:  plain lines, one each time another line_fraction of the range is done or
//                  line_interval seconds have passed since the last line, and one at the end:
//     stickslip: harmonic balance: 20/40 points (50%), 3.1 points/s, 0:06 left
//   quiet:         nothing.
// Points done / total for a stepped sweep (total known); for arc-length continuation (total 0:
// unknown) the points so far and the part of the frequency range covered. Rate = points / elapsed
// time since start(); time left = elapsed · (1 − f) / f for the fraction f done. Points that did
// not converge are counted ("2 not converged").
// The clock is injected (seconds, monotonic) so that tests can drive it; the default is
// std::chrono::steady_clock. The reporter does no I/O but writing to the stream it is given.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

#include "continuation/sweep.h"

namespace stickslip {

struct ProgressOptions {
  bool terminal = false;         // a bar redrawn in place; false: plain lines
  bool quiet = false;            // print nothing
  double redraw_interval = 0.1;  // s (terminal): minimum time between redraws
  double line_fraction = 0.1;    // plain lines: a line every time this part of the range is done
  double line_interval = 10.0;   // s (plain lines): and at least one line this often
  int bar_width = 20;            // characters inside [ ]
  int columns = 0;  // terminal: the bar narrows (to 4) and the line is cut to fit columns − 1
                    // characters (0: no limit)
  std::string prefix = "stickslip: ";
};
void validate(const ProgressOptions& options);  // throws InvalidInput naming the field

// Options for stderr: terminal when stderr is a terminal (isatty), its width from the terminal
// (80 if unknown), quiet as given.
ProgressOptions stderr_progress_options(bool quiet);

// The stage commands' plain progress lines on stderr, "stickslip: <line>"; nothing when quiet.
std::function<void(const std::string&)> stderr_progress(bool quiet);
// A warning on stderr, "stickslip: warning: <text>" (printed also when quiet; bytes that are not
// printable escaped as \xNN, core/printable.h).
void stderr_warning(const std::string& warning);

// "0:07", "12:34", "1:02:03" (seconds rounded up to whole seconds; "--:--" if not finite).
std::string format_duration(double seconds);

class ProgressReporter {
 public:
  using Clock = std::function<double()>;  // seconds, monotonic
  explicit ProgressReporter(std::ostream& out, ProgressOptions options = {}, Clock clock = {});
  ~ProgressReporter();  // finish()
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  // Starts a stage: `label` names it, total_points > 0 is the number of points (stepped sweep),
  // 0 = unknown (continuation: progress is the fraction of the range). Finishes a running stage.
  void start(const std::string& label, int total_points);
  // After each point; `progress.fraction` in [0, 1]. Never throws.
  void update(const ContinuationProgress& progress) noexcept;
  // Ends the stage: the terminal line is completed with a newline; plain mode writes the final
  // state if the last line did not show it. No effect when no stage runs.
  void finish() noexcept;
  // A callback for SteppedSweepOptions / ArcLengthOptions::on_point bound to this reporter.
  ProgressCallback callback();

 private:
  std::string status(bool plain) const;
  void draw(bool plain);

  std::ostream& out_;
  ProgressOptions options_;
  Clock clock_;
  std::string label_;
  int total_ = 0;
  bool running_ = false;
  double t0_ = 0, last_draw_ = 0;
  int last_step_ = 0;  // plain: line_fraction steps already reported
  bool shown_last_ = true;
  size_t drawn_width_ = 0;
  ContinuationProgress last_{};
  int failed_ = 0;
  bool any_ = false;
};

}  // namespace stickslip

#include "cli/distributed_run.h"

#include <fcntl.h>
#include <unistd.h>

#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "cli/stale_results.h"
#include "cli/summary_file.h"
#include "core/errors.h"
#include "core/types.h"
#include "hbm/frequency_response.h"
#include "io/atomic_file.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

// Message tags of the protocols (checkpoint() of cli/processes.cpp uses 900).
constexpr int kResultTag = 1;   // a study value's files, log and tally
constexpr int kFailureTag = 2;  // a study value failed: log, error line, exit code
constexpr int kDoneTag = 3;     // a process has sent its last value
constexpr int kStopTag = 4;     // rank 0: analyse no more values
constexpr int kFinishTag = 5;   // rank 0: the run is over
constexpr int kSegmentTag = 6;  // a segment of a stepped sweep

int owner(size_t value, int processes) { return static_cast<int>(value % processes); }

void replace_all(std::string& text, const std::string& from, const std::string& to) {
  if (from.empty() || from == to) return;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string() + " to send it to rank 0");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// What this process prints while it lives (descriptor 2, hence stderr and std::cerr): kept in a
// temporary file instead, and handed back by text().
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    file_ = std::tmpfile();
    if (file_ == nullptr) throw std::runtime_error("cannot create a temporary file for the log");
    saved_ = ::dup(2);
    ::dup2(::fileno(file_), 2);
  }
  ~StderrCapture() {
    restore();
    if (file_ != nullptr) std::fclose(file_);
  }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;
  std::string text() {
    restore();
    if (file_ == nullptr) return taken_;  // handed back already
    std::string text;
    std::rewind(file_);
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, file_)) > 0;) text.append(buffer, n);
    std::fclose(file_);
    file_ = nullptr;
    taken_ = text;
    return text;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
  std::string taken_;
};

void put_series(Packer& p, const std::vector<PlotSeries>& series) {
  p.put(static_cast<std::int64_t>(series.size()));
  for (const PlotSeries& s : series) {
    p.put(s.label);
    p.put(s.x);
    p.put(s.y);
    p.put(s.style);
  }
}

std::vector<PlotSeries> get_series(Unpacker& u) {
  std::vector<PlotSeries> series(static_cast<size_t>(u.integer()));
  for (PlotSeries& s : series) {
    s.label = u.text();
    s.x = u.numbers();
    s.y = u.numbers();
    s.style = u.text();
  }
  return series;
}

using ValueCurves = std::vector<std::pair<double, PlotSeries>>;

void put_curves(Packer& p, const ValueCurves& curves) {
  p.put(static_cast<std::int64_t>(curves.size()));
  for (const auto& [value, series] : curves) {
    p.put(value);
    put_series(p, {series});
  }
}

void get_curves(Unpacker& u, ValueCurves* curves) {
  for (auto n = u.integer(); n > 0; --n) {
    const double value = u.number();
    std::vector<PlotSeries> series = get_series(u);
    curves->emplace_back(value, series.at(0));
  }
}

// The tally of one value, its pictures not drawn named as rank 0 names them.
void put_tally(Packer& p, const RunTally& t, const std::string& scratch, const std::string& real) {
  p.put(static_cast<std::int64_t>(t.outcome.failed_points));
  p.put(static_cast<std::int64_t>(t.outcome.incomplete_analyses));
  p.put(static_cast<std::int64_t>(t.overlay.size()));
  for (const auto& [value, series] : t.overlay) {
    p.put(value);
    put_series(p, series);
  }
  put_curves(p, t.mode_overlay.backbone);
  put_curves(p, t.mode_overlay.damping);
  p.put(static_cast<std::int64_t>(t.plots.missing().size()));
  for (std::string picture : t.plots.missing()) {
    replace_all(picture, scratch, real);
    p.put(picture);
  }
}

void add_tally(Unpacker& u, RunTally* t) {
  SolveOutcome outcome;
  outcome.failed_points = static_cast<int>(u.integer());
  outcome.incomplete_analyses = static_cast<int>(u.integer());
  t->outcome += outcome;
  for (auto n = u.integer(); n > 0; --n) {
    const double value = u.number();
    t->overlay.emplace_back(value, get_series(u));
  }
  get_curves(u, &t->mode_overlay.backbone);
  get_curves(u, &t->mode_overlay.damping);
  for (auto n = u.integer(); n > 0; --n) t->plots.add_missing(u.text());
}

// Rank 0: the files of a value analysed elsewhere, written where a run alone writes them; the
// results of an earlier run there removed (and named in summary.json, as the solve names them).
void write_received_files(Unpacker& u, const StageRun& run, const ProgressFn& progress) {
  for (auto n = u.integer(); n > 0; --n) {
    const fs::path relative = u.text();
    const std::string bytes = u.text();
    const fs::path path = run.dir / relative;
    create_output_folder(path.parent_path());
    write_file_atomically(path.string(), [&](std::ostream& out) { out << bytes; });
  }
  const std::vector<std::string> removed = remove_stale_results(run.dir, ResultFamily::kEverything);
  if (removed.empty()) return;
  if (progress) progress(describe_removed(removed));
  const fs::path summary_path = run.dir / "summary.json";
  if (!fs::exists(summary_path)) return;
  nlohmann::ordered_json summary = read_summary(summary_path, "stickslip run");
  summary["removed_stale"] = removed;
  write_summary(run.dir, summary);
}

// Rank 0 after a failure: the other processes stop after the value they are analysing; what
// they still send is dropped.
void stop_the_others(Processes& processes) {
  for (int r = 1; r < processes.size(); ++r) processes.send(r, kStopTag, "");
  for (int r = 1; r < processes.size(); ++r) {
    while (processes.receive(r).tag != kDoneTag) {
    }
  }
  for (int r = 1; r < processes.size(); ++r) processes.send(r, kFinishTag, "");
}

void root_study(Processes& processes, const std::vector<StageRun>& runs, bool quiet,
                const AnalyseFn& analyse, RunTally* tally) {
  const ProgressFn progress = stderr_progress(quiet);
  ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
  if (static_cast<int>(runs.size()) < processes.size()) {
    progress(fmt::format("{} study values on {} processes: {} of them have nothing to do",
                         runs.size(), processes.size(), processes.size() - runs.size()));
  }
  try {
    for (size_t i = 0; i < runs.size(); ++i) {
      const int from = owner(i, processes.size());
      if (from == 0) {
        analyse(runs[i], progress, &reporter, *tally);
        continue;
      }
      const Processes::Message m = processes.receive(from);
      Unpacker u(m.bytes);
      std::string log = u.text();
      std::fputs(log.c_str(), stderr);
      if (m.tag == kFailureTag) {
        const std::string text = u.text();
        throw PeerError(text, static_cast<int>(u.integer()));
      }
      if (m.tag != kResultTag) throw std::runtime_error("unexpected message from a process");
      write_received_files(u, runs[i], progress);
      add_tally(u, tally);
    }
  } catch (...) {
    stop_the_others(processes);
    throw;
  }
  for (int r = 1; r < processes.size(); ++r) {
    if (processes.receive(r).tag != kDoneTag) throw std::runtime_error("unexpected message");
  }
  for (int r = 1; r < processes.size(); ++r) processes.send(r, kFinishTag, "");
}

// A process other than 0: value `run` analysed in its scratch folder `scratch`; returns the
// message for rank 0 (kResultTag or kFailureTag) and never throws.
std::pair<int, std::string> analyse_elsewhere(Processes& processes, const StageRun& real,
                                              const fs::path& scratch, bool quiet,
                                              const AnalyseFn& analyse) {
  StageRun run = real;
  run.reported_dir = real.dir;
  run.dir = scratch / (run.folder.empty() ? fs::path("run") : fs::path(run.folder));
  const std::string scratch_dir = run.dir.string(), real_dir = real.dir.string();
  std::string failure, log;
  int failure_code = 0;
  try {
    StderrCapture capture;
    try {
      if (scratch.empty()) {
        throw InvalidInput(
            {"", 0, "TMPDIR"},
            fmt::format("process {} has no folder for temporary files (TMPDIR: "
                        "{})",
                        processes.rank(),
                        std::getenv("TMPDIR") != nullptr ? std::getenv("TMPDIR") : "not set"));
      }
      std::error_code ignored;
      fs::remove_all(run.dir, ignored);
      create_output_folder(run.dir);
      const ProgressFn printed = stderr_progress(quiet);
      // Each line of progress also lets the sends under way advance.
      const ProgressFn progress = [&](const std::string& line) {
        printed(line);
        processes.progress();
      };
      ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
      RunTally tally;
      analyse(run, progress, &reporter, tally);
      reporter.finish();
      log = capture.text();
      replace_all(log, scratch_dir, real_dir);
      Packer p;
      p.put(log);
      const std::vector<fs::path> files = published_files_under(run.dir);
      p.put(static_cast<std::int64_t>(files.size()));
      for (const fs::path& f : files) {
        p.put(f.generic_string());
        p.put(file_bytes(run.dir / f));
      }
      put_tally(p, tally, scratch_dir, real_dir);
      fs::remove_all(run.dir, ignored);
      return {kResultTag, p.take()};
    } catch (...) {
      failure = describe_failure(std::current_exception(), &failure_code);
      log = capture.text();
    }
  } catch (...) {  // no capture: the log is lost, the error is not
    failure = describe_failure(std::current_exception(), &failure_code);
  }
  std::error_code ignored;
  if (!scratch.empty()) fs::remove_all(run.dir, ignored);
  replace_all(log, scratch_dir, real_dir);
  replace_all(failure, scratch_dir, real_dir);
  Packer p;
  p.put(log);
  p.put(failure);
  p.put(static_cast<std::int64_t>(failure_code));
  return {kFailureTag, p.take()};
}

void other_study(Processes& processes, const std::vector<StageRun>& runs, bool quiet,
                 const AnalyseFn& analyse) {
  std::error_code no_tmp;
  const fs::path tmp = fs::temp_directory_path(no_tmp);
  const fs::path scratch =
      no_tmp ? fs::path() : tmp / fmt::format("stickslip-rank{}-{}", processes.rank(), ::getpid());
  for (size_t i = processes.rank(); i < runs.size(); i += processes.size()) {
    if (processes.pending(0) && processes.receive(0).tag == kStopTag) break;
    const auto [tag, bytes] = analyse_elsewhere(processes, runs[i], scratch, quiet, analyse);
    processes.send(0, tag, bytes);
    if (tag == kFailureTag) break;
  }
  std::error_code ignored;
  if (!scratch.empty()) fs::remove_all(scratch, ignored);
  processes.send(0, kDoneTag, "");
  while (processes.receive(0).tag != kFinishTag) {
  }
}

// Outputs of a point solved on another process.
void put_point(Packer& p, const FrequencyPoint& point) {
  p.put(point.omega);
  p.put(static_cast<std::int64_t>(point.converged));
  p.put(static_cast<std::int64_t>(point.iterations));
  p.put(point.residual_norm);
  p.put(point.message);
  p.put(std::vector<double>(point.unknowns.data(), point.unknowns.data() + point.unknowns.size()));
  p.put(static_cast<std::int64_t>(point.stability_computed));
  const FloquetSummary& f = point.floquet;
  std::vector<double> exponents;
  for (const std::complex<double>& e : f.exponents)
    exponents.insert(exponents.end(), {e.real(), e.imag()});
  p.put(exponents);
  p.put(f.max_real_part);
  p.put(f.max_multiplier);
  p.put(static_cast<std::int64_t>(f.stable));
  p.put(static_cast<std::int64_t>(f.dynamic_modes));
  p.put(static_cast<std::int64_t>(f.quasi_static_modes));
}

FrequencyPoint get_point(Unpacker& u, const HarmonicBalanceSystem& system,
                         const std::vector<int>& history_pairs) {
  const double omega = u.number();
  const bool converged = u.integer() != 0;
  const int iterations = static_cast<int>(u.integer());
  const double residual_norm = u.number();
  const std::string message = u.text();
  const std::vector<double> x = u.numbers();
  // The outputs follow from (x, Ω) as on the process that solved them.
  FrequencyPoint point = evaluate_point(
      system, Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())),
      omega, history_pairs);
  point.converged = converged;
  point.iterations = iterations;
  point.residual_norm = residual_norm;
  point.message = message;
  point.stability_computed = u.integer() != 0;
  const std::vector<double> exponents = u.numbers();
  point.floquet.exponents.resize(static_cast<Eigen::Index>(exponents.size() / 2));
  for (size_t k = 0; k + 1 < exponents.size(); k += 2)
    point.floquet.exponents(static_cast<Eigen::Index>(k / 2)) = {exponents[k], exponents[k + 1]};
  point.floquet.max_real_part = u.number();
  point.floquet.max_multiplier = u.number();
  point.floquet.stable = u.integer() != 0;
  point.floquet.dynamic_modes = static_cast<int>(u.integer());
  point.floquet.quasi_static_modes = static_cast<int>(u.integer());
  return point;
}

FrequencyResponse sweep_segments(Processes& processes, const HarmonicBalanceSystem& system,
                                 const FrequencyResponseOptions& options) {
  const size_t n = options.omegas.size(), parts = static_cast<size_t>(processes.size());
  const auto first = [&](size_t r) { return n * r / parts; };  // segment r: [first(r), first(r+1))
  const auto describe = [&](size_t r) {
    return first(r) < first(r + 1)
               ? fmt::format("points {}-{} ({:.6g}-{:.6g} Hz)", first(r), first(r + 1) - 1,
                             rad_s_to_hz(options.omegas[first(r)]),
                             rad_s_to_hz(options.omegas[first(r + 1) - 1]))
               : std::string("no points");
  };
  const size_t r = static_cast<size_t>(processes.rank());
  FrequencyResponse mine;
  std::string failure;
  int failure_code = 0;
  try {
    if (first(r) < first(r + 1)) {
      FrequencyResponseOptions o = options;
      o.omegas.assign(options.omegas.begin() + static_cast<std::ptrdiff_t>(first(r)),
                      options.omegas.begin() + static_cast<std::ptrdiff_t>(first(r + 1)));
      // The progress (rank 0's) is of the whole sweep: this segment is its share of it.
      const double share = static_cast<double>(o.omegas.size()) / static_cast<double>(n);
      if (options.sweep.on_point) {
        o.sweep.on_point = [user = options.sweep.on_point, share](const ContinuationProgress& p) {
          ContinuationProgress whole = p;
          whole.fraction *= share;
          user(whole);
        };
      }
      mine = frequency_response(system, o);
    } else {
      mine.completed = true;
      mine.harmonics = system.output_harmonics();
    }
  } catch (...) {
    if (processes.root()) throw;  // the others wait for messages that never come: see below
    failure = describe_failure(std::current_exception(), &failure_code);
  }
  if (!processes.root()) {
    Packer p;
    if (failure.empty()) {
      p.put(static_cast<std::int64_t>(mine.completed));
      p.put(mine.message);
      p.put(static_cast<std::int64_t>(mine.points.size()));
      for (const FrequencyPoint& point : mine.points) put_point(p, point);
    } else {
      p.put(failure);
      p.put(static_cast<std::int64_t>(failure_code));
    }
    processes.send(0, failure.empty() ? kSegmentTag : kFailureTag, p.take());
    throw SegmentSent();
  }
  FrequencyResponse all = std::move(mine);
  std::string message = fmt::format("segment 0, {}: {}", describe(0), all.message);
  for (int from = 1; from < processes.size(); ++from) {
    const Processes::Message m = processes.receive(from);
    Unpacker u(m.bytes);
    if (m.tag == kFailureTag) {
      const std::string text = u.text();
      throw PeerError(text + fmt::format(" (process {})", from), static_cast<int>(u.integer()));
    }
    const bool completed = u.integer() != 0;
    const std::string segment_message = u.text();
    for (auto k = u.integer(); k > 0; --k) {
      all.points.push_back(get_point(u, system, options.history_pairs));
    }
    all.completed = all.completed && completed;
    message += fmt::format("; segment {}, {}: {}", from, describe(static_cast<size_t>(from)),
                           segment_message);
  }
  all.message = fmt::format("{} segments on {} processes, each from its own start: {}",
                            processes.size(), processes.size(), message);
  return all;
}

}  // namespace

void analyse_study_on_processes(Processes& processes, const std::vector<StageRun>& runs, bool quiet,
                                const AnalyseFn& analyse, RunTally* tally) {
  if (processes.root()) {
    root_study(processes, runs, quiet, analyse, tally);
  } else {
    other_study(processes, runs, quiet, analyse);
  }
}

SweepRunner segment_runner(Processes& processes, bool* reached) {
  return [&processes, reached](const HarmonicBalanceSystem& system,
                               const FrequencyResponseOptions& options) {
    *reached = true;
    processes.checkpoint(nullptr);  // every process has its system: the sweep can be cut
    return sweep_segments(processes, system, options);
  };
}

void silence_stderr() {
  std::fflush(stderr);
  const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (null < 0) return;
  ::dup2(null, 2);
  ::close(null);
}

}  // namespace stickslip

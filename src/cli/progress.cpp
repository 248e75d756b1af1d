#include "cli/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

#include <fmt/core.h>

#include "core/errors.h"
#include "core/printable.h"

namespace stickslip {

void validate(const ProgressOptions& o) {
  require(std::isfinite(o.redraw_interval) && o.redraw_interval >= 0,
          "ProgressOptions.redraw_interval", fmt::format("{:g}", o.redraw_interval), ">= 0");
  require(o.line_fraction > 0 && o.line_fraction <= 1, "ProgressOptions.line_fraction",
          fmt::format("{:g}", o.line_fraction), "in (0, 1]");
  require(o.line_interval > 0, "ProgressOptions.line_interval",
          fmt::format("{:g}", o.line_interval), "> 0");
  require(o.bar_width >= 1, "ProgressOptions.bar_width", std::to_string(o.bar_width), ">= 1");
  require(o.columns >= 0, "ProgressOptions.columns", std::to_string(o.columns), ">= 0");
}

ProgressOptions stderr_progress_options(bool quiet) {
  ProgressOptions o;
  o.terminal = isatty(fileno(stderr)) != 0;
  if (o.terminal) {
    winsize w{};
    o.columns = ioctl(fileno(stderr), TIOCGWINSZ, &w) == 0 && w.ws_col > 0 ? w.ws_col : 80;
  }
  o.quiet = quiet;
  return o;
}

std::function<void(const std::string&)> stderr_progress(bool quiet) {
  return [quiet](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "stickslip: %s\n", line.c_str());
  };
}

void stderr_warning(const std::string& warning) {
  std::fprintf(stderr, "stickslip: warning: %s\n", printable(warning).c_str());
}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long long s = static_cast<long long>(std::ceil(seconds));
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

ProgressReporter::ProgressReporter(std::ostream& out, ProgressOptions options, Clock clock)
    : out_(out), options_(std::move(options)), clock_(std::move(clock)) {
  validate(options_);
  if (!clock_) {
    clock_ = [] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
          .count();
    };
  }
}

ProgressReporter::~ProgressReporter() { finish(); }

void ProgressReporter::start(const std::string& label, int total_points) {
  finish();
  label_ = label;
  total_ = std::max(0, total_points);
  running_ = true;
  t0_ = clock_();
  last_draw_ = t0_;
  last_step_ = 0;
  shown_last_ = true;
  drawn_width_ = 0;
  last_ = {};
  failed_ = 0;
  any_ = false;
}

std::string ProgressReporter::status(bool plain) const {
  const double elapsed = clock_() - t0_;
  const double f = std::clamp(last_.fraction, 0.0, 1.0);
  const std::string percent = fmt::format("{}%", static_cast<int>(std::floor(100 * f + 1e-9)));
  const std::string points = total_ > 0 ? fmt::format("{}/{} points", last_.points, total_)
                                        : fmt::format("{} points", last_.points);
  const std::string rate = elapsed > 0 ? fmt::format("{:.3g} points/s", last_.points / elapsed)
                                       : std::string("- points/s");
  const std::string left =
      f >= 1 ? std::string("0:00 left")
             : (f > 0 && elapsed > 0 ? format_duration(elapsed * (1 - f) / f) + " left"
                                     : std::string("--:-- left"));
  const std::string failed = failed_ > 0 ? fmt::format(", {} not converged", failed_) : "";
  if (plain) {
    return fmt::format("{}{}: {} ({}{}{}), {}, {}", options_.prefix, label_, points,
                       total_ > 0 ? "" : "range ", percent, failed, rate, left);
  }
  // The bar shrinks (down to kMinBar) to keep the line within the terminal's width.
  constexpr int kMinBar = 4;
  const std::string head = options_.prefix + label_ + " [";
  const std::string tail = fmt::format("] {:>4} {}{} {} {}", percent, points, failed, rate, left);
  int width = options_.bar_width;
  if (options_.columns > 0) {
    const int room = options_.columns - 1 - static_cast<int>(head.size() + tail.size());
    width = std::clamp(room, std::min(kMinBar, options_.bar_width), options_.bar_width);
  }
  const int filled = static_cast<int>(std::floor(f * width));
  return head + std::string(static_cast<size_t>(filled), '#') +
         std::string(static_cast<size_t>(width - filled), '-') + tail;
}

void ProgressReporter::draw(bool plain) {
  std::string s = status(plain);
  if (!plain && options_.columns > 0 && s.size() >= static_cast<size_t>(options_.columns)) {
    s.resize(static_cast<size_t>(options_.columns - 1));  // a wrapped line cannot be redrawn
  }
  if (plain) {
    out_ << s << '\n';
  } else {
    // Blank out what is left of a longer previous line.
    const size_t pad = drawn_width_ > s.size() ? drawn_width_ - s.size() : 0;
    out_ << '\r' << s << std::string(pad, ' ');
    drawn_width_ = s.size();
  }
  out_.flush();
  last_draw_ = clock_();
}

void ProgressReporter::update(const ContinuationProgress& progress) noexcept {
  if (!running_ || options_.quiet) return;
  try {
    last_ = progress;
    any_ = true;
    if (!progress.converged) ++failed_;
    const double now = clock_();
    const double f = std::clamp(progress.fraction, 0.0, 1.0);
    if (options_.terminal) {
      if (f >= 1 || now - last_draw_ >= options_.redraw_interval || drawn_width_ == 0) {
        draw(false);
        shown_last_ = true;
      } else {
        shown_last_ = false;
      }
      return;
    }
    // Steps of line_fraction reached (a small tolerance so that 3/10 counts as 30 %).
    const int step = static_cast<int>(std::floor(f / options_.line_fraction + 1e-9));
    if (step > last_step_ || now - last_draw_ >= options_.line_interval) {
      last_step_ = std::max(last_step_, step);
      draw(true);
      shown_last_ = true;
    } else {
      shown_last_ = false;
    }
  } catch (...) {
    // Progress output must never stop a solve.
  }
}

void ProgressReporter::finish() noexcept {
  if (!running_) return;
  running_ = false;
  if (options_.quiet || !any_) return;
  try {
    if (options_.terminal) {
      if (!shown_last_) draw(false);
      out_ << '\n';
      out_.flush();
    } else if (!shown_last_) {
      draw(true);
    }
  } catch (...) {
  }
}

ProgressCallback ProgressReporter::callback() {
  return [this](const ContinuationProgress& p) { update(p); };
}

}  // namespace stickslip

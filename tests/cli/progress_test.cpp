// The progress reporter's output, driven by an injected clock into a string stream: plain lines
// every 10 % (and after line_interval seconds of silence) when the stream is not a terminal, one
// bar redrawn in place on a terminal, nothing when quiet. Rates and times left are checked against
// the hand values of the injected clock.
#include "cli/progress.h"

#include <gtest/gtest.h>

#include "core/errors.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace stickslip {
namespace {

std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string line;
  while (std::getline(ss, line)) out.push_back(line);
  return out;
}

// A clock the test sets by hand.
struct FakeClock {
  double now = 100.0;  // s; an arbitrary origin
  ProgressReporter::Clock clock() {
    return [this] { return now; };
  }
};

ContinuationProgress point(int done, int total, bool converged = true) {
  return {done, 0.0, static_cast<double>(done) / total, converged};
}

// The output of a stage "harmonic balance" of `total` points with one update, `done` points
// 1 s after the start.
std::string one_update(const ProgressOptions& o, int done, int total) {
  std::ostringstream out;
  FakeClock t;
  ProgressReporter r(out, o, t.clock());
  r.start("harmonic balance", total);
  t.now += 1;
  r.update(point(done, total));
  r.finish();
  return out.str();
}

TEST(Progress, DurationsAreMinutesSecondsOrHours) {
  EXPECT_EQ(format_duration(0), "0:00");
  EXPECT_EQ(format_duration(6.2), "0:07");  // rounded up: never promise too little
  EXPECT_EQ(format_duration(754), "12:34");
  EXPECT_EQ(format_duration(3723), "1:02:03");
  EXPECT_EQ(format_duration(-1), "--:--");
}

TEST(Progress, PlainLinesEveryTenPercentWithRateAndTimeLeft) {
  std::ostringstream out;
  FakeClock t;
  ProgressOptions o;
  o.terminal = false;
  ProgressReporter r(out, o, t.clock());
  r.start("harmonic balance", 40);
  for (int i = 1; i <= 40; ++i) {
    t.now += 0.5;  // 2 points/s
    r.update(point(i, 40));
  }
  r.finish();
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 10u) << out.str();  // 10 %, 20 %, ..., 100 %
  EXPECT_EQ(out.str().find('\r'), std::string::npos);
  // After 4 points: 2 s elapsed, 10 % done, so 18 s left.
  EXPECT_EQ(lines[0], "stickslip: harmonic balance: 4/40 points (10%), 2 points/s, 0:18 left");
  EXPECT_EQ(lines[4], "stickslip: harmonic balance: 20/40 points (50%), 2 points/s, 0:10 left");
  EXPECT_EQ(lines[9], "stickslip: harmonic balance: 40/40 points (100%), 2 points/s, 0:00 left");
}

TEST(Progress, PlainLineAfterIntervalOfSilenceAndFinalStateAtFinish) {
  std::ostringstream out;
  FakeClock t;
  ProgressOptions o;
  o.line_interval = 5.0;
  ProgressReporter r(out, o, t.clock());
  r.start("harmonic balance", 1000);
  t.now += 6.0;  // one slow point: no 10 % step, but 6 s since the start
  r.update(point(1, 1000));
  t.now += 1.0;
  r.update(point(2, 1000, /*converged=*/false));  // nothing: 1 s since the last line
  r.finish();  // the state after point 2 was not shown: one more line
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 2u) << out.str();
  EXPECT_EQ(lines[0],
            "stickslip: harmonic balance: 1/1000 points (0%), 0.167 points/s, 1:39:54 left");
  // 2 points in 7 s; 998 left at 3.5 s each.
  EXPECT_EQ(lines[1],
            "stickslip: harmonic balance: 2/1000 points (0%, 1 not converged), 0.286 points/s, "
            "58:13 left");
}

TEST(Progress, ContinuationShowsPointsAndTheRangeCovered) {
  std::ostringstream out;
  FakeClock t;
  ProgressReporter r(out, ProgressOptions{}, t.clock());
  r.start("harmonic balance", 0);
  t.now += 10;
  r.update({25, 0.0, 0.25, true});
  r.finish();
  EXPECT_EQ(out.str(),
            "stickslip: harmonic balance: 25 points (range 25%), 2.5 points/s, 0:30 left\n");
}

TEST(Progress, TerminalBarIsRedrawnInPlaceAndThrottled) {
  std::ostringstream out;
  FakeClock t;
  ProgressOptions o;
  o.terminal = true;
  o.bar_width = 10;
  o.redraw_interval = 1.0;
  ProgressReporter r(out, o, t.clock());
  r.start("hb", 4);
  t.now += 2;
  r.update(point(1, 4));  // drawn (first)
  t.now += 0.5;
  r.update(point(2, 4));  // 0.5 s after the last draw: skipped
  t.now += 0.5;
  r.update(point(3, 4));  // 1 s: drawn
  t.now += 0.1;
  r.update(point(4, 4));  // the last point: always drawn
  r.finish();
  const std::string s = out.str();
  EXPECT_EQ(std::count(s.begin(), s.end(), '\r'), 3) << s;
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1) << s;  // only at finish
  EXPECT_NE(s.find("\rstickslip: hb [##--------]  25% 1/4 points 0.5 points/s 0:06 left"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("\rstickslip: hb [#######---]  75% 3/4 points 1 points/s 0:01 left"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("\rstickslip: hb [##########] 100% 4/4 points 1.29 points/s 0:00 left"),
            std::string::npos)
      << s;
  EXPECT_EQ(s.back(), '\n');
}

TEST(Progress, TerminalBarBlanksTheRestOfALongerPreviousLine) {
  std::ostringstream out;
  FakeClock t;
  ProgressOptions o;
  o.terminal = true;
  o.redraw_interval = 0;
  ProgressReporter r(out, o, t.clock());
  r.start("hb", 1000);
  t.now += 6;
  r.update(point(1, 1000));                   // "... 1/1000 points  0.167 points/s  1:39:54 left"
  const size_t first = out.str().size() - 1;  // without its leading '\r'
  t.now += 1;
  r.update(point(500, 1000));  // "... 500/1000 points 71.4 points/s 0:07 left": 2 shorter
  const std::string s = out.str();
  const std::string second = s.substr(first + 2);  // after the second '\r'
  EXPECT_EQ(second.size(), first);                 // padded to the width of the previous line
  EXPECT_EQ(second.substr(second.size() - 2), "  ");
  EXPECT_NE(second.find("0:07 left  "), std::string::npos) << second;
}

TEST(Progress, TerminalLinesFitTheTerminalWidth) {
  ProgressOptions o;
  o.terminal = true;
  o.bar_width = 20;
  // 80 columns: the bar narrows from 20 to 11 so that the line has 79 characters.
  o.columns = 80;
  EXPECT_EQ(one_update(o, 5, 10),
            "\rstickslip: harmonic balance [#####------]  50% 5/10 points 5 points/s 0:01 left\n");
  // 40 columns: the bar at its minimum (4) and the line cut to 39 characters.
  o.columns = 40;
  EXPECT_EQ(one_update(o, 10, 10), "\rstickslip: harmonic balance [####] 100%\n");
}

TEST(Progress, QuietPrintsNothing) {
  std::ostringstream out;
  FakeClock t;
  ProgressOptions o;
  o.quiet = true;
  for (bool terminal : {false, true}) {
    o.terminal = terminal;
    ProgressReporter r(out, o, t.clock());
    r.start("hb", 2);
    r.update(point(1, 2));
    r.update(point(2, 2));
    r.finish();
  }
  EXPECT_TRUE(out.str().empty());
}

TEST(Progress, BadOptionsAreRejected) {
  std::ostringstream out;
  ProgressOptions o;
  o.line_fraction = 0;
  EXPECT_THROW(ProgressReporter(out, o), InvalidInput);
}

}  // namespace
}  // namespace stickslip

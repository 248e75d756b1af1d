// End-to-end: inputs that make no sense (damaged, contradictory, absurd) go through `stickslip`
// and stop with exit 2 and a message naming the file, the line and the key (issue 26; docs/
// case-file.md states each rule). Each test builds its input from a small valid case and first
// checks that the valid case is accepted where the difference matters, so a refusal cannot come
// from something else.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace stickslip::cli_test;

struct Outcome {
  int code = -1;
  std::string log;  // stdout and stderr
};

Outcome run_in(const fs::path& dir, const std::string& args) {
  Outcome o;
  o.code = run(args, dir / "log.txt");
  o.log = slurp(dir / "log.txt");
  return o;
}

// Exit 2 and a message holding every part (file:line, key, rule), on one line.
void expect_refused(const Outcome& o, const std::vector<std::string>& parts) {
  EXPECT_EQ(o.code, 2) << o.log;
  for (const std::string& p : parts) EXPECT_NE(o.log.find(p), std::string::npos) << p << "\n" << o.log;
}

// The small joint without recovery output files or plots, fast to run.
std::string quick_joint(const std::string& tail = "recovery: {points: none}\n") {
  return small_joint_case(0.5, 150, tail + "output: {vtu: false, plots: false}\n");
}

int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << needle;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

TEST(NonsenseInput, CaseFileThatIsNotUtf8) {
  const fs::path dir = fresh_dir("nonsense_utf8");
  std::string text = quick_joint();
  text.replace(text.find("title: small joint"), 18, "title: small \xff\xfe joint");
  const fs::path file = write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":2: ", "byte \\xFF (column 14) is not UTF-8"});
  EXPECT_FALSE(fs::exists(dir / "out" / "points.csv"));
  // UTF-8 text (a name with accents) is fine.
  text.replace(text.find("small \xff\xfe joint"), 14, "small j\xC3\xB6int");
  write_case(dir, "case", text);
  EXPECT_EQ(run_in(dir, "run " + file.string() + " -q -o " + (dir / "out").string()).code, 0);
}

TEST(NonsenseInput, CaseFileTooLargeIsRefusedBeforeItIsRead) {
  const fs::path dir = fresh_dir("nonsense_huge");
  // 1 GiB: a sparse file (no disk space); reading it into a YAML tree took 5.8 GB.
  const fs::path file = write_case(dir, "case", "stickslip: 1\nbodies: [");
  fs::resize_file(file, std::uintmax_t{1} << 30);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ": ", "1073741824 bytes", "at most 16777216 bytes"});
}

}  // namespace

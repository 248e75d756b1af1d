// End-to-end: inputs that make no sense (damaged, contradictory, absurd) go through `stickslip`
// and stop with exit 2 and a message naming the file, the line and the key (issue 26; docs/
// case-file.md states each rule). Each test builds its input from a small valid case and first
// checks that the valid case is accepted where the difference matters, so a refusal cannot come
// from something else.
#include <gtest/gtest.h>

#include "cli_test_support.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <sstream>
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
  for (const std::string& p : parts)
    EXPECT_NE(o.log.find(p), std::string::npos) << p << "\n" << o.log;
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

TEST(NonsenseInput, RecoveryNodeThatIsNotInAnyBody) {
  const fs::path dir = fresh_dir("nonsense_recovery_node");
  const std::string text = quick_joint("recovery: {points: peak, nodes: [12,\n  999999]}\n");
  const fs::path file = write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":" + std::to_string(line_of(text, "999999")) +
                  ": recovery.nodes[1]: node 999999 is not a node of any body"});
  EXPECT_FALSE(fs::exists(dir / "out" / "points.csv"));
}

TEST(NonsenseInput, ContactPairThatJoinsANodeToItself) {
  const fs::path dir = fresh_dir("nonsense_self_pair");
  std::string text = quick_joint();
  const std::string between = "between: {beam1: CONTACT1, beam2: CONTACT2}";
  text.replace(text.find(between), between.size(),
               "bodies: [beam1, beam1]\n    pairs: [[1, 2],\n      [3, 3]]");
  const fs::path file = write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":" + std::to_string(line_of(text, "[3, 3]")) +
                  ": contacts.joint.pairs: the pair joins node 3 of body beam1 to itself"});
  // The same from a pairs_file, at the file's line.
  std::ofstream(dir / "pairs.csv") << "node_a,node_b\n1,2\n4,4\n";
  text.replace(text.find("pairs: [[1, 2],\n      [3, 3]]"), 29, "pairs_file: pairs.csv");
  write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {(dir / "pairs.csv").string() + ":3: contacts.joint.pairs[1]: the pair joins "
                                                 "node 4 of body beam1 to itself"});
}

TEST(NonsenseInput, PreloadFileNamingANodeTheContactDoesNotHave) {
  const fs::path dir = fresh_dir("nonsense_preload_file");
  std::string text = quick_joint();
  text.replace(text.find(", preload: 150}"), 15, "}\n    preload_file: preload.csv");
  std::ofstream(dir / "preload.csv") << "# node, N0\n999999, 100\n";
  const fs::path file = write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {(dir / "preload.csv").string() + ":2: contacts.joint.preloads[0]: node 999999 "
                                                   "is not the first node (body beam1) of any "
                                                   "pair of contact joint"});
}

TEST(NonsenseInput, StudyValuesThatShareAnOutputFolder) {
  const fs::path dir = fresh_dir("nonsense_study");
  const std::string study = "study:\n  parameter: contacts.joint.per_pair.preload\n  values:\n";
  // The same value twice.
  std::string text = quick_joint() + study + "    - 150\n    - 100\n    - 150.0\n";
  const fs::path file = write_case(dir, "case", text);
  const int second = line_of(text, "150.0\n");
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":" + std::to_string(second) +
                  ": study.values: the value 150 is listed twice (first on line " +
                  std::to_string(second - 2) + ")"});
  // Two values whose folders would both be preload_150.
  text = quick_joint() + study + "    - 150\n    - 150.0000001\n";
  write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":" + std::to_string(line_of(text, "150.0000001")) +
                      ": study.values: values 150.0000001 and 150",
                  "folder preload_150/"});
  EXPECT_FALSE(fs::exists(dir / "out" / "preload_150"));
}

TEST(NonsenseInput, UnterminatedQuoteIsReportedWhereItStarts) {
  const fs::path dir = fresh_dir("nonsense_quote");
  std::string text = quick_joint();
  text.replace(text.find("title: small joint"), 18, "title: \"small joint");
  const fs::path file = write_case(dir, "case", text);
  expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                 {file.string() + ":2: the string quoted with \" at column 8 is not closed"});
  // Quotes that are closed, with escapes, are fine.
  text.replace(text.find("\"small joint"), 12, "'small ''joint'' \"1\"'");
  write_case(dir, "case", text);
  EXPECT_EQ(run_in(dir, "run " + file.string() + " -q -o " + (dir / "out").string()).code, 0);
}

TEST(NonsenseInput, AbsurdMagnitudesStopAtTheirKey) {
  const fs::path dir = fresh_dir("nonsense_magnitude");
  for (const auto& [from, to, key] : std::vector<std::array<std::string, 3>>{
           {"preload: 150", "preload: 1e300", "contacts.joint.per_pair.preload"},
           {"density: 7800", "density: 1.0e+300", "materials.steel.density"},
           {"amplitude: 50}", "amplitude: 1e-200}", "excitation[0].amplitude"}}) {
    std::string text = quick_joint();
    text.replace(text.find(from), from.size(), to);
    const fs::path file = write_case(dir, "case", text);
    expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                   {file.string() + ":" + std::to_string(line_of(text, to)) + ": " + key + ": ",
                    "out of range: numbers of a case are 0 or of magnitude between 1e-30 and "
                    "1e+30"});
  }
}

TEST(NonsenseInput, RecoverRefusesContactForcesThatAreNotFinite) {
  const fs::path dir = fresh_dir("nonsense_recover_nan");
  const fs::path file = write_case(dir, "case", quick_joint("recovery: {points: peak}\n"));
  const std::string out = (dir / "out").string();
  ASSERT_EQ(run_in(dir, "solve -q " + file.string() + " -o " + out).code, 0);
  ASSERT_EQ(run_in(dir, "recover -q " + file.string() + " -o " + out).code, 0);
  // Every point of this sweep converges: damage the real part of one force row.
  std::vector<std::string> lines;
  {
    std::ifstream in(dir / "out" / "contact_forces.csv");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_GT(lines.size(), 10u);
  const size_t damaged = 7;  // 0-based: line 8 of the file
  std::vector<std::string> cells;
  {
    std::stringstream ss(lines[damaged]);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
  }
  ASSERT_EQ(cells.size(), 10u);
  cells[8] = "nan";
  lines[damaged].clear();
  for (size_t i = 0; i < cells.size(); ++i) lines[damaged] += (i ? "," : "") + cells[i];
  {
    std::ofstream o(dir / "out" / "contact_forces.csv");
    for (const std::string& line : lines) o << line << "\n";
  }
  expect_refused(run_in(dir, "recover " + file.string() + " -o " + out),
                 {(dir / "out" / "contact_forces.csv").string() +
                  ":8: the force of converged point " + cells[0] + " is not a finite number"});
}

// Example 01 (a 1-DOF oscillator given by Harwell-Boeing matrices and an ANSYS mapping) copied to
// `dir`, with a coarse sweep; returns the case file.
fs::path oscillator_case(const fs::path& dir) {
  const fs::path example =
      fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples" / "01_jenkins_oscillator";
  for (const char* f : {"K.hb", "M.hb", "K.mapping", "case.yaml"}) {
    fs::copy_file(example / f, dir / f, fs::copy_options::overwrite_existing);
  }
  std::string text = slurp(dir / "case.yaml");
  text.replace(text.find("step_hz: 0.5"), 12, "step_hz: 20");
  text.replace(text.find("plots: true"), 11, "plots: false");
  return write_case(dir, "case", text);
}

TEST(NonsenseInput, MappingFileRowsThatAreDuplicatedOrMislabelled) {
  const fs::path dir = fresh_dir("nonsense_mapping");
  const fs::path file = oscillator_case(dir);
  const std::string args = "run " + file.string() + " -q -o " + (dir / "out").string();
  ASSERT_EQ(run_in(dir, args).code, 0);
  const std::string mapping = (dir / "K.mapping").string();
  // Node 1 UX twice (the UY row mislabelled).
  std::ofstream(dir / "K.mapping") << "Matrix Eqn   Node   DOF\n1 1 UX\n2 1 UX\n3 1 UZ\n";
  expect_refused(run_in(dir, args),
                 {mapping + ":3: DOF: node 1 UX is mapped twice (also on line 2)"});
  // A label that is no DOF label (it was read as a generalised coordinate: "node 1 direction y is
  // not a DOF" later, at the body).
  std::ofstream(dir / "K.mapping") << "Matrix Eqn   Node   DOF\n1 1 UX\n2 1 UQ\n3 1 UZ\n";
  expect_refused(run_in(dir, args), {mapping + ":3: DOF: 'UQ' is not a DOF label"});
}

TEST(NonsenseInput, NodeThatIsNotADofOfAReducedBodyNamesTheEntryThatAskedForIt) {
  const fs::path dir = fresh_dir("nonsense_not_a_dof");
  const fs::path file = oscillator_case(dir);
  std::string text = slurp(file);
  // The excitation, the FRF and the contact pair in turn ask for node 2, which the mapping lacks.
  for (const auto& [from, to, key] : std::vector<std::array<std::string, 3>>{
           {"{body: oscillator, node: 1, direction: x, amplitude: 5}",
            "{body: oscillator, node: 2, direction: x, amplitude: 5}", "excitation[0]"},
           {"{body: oscillator, node: 1, direction: x}",
            "{body: oscillator, node: 2, direction: x}", "output.frf[0]"},
           {"pairs: [1]", "pairs: [2]", "contacts.jenkins.pairs[0]"}}) {
    std::string changed = text;
    changed.replace(changed.find(from), from.size(), to);
    write_case(dir, "case", changed);
    expect_refused(run_in(dir, "run " + file.string() + " -o " + (dir / "out").string()),
                   {file.string() + ":" + std::to_string(line_of(changed, to)) + ": " + key +
                    ": node 2 direction x is not a DOF of the reduced matrices of body "
                    "oscillator"});
  }
}

}  // namespace

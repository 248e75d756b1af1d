// End-to-end: text from a case file and the output folder's name never reaches a shell or
// gnuplot's interpreter. A tiny study whose title, body name, contact name (hence the study's
// parameter) and output folder hold backquotes, $(...), quotes, a newline and semicolons, each
// with a command that would create a marker file, runs through `stickslip run` and `stickslip
// plot` with the real gnuplot: no marker appears, and every picture is drawn, complete, with the
// text shown literally.
#include <gtest/gtest.h>

#include <fcntl.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "cli_test_support.h"
#include "../required_tool.h"

namespace stickslip::cli_test {
namespace {

bool have_gnuplot() { return std::system("command -v gnuplot > /dev/null 2>&1") == 0; }

// A PNG that ends with its IEND chunk (what a complete file does).
bool complete_png(const fs::path& p) {
  const std::string b = slurp(p);
  return b.size() > 20 && b.compare(0, 4, "\x89PNG") == 0 &&
         b.compare(b.size() - 8, 4, "IEND") == 0;
}

// Every way to make gnuplot or a shell run `touch <marker>`: backquotes (gnuplot substitutes them
// in double-quoted strings), $(...) and `;` (a shell), quotes to end a string early, gnuplot's
// system(), a newline to end a command and a trailing backslash to continue one (when `free_text`:
// names may hold neither, docs/case-file.md).
// The marker is ${SS_MARK}<what>_<how>: no slash in the text (a name may become a file name), the
// environment of the program gives the folder.
std::string hostile(const std::string& what, bool free_text) {
  const std::string m = "${SS_MARK}" + what;
  return "x`touch " + m + "_bq` $(touch " + m + "_dollar) ' \"; touch " + m + "_semi; \" '; " +
         "system('touch " + m + "_sys'); " + (free_text ? "\n!touch " + m + "_nl \\" : "");
}

// Names in the case: the title (free text, with newlines), a body and a contact (the study's
// parameter names the contact).
std::string tiny_case() {
  // Appended rather than `"b" + hostile(...)`: gcc 12 at -O2/-O3 warns -Wrestrict on
  // operator+(const char*, std::string&&) (a false positive of its memcpy overlap analysis).
  std::string body = "b";
  body += hostile("body", false);
  std::string contact = "c";
  contact += hostile("contact", false);
  // YAML double-quoted scalars: escape backslashes and quotes; \n in the title is a newline.
  const auto yaml = [](const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
      if (c == '\\' || c == '"') out += '\\';
      if (c == '\n') {
        out += "\\n";
        continue;
      }
      out += c;
    }
    return out + "\"";
  };
  const std::string b = yaml(body), c = yaml(contact);
  return "stickslip: 1\n"
         "title: " + yaml("line one\n" + hostile("title", true)) + "\n"
         "materials:\n"
         "  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}\n"
         "meshes:\n"
         "  joint: {generate: two_beam, arrangement: butt, element: C3D8, box: [4, 2, 2], "
         "end_block: [2, 2, 1]}\n"
         "bodies:\n"
         "  " + b + ": {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, "
         "masters: [FORCE1], modes: 4}\n"
         "  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, "
         "masters: [FORCE2], modes: 4}\n"
         "contacts:\n"
         "  - name: " + c + "\n"
         "    law: friction\n"
         "    between: {" + b + ": CONTACT1, beam2: CONTACT2}\n"
         "    normal: [1, 0, 0]\n"
         "    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.3, preload: 50}\n"
         "excitation:\n"
         "  - {body: " + b + ", node_set: FORCE1, direction: y, amplitude: 50}\n"
         "  - {body: beam2, node_set: FORCE2, direction: -y, amplitude: 50}\n"
         "damping: {alpha: 5.0, beta: 0.0}\n"
         "analysis:\n"
         "  frequency: {around_mode: 4, half_width_hz: 4, step_hz: 2}\n"
         "  harmonics: 1\n"
         "  time_samples: 32\n"
         "study:\n"
         "  parameter: " + yaml("contacts." + contact + ".per_pair.preload") + "\n"
         "  values: [50, 80]\n"
         "recovery: {points: all}\n"
         "output:\n"
         "  vtu: false\n"
         "  histories: {" + c + ": [0]}\n"
         "  frf:\n"
         "    - {body: " + b + ", node: 11, direction: y}\n";
}

std::vector<fs::path> markers(const fs::path& root) {
  std::vector<fs::path> found;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    if (e.path().filename().string().find("mark_") == 0) found.push_back(e.path());
  }
  return found;
}

TEST(PlotSafety, HostileNamesRunNothingAndArePlottedLiterally) {
  STICKSLIP_REQUIRE_TOOL(have_gnuplot(), "gnuplot");
  const fs::path dir = fresh_dir("plot_safety");
  const fs::path marks = dir / "marks";
  fs::create_directories(marks);
  const fs::path file = write_case(dir, "case", tiny_case());
  setenv("SS_MARK", (marks / "mark_").c_str(), 1);
  // The output folder's name: shell and gnuplot syntax too (no slash, so it is one folder).
  const std::string folder = "out" + hostile("dir", true);
  const fs::path out = dir / folder;
  const fs::path log = dir / "run.log";
  // The program is started without a shell here: the folder name reaches it verbatim.
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1), dup2(fd, 2);
    if (chdir(dir.c_str()) != 0) _exit(126);
    execl(kProgram.c_str(), "stickslip", "run", file.c_str(), "-o", out.c_str(), (char*)nullptr);
    _exit(127);
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(log);
  // No warning but the case's own (a response peak at the edge of its window).
  EXPECT_EQ(count(slurp(log), "warning"), count(slurp(log), "is at the edge of the sweep window"))
      << slurp(log);
  EXPECT_TRUE(markers(dir).empty()) << markers(dir).front();

  // Every picture is there and complete; the SVGs show the hostile text as text.
  const std::string study_folder = "preload_50";
  for (const std::string stem : {"frf", "contact_state", "hysteresis", "frf_full_vs_reduced"}) {
    for (const std::string value : {"preload_50", "preload_80"}) {
      EXPECT_TRUE(complete_png(out / value / (stem + ".png"))) << value << "/" << stem;
      EXPECT_NE(slurp(out / value / (stem + ".svg")).find("</svg>"), std::string::npos);
    }
  }
  EXPECT_TRUE(complete_png(out / "frf_study.png"));
  const std::string svg = slurp(out / "frf_study.svg");
  EXPECT_NE(svg.find("$(touch ${SS_MARK}title_dollar)"), std::string::npos);
  EXPECT_NE(svg.find("`touch ${SS_MARK}body_bq`"), std::string::npos);
  EXPECT_NE(svg.find("`touch ${SS_MARK}contact_bq`"), std::string::npos);

  // Redrawing from the files runs nothing either, and draws the same pictures.
  fs::remove(out / study_folder / "frf.png");
  fs::remove(out / study_folder / "frf_full_vs_reduced.svg");
  const pid_t plot = fork();
  if (plot == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1), dup2(fd, 2);
    if (chdir(dir.c_str()) != 0) _exit(126);
    execl(kProgram.c_str(), "stickslip", "plot", out.c_str(), (char*)nullptr);
    _exit(127);
  }
  ASSERT_EQ(waitpid(plot, &status, 0), plot);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(log);
  EXPECT_TRUE(markers(dir).empty());
  EXPECT_TRUE(complete_png(out / study_folder / "frf.png"));
  EXPECT_NE(slurp(out / study_folder / "frf_full_vs_reduced.svg").find("full model: b"),
            std::string::npos);
  // No temporaries are left anywhere.
  for (const auto& e : fs::recursive_directory_iterator(out)) {
    EXPECT_EQ(e.path().filename().string().find(".stickslip-tmp"), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace stickslip::cli_test

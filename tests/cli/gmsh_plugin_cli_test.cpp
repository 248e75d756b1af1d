// The Gmsh API is a plugin loaded when a case needs it (io/gmsh_plugin.h): the program does not
// link libgmsh, a case without Gmsh never loads it (the dynamic loader's own report, LD_DEBUG),
// and a missing plugin is a clear error (exit 5) only for the cases that need it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_test_support.h"

namespace stickslip::cli_test {
namespace {

const fs::path kExamples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";

TEST(GmshPlugin, TheProgramDoesNotLinkGmsh) {
  const fs::path dir = fresh_dir("gmsh_plugin_needed");
  ASSERT_EQ(shell("readelf -d " + kProgram, dir / "readelf.txt"), 0) << slurp(dir / "readelf.txt");
  const std::string needed = slurp(dir / "readelf.txt");
  ASSERT_NE(needed.find("(NEEDED)"), std::string::npos) << needed;
  EXPECT_EQ(needed.find("libgmsh"), std::string::npos) << needed;
}

TEST(GmshPlugin, ACaseWithoutGmshNeverLoadsItAndNeedsNoPlugin) {
  const fs::path dir = fresh_dir("gmsh_plugin_unused");
  // The loader lists every object it loads ("file=... [0];  needed by ..." / "calling init").
  ASSERT_EQ(
      shell("LD_DEBUG=files LD_DEBUG_OUTPUT=" + (dir / "ld").string() +
                " STICKSLIP_GMSH_PLUGIN=" + (dir / "no_such_plugin.so").string() + " " + kProgram +
                " run -q " + (kExamples / "01_jenkins_oscillator/case.yaml").string() + " -o " +
                (dir / "out").string(),
            dir / "log.txt"),
      0)
      << slurp(dir / "log.txt");
  EXPECT_TRUE(fs::exists(dir / "out" / "points.csv"));
  std::string loaded;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename().string().rfind("ld.", 0) == 0) loaded += slurp(entry.path());
  }
  ASSERT_NE(loaded.find("libyaml-cpp"), std::string::npos) << loaded.substr(0, 2000);
  EXPECT_EQ(loaded.find("libgmsh"), std::string::npos);
  EXPECT_EQ(loaded.find("libstickslip_gmsh"), std::string::npos);
}

TEST(GmshPlugin, AMissingPluginIsAClearErrorForACaseThatNeedsGmsh) {
  const fs::path dir = fresh_dir("gmsh_plugin_missing");
  const fs::path plugin = dir / "no_such_plugin.so";
  const int code = shell("STICKSLIP_GMSH_PLUGIN=" + plugin.string() + " " + kProgram + " run -q " +
                             (kExamples / "02_two_beam_joint/case.yaml").string() + " -o " +
                             (dir / "out").string(),
                         dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_EQ(code, 5) << log;
  EXPECT_NE(log.find("needs Gmsh"), std::string::npos) << log;
  EXPECT_NE(log.find(plugin.string() + ": no such file"), std::string::npos) << log;
  EXPECT_NE(log.find("STICKSLIP_GMSH_PLUGIN"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "out" / "points.csv"));
  // A file that is not a shared object: dlopen's own reason is given.
  std::ofstream(dir / "not_a_library.so") << "not an ELF file\n";
  EXPECT_EQ(shell("STICKSLIP_GMSH_PLUGIN=" + (dir / "not_a_library.so").string() + " " + kProgram +
                      " run -q " + (kExamples / "02_two_beam_joint/case.yaml").string() + " -o " +
                      (dir / "out2").string(),
                  dir / "log2.txt"),
            5)
      << slurp(dir / "log2.txt");
  EXPECT_NE(slurp(dir / "log2.txt").find("not_a_library.so: "), std::string::npos)
      << slurp(dir / "log2.txt");
}

}  // namespace
}  // namespace stickslip::cli_test

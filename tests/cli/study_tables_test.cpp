// Tables of a study concatenate in pandas (docs/output-files.md): points.csv of each study folder
// carries the studied parameter and value; energies of stuck cycles are 0, not round-off.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace stickslip {
namespace {

using namespace cli_test;

TEST(StudyTables, PointsOfAllFoldersConcatenateInPandasByValue) {
  const fs::path dir = fresh_dir("study_tables");
  // Example 01's Jenkins oscillator with a study of the friction coefficient.
  const fs::path examples = fs::path(STICKSLIP_TEST_DATA_DIR) / ".." / ".." / "examples";
  std::string text = slurp(examples / "01_jenkins_oscillator" / "case.yaml");
  text += "study: {parameter: contacts.jenkins.per_pair.mu, values: [0.5, 5]}\n";
  text.replace(text.find("K.hb"), 4, (examples / "01_jenkins_oscillator" / "K.hb").string());
  text.replace(text.find("M.hb"), 4, (examples / "01_jenkins_oscillator" / "M.hb").string());
  const fs::path file = write_case(dir, "case", text);
  ASSERT_EQ(run("solve -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  // pandas if installed (python3-pandas), else the csv module: one table, 361 rows per value;
  // a cycle without slip dissipates exactly 0 (not round-off), no energy is negative.
  const std::string script =
      "import glob, sys\n"
      "files = sorted(glob.glob(sys.argv[1] + '/*/points.csv'))\n"
      "assert len(files) == 2, files\n"
      "try:\n"
      "    import pandas as pd\n"
      "    t = pd.concat([pd.read_csv(f) for f in files])\n"
      "    counts = t.groupby('value').size().to_dict()\n"
      "    assert counts == {0.5: 361, 5.0: 361}, counts\n"
      "    assert set(t['parameter']) == {'contacts.jenkins.per_pair.mu'}\n"
      "    assert (t['dissipated_energy'] >= 0).all()\n"
      "    assert (t[t['value'] == 0.5]['dissipated_energy'] > 0).any()\n"
      "    s = pd.concat([pd.read_csv(f.replace('points', 'contact_state')) for f in files])\n"
      "    stuck = s[s['slip'] == 0]\n"
      "    assert len(stuck) > 100 and (stuck['dissipated_energy'] == 0).all()\n"
      "    assert (s['dissipated_energy'] >= 0).all()\n"
      "except ImportError:\n"
      "    import csv\n"
      "    rows = [r for f in files for r in csv.DictReader(open(f))]\n"
      "    assert len(rows) == 722 and {r['value'] for r in rows} == {'0.5', '5'}\n"
      "    assert all(float(r['dissipated_energy']) >= 0 for r in rows)\n"
      "print('ok')\n";
  std::ofstream(dir / "concat.py") << script;
  EXPECT_EQ(shell("/usr/bin/python3 " + (dir / "concat.py").string() + " " +
                      (dir / "out").string(),
                  dir / "py.log"),
            0)
      << slurp(dir / "py.log");
}

}  // namespace
}  // namespace stickslip

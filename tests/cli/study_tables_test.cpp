// The tables of a run read by pandas (Debian's /usr/bin/python3 with python3-pandas), as users read
// them (docs/output-files.md, "Tables"): one direction column `axis`, the unit in the name of every
// column that has one, every number the shortest decimal that reads back to its double (never
// padded, never cut short), a `parameter`,`value` pair on every row of every per-point table of a
// study folder so that the folders concatenate, and friction energies that are exactly 0 where the
// cycle integral only gives round-off. A file of an earlier version (`dof`, `real`, ...) is still
// read, with a warning.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli_test_support.h"
#include "../required_tool.h"

namespace stickslip {
namespace {

using namespace cli_test;

bool pandas_available() {
  return fs::exists("/usr/bin/python3") &&
         shell("/usr/bin/python3 -c 'import pandas'", fs::temp_directory_path() / "pandas.log") ==
             0;
}

// Checks of every table, in Python: headers exactly, `value` on every row and concatenation by
// value, numbers written shortest-exact.
constexpr const char* kTablesScript = R"(import glob, os, sys
import pandas as pd
root, values = sys.argv[1], [float(v) for v in sys.argv[2].split(',')]
folders = sorted(glob.glob(os.path.join(root, 'preload_*')))
assert len(folders) == len(values), folders
expected = {
    'points.csv': ['point', 'frequency_hz', 'converged', 'iterations', 'residual_m',
                   'dissipated_energy_j', 'residual_relative', 'static_mismatch', 'static_warning',
                   'aft_fallback_pairs'],
    'master_response.csv': ['point', 'body', 'node', 'axis', 'harmonic', 'real_m', 'imag_m'],
    'contact_forces.csv': ['point', 'contact', 'pair', 'node_a', 'node_b', 'frame', 'axis',
                           'harmonic', 'real_n', 'imag_n'],
    'contact_state.csv': ['point', 'contact', 'pair', 'node_a', 'node_b', 'stick', 'slip',
                          'separation', 'dissipated_energy_j'],
    'histories.csv': ['point', 'contact', 'pair', 'sample', 't_over_period', 'axis',
                      'displacement_m', 'force_n'],
    'recovery_check.csv': ['point', 'frequency_hz', 'body', 'harmonic', 'reduced_max_m',
                           'max_relative', 'rms_relative', 'max_absolute_m'],
    'recovered_nodes.csv': ['point', 'body', 'node', 'axis', 'harmonic', 'real_m', 'imag_m'],
    'reactions.csv': ['point', 'body', 'node', 'axis', 'harmonic', 'real_n', 'imag_n'],
}
# Computed quantities: some cell of each must carry (nearly) all of a double's digits.
full_precision = {'frequency_hz', 'residual_m', 'real_m', 'imag_m', 'real_n', 'imag_n',
                  'displacement_m', 'force_n', 'reduced_max_m', 'max_absolute_m'}
def digits(cell):
    mantissa = cell.lower().lstrip('+-').split('e')[0]
    return mantissa.replace('.', '').lstrip('0')
fvals = [float(f.rsplit('_', 1)[1]) for f in folders]
assert sorted(fvals) == sorted(values), fvals
checked = 0
for name, columns in expected.items():
    tables = [pd.read_csv(os.path.join(f, name)) for f in folders]
    texts = [pd.read_csv(os.path.join(f, name), dtype=str) for f in folders]
    for f, v, t in zip(folders, fvals, tables):
        assert list(t.columns) == columns + ['parameter', 'value'], (f, name, list(t.columns))
        assert len(t) > 0 and (t['value'] == v).all(), (f, name)
    every = pd.concat(tables, ignore_index=True)
    assert set(every['parameter']) == {'contacts.joint.per_pair.preload'}, name
    counts = every.groupby('value').size().to_dict()
    assert counts == {v: len(t) for v, t in zip(fvals, tables)}, (name, counts)
    for t, text in zip(tables, texts):
        for c in columns:
            if not pd.api.types.is_float_dtype(t[c]):
                continue
            cells = list(text[c])
            for cell in cells:
                float(cell)
                mantissa = cell.lower().split('e')[0]
                # Never padded: a shortest decimal has no trailing zero after its point.
                assert not ('.' in mantissa and mantissa.endswith('0')), (name, c, cell)
            if c in full_precision:
                assert max(len(digits(x)) for x in cells) >= 15, (name, c, cells[:5])
            checked += 1
# Friction energy: >= 0, and no round-off left: 0 or above 1e-12 of the folder's largest.
largest = 0
for f in folders:
    for name in ('points.csv', 'contact_state.csv'):
        e = pd.read_csv(os.path.join(f, name))['dissipated_energy_j']
        assert (e >= 0).all(), (f, name, e.min())
        assert not ((e > 0) & (e <= 1e-12 * e.max())).any(), (f, name)
        largest = max(largest, e.max())
assert largest > 0
print('OK', checked)
)";

TEST(StudyTables, EveryTableOfAStudyHasUnitsAxisValueAndConcatenatesInPandas) {
  STICKSLIP_REQUIRE_TOOL(pandas_available(), "Debian's python3 with pandas (python3-pandas)");
  const fs::path dir = fresh_dir("study_tables_all");
  const std::string text = coarse_joint_head(20, 2) + R"(study: {parameter: contacts.joint.per_pair.preload, values: [80, 5]}
recovery: {points: peak, method: direct, fields: [displacement], nodes: [1, 2]}
output:
  vtu: false
  plots: false
  histories: {joint: [0]}
)";
  const fs::path file = write_case(dir, "case", text);
  ASSERT_EQ(run("run -q " + file.string() + " -o " + (dir / "out").string(), dir / "log"), 0)
      << slurp(dir / "log");
  std::ofstream(dir / "tables.py") << kTablesScript;
  ASSERT_EQ(shell("/usr/bin/python3 " + (dir / "tables.py").string() + " " +
                      (dir / "out").string() + " 80,5",
                  dir / "py.log"),
            0)
      << slurp(dir / "py.log");
  EXPECT_NE(slurp(dir / "py.log").find("OK "), std::string::npos) << slurp(dir / "py.log");

  // A folder written by an earlier version (`dof`, `real`, `imag`, `dissipated_energy`) is still
  // read, with a warning naming the file and the column; the recovery from it is the same.
  const fs::path old = dir / "out" / "preload_80";
  const std::string master = slurp(old / "master_response.csv");
  const std::string header = "point,body,node,axis,harmonic,real_m,imag_m";
  ASSERT_EQ(master.rfind(header, 0), 0u) << master.substr(0, 80);
  std::ofstream(old / "master_response.csv")
      << "point,body,node,dof,harmonic,real,imag" << master.substr(header.size());
  const std::string state = slurp(old / "contact_state.csv");
  const size_t e = state.find("dissipated_energy_j");
  ASSERT_NE(e, std::string::npos);
  std::ofstream(old / "contact_state.csv")
      << state.substr(0, e) << "dissipated_energy" << state.substr(e + 19);
  const std::string before = slurp(old / "recovered_nodes.csv");
  ASSERT_EQ(run("recover " + file.string() + " -o " + (dir / "out").string(), dir / "recover.log"),
            0)
      << slurp(dir / "recover.log");
  const std::string log = slurp(dir / "recover.log");
  EXPECT_NE(log.find("master_response.csv: column 'dof' is read as 'axis'"), std::string::npos)
      << log;
  EXPECT_NE(log.find("contact_state.csv: column 'dissipated_energy' is read as "
                     "'dissipated_energy_j'"),
            std::string::npos)
      << log;
  EXPECT_EQ(slurp(old / "recovered_nodes.csv"), before);
}

TEST(StudyTables, PointsOfAllFoldersConcatenateInPandasByValue) {
  STICKSLIP_REQUIRE_TOOL(pandas_available(), "Debian's python3 with pandas (python3-pandas)");
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
  // One table, 361 rows per value; a cycle without slip dissipates exactly 0 (not round-off), no
  // energy is negative.
  const std::string script =
      "import glob, sys\n"
      "import pandas as pd\n"
      "files = sorted(glob.glob(sys.argv[1] + '/*/points.csv'))\n"
      "assert len(files) == 2, files\n"
      "t = pd.concat([pd.read_csv(f) for f in files])\n"
      "counts = t.groupby('value').size().to_dict()\n"
      "assert counts == {0.5: 361, 5.0: 361}, counts\n"
      "assert set(t['parameter']) == {'contacts.jenkins.per_pair.mu'}\n"
      "assert (t['dissipated_energy_j'] >= 0).all()\n"
      "assert (t[t['value'] == 0.5]['dissipated_energy_j'] > 0).any()\n"
      "s = pd.concat([pd.read_csv(f.replace('points', 'contact_state')) for f in files])\n"
      "stuck = s[s['slip'] == 0]\n"
      "assert len(stuck) > 100 and (stuck['dissipated_energy_j'] == 0).all()\n"
      "assert (s['dissipated_energy_j'] >= 0).all()\n"
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

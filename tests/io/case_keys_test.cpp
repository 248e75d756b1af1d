// The key table (io/case_keys.h) against what it must agree with: the documentation (every key of
// docs/case-file.md's key tables is in the table, with the same default, and nothing else), the
// parser's defaults (a default written as one value is what describe_case writes for a case that
// does not give the key), and the study (with_parameter accepts every study key, refuses the rest).
#include "io/case_keys.h"

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "core/errors.h"
#include "io/case_file.h"
#include "minimal_case.h"

namespace stickslip {
namespace {

const std::string kSource = std::string(STICKSLIP_TEST_DATA_DIR) + "/../..";

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  const size_t b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// Cells of a Markdown table row ("\|" is a pipe inside a cell).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (row[i] == '|') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  return out;
}

// (section, key) -> default column, from every table of docs/case-file.md whose first column is
// `key`; the section is the heading above it ("Top level" is "").
std::map<std::pair<std::string, std::string>, std::string> documented_keys() {
  std::ifstream in(kSource + "/docs/case-file.md");
  EXPECT_TRUE(in.good());
  std::map<std::pair<std::string, std::string>, std::string> out;
  std::string line, section, previous;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.rfind("#", 0) == 0) {
      section = trim(line.substr(line.find(' ') + 1));
      if (section == "Top level") section.clear();
      header.clear();
    } else if (line.rfind("|", 0) == 0) {
      if (previous.rfind("|", 0) != 0) header = cells(line);  // a table's first row
      const std::vector<std::string> c = cells(line);
      if (!header.empty() && header[0] == "key" && c.size() == header.size() && c[0].size() > 2 &&
          c[0].front() == '`' && c[0].back() == '`') {
        std::string value = "required";  // materials: "All three keys are required."
        for (size_t i = 0; i < header.size(); ++i)
          if (header[i] == "default") value = c[i];
        out[{section, c[0].substr(1, c[0].size() - 2)}] = value;
      }
    } else {
      header.clear();
    }
    previous = line;
  }
  return out;
}

TEST(CaseKeys, TheDocumentationDescribesExactlyTheTableKeysWithTheSameDefaults) {
  const auto documented = documented_keys();
  ASSERT_GT(documented.size(), 50u);
  std::set<std::pair<std::string, std::string>> in_table;
  for (const CaseKey& k : case_keys()) {
    const std::pair<std::string, std::string> id{std::string(k.section), std::string(k.key)};
    EXPECT_TRUE(in_table.insert(id).second) << "twice in the table: " << k.section << " " << k.key;
    const auto it = documented.find(id);
    if (it == documented.end()) {
      ADD_FAILURE() << "not in docs/case-file.md: section '" << k.section << "', key `" << k.key
                    << "`";
      continue;
    }
    EXPECT_EQ(it->second, k.default_value) << k.section << " " << k.key;
  }
  for (const auto& [id, value] : documented) {
    EXPECT_TRUE(in_table.count(id)) << "documented but not in io/case_keys.cpp: section '"
                                    << id.first << "', key `" << id.second << "`";
  }
}

// A case that gives nothing optional: describe_case writes the defaults.
const std::string& kMinimal = testing_cases::kMinimalCase;

// The node of `section` in a described case (NAME: the first entry, []: the first element).
YAML::Node section_node(YAML::Node root, const std::string& section) {
  // reset() rebinds the handle (operator= would assign into the tree).
  YAML::Node node;
  node.reset(root);
  std::stringstream parts(section);
  std::string part;
  while (std::getline(parts, part, '.')) {
    const bool list = part.size() > 2 && part.substr(part.size() - 2) == "[]";
    if (list) part = part.substr(0, part.size() - 2);
    if (part == "NAME") {
      if (!node.IsMap() || node.size() == 0) return YAML::Node(YAML::NodeType::Undefined);
      node.reset(node.begin()->second);
    } else {
      node.reset(node[part]);
    }
    if (list) node.reset(node[0]);
    if (!node.IsDefined()) return node;
  }
  return node;
}

bool same_value(const YAML::Node& written, const std::string& documented) {
  if (written.IsSequence() && written.size() == 1 && written[0].Scalar() == documented)
    return true;  // harmonics: 1 is the list [1]
  if (written.IsSequence()) {
    std::string text = "[";
    for (size_t i = 0; i < written.size(); ++i) text += (i ? ", " : "") + written[i].Scalar();
    return text + "]" == documented;
  }
  if (!written.IsScalar()) return false;
  const std::string& w = written.Scalar();
  if (w == documented || (documented == "\"\"" && w.empty())) return true;
  try {  // 1.0e-8 written as 1e-08
    size_t a = 0, b = 0;
    const double x = std::stod(w, &a), y = std::stod(documented, &b);
    return a == w.size() && b == documented.size() && x == y;
  } catch (const std::exception&) {
    return false;
  }
}

TEST(CaseKeys, EveryDefaultGivenAsOneValueIsWhatTheParserFillsIn) {
  const CaseDefinition c = parse_case(kMinimal, "case.yaml", STICKSLIP_TEST_DATA_DIR);
  const YAML::Node root = YAML::Load(describe_case(c));
  // Keys whose default describe_case does not write as the value: the output folder is written
  // resolved (an absolute path), `aft` only when the case gives it (the default then warns less),
  // `coupling` and `unpaired` only for mortar contacts (the default keeps the fingerprints of
  // earlier runs), `max_points` and recovery `modes` only with the method they belong to
  // (continuation, modal), `amplitude.points` only with nonlinear_mode, `gap` is exclusive with the
  // preload this case gives, `mass_rule` only when it is calculix and `reduction_solver` only when
  // it is petsc (describe_case enters the
  // reduction's fingerprint, which stays that of earlier runs for the default), the .msh-only and
  // `supports` keys belong to blocks this case does not have, and so do `cyclic` (its
  // tolerance: tests/io/cyclic_case_test.cpp) and `rotation` (tests/io/rotation_case_test.cpp).
  const std::set<std::string> not_written{"output.directory",
                                          "analysis.aft",
                                          "bodies.NAME.mass_rule",
                                          "bodies.NAME.reduction_solver",
                                          "contacts[].gap",
                                          "contacts[].coupling",
                                          "contacts[].unpaired",
                                          "analysis.max_points",
                                          "analysis.amplitude.points",
                                          "recovery.modes",
                                          "meshes.NAME.hexahedron8",
                                          "meshes.NAME.hexahedron20",
                                          "bodies.NAME.supports.from_mesh",
                                          "bodies.NAME.cyclic.tolerance",
                                          "rotation.stress_stiffening",
                                          "rotation.spin_softening"};
  int checked = 0;
  const std::regex one_value("`([^`]*)`");
  for (const CaseKey& k : case_keys()) {
    std::smatch m;
    const std::string value(k.default_value);
    if (!std::regex_match(value, m, one_value)) continue;  // required, none, a sentence
    const std::string path = std::string(k.section) + "." + std::string(k.key);
    if (not_written.count(path) || k.key.find('.') != std::string_view::npos) continue;
    const YAML::Node block = section_node(root, std::string(k.section));
    ASSERT_TRUE(block.IsDefined()) << "no block " << k.section << " in\n" << describe_case(c);
    const YAML::Node written = block[std::string(k.key)];
    if (!written.IsDefined()) {
      ADD_FAILURE() << path << " not written by describe_case";
      continue;
    }
    EXPECT_TRUE(same_value(written, m[1].str()))
        << path << ": documented default " << m[1] << ", parser's " << YAML::Dump(written);
    ++checked;
  }
  EXPECT_GE(checked, 25);
}

TEST(CaseKeys, EveryStudyKeyIsAcceptedByTheStudyAndListedWhenAKeyIsNot) {
  const std::string text = kMinimal + R"(damping: {alpha: 1, beta: 1.0e-7}
static_loads:
  - {body: beam1, node_set: FORCE1, force: [0, 0, 10]}
)";
  const CaseDefinition c = parse_case(text, "case.yaml", STICKSLIP_TEST_DATA_DIR);
  // A gap instead of a preload for contacts.NAME.gap.
  std::string gap_text = text;
  gap_text.replace(gap_text.find(", preload: 150}"), 15, "}\n    gap: 1.0e-6");
  const CaseDefinition with_gap = parse_case(gap_text, "gap.yaml", STICKSLIP_TEST_DATA_DIR);
  const std::map<std::string, std::vector<std::string>> examples{
      {"materials.NAME.youngs_modulus", {"materials.steel.youngs_modulus"}},
      {"materials.NAME.poisson_ratio", {"materials.steel.poisson_ratio"}},
      {"materials.NAME.density", {"materials.steel.density"}},
      {"bodies.NAME.modal_damping_ratio", {"bodies.beam1.modal_damping_ratio"}},
      {"contacts.NAME.per_pair.<parameter>",
       {"contacts.joint.per_pair.kt", "contacts.joint.per_pair.mu",
        "contacts.joint.per_pair.preload"}},
      {"contacts.NAME.total.<parameter>", {}},  // per_pair here: refused below
      {"contacts.NAME.per_area.<parameter>", {}},
      {"contacts.NAME.gap", {"contacts.joint.gap"}},
      {"excitation[i].amplitude", {"excitation[0].amplitude"}},
      {"static_loads[i].force", {"static_loads[0].force"}},
      {"static_loads[i].total_force", {}},  // the entry gives `force`
      {"static_loads[i].pressure", {}},
      {"damping.alpha", {"damping.alpha"}},
      {"damping.beta", {"damping.beta"}},
      {"rotation.speed_rpm", {}},  // this case does not rotate: tests/io/rotation_case_test.cpp
  };
  const std::vector<std::string> paths = study_parameter_paths();
  EXPECT_EQ(paths.size(), examples.size());
  for (const std::string& p : paths) {
    const auto it = examples.find(p);
    ASSERT_NE(it, examples.end()) << "a study key without an example here: " << p;
    for (const std::string& concrete : it->second) {
      const CaseDefinition& base = concrete == "contacts.joint.gap" ? with_gap : c;
      EXPECT_NO_THROW(with_parameter(base, concrete, 0.25)) << concrete;
    }
  }
  // A numeric key that no study varies: refused, and the message lists the table's study keys.
  try {
    with_parameter(c, "analysis.tolerance", 1e-6);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    for (const std::string& p : paths)
      EXPECT_NE(e.message().find(p), std::string::npos) << p << " not in: " << e.message();
  }
}

// The parser's known keys of each block are the table's: an unknown key is refused with the
// table's list, and every key of the table's analysis block is taken.
TEST(CaseKeys, TheParserKnowsExactlyTheTableKeysOfEachBlock) {
  try {
    parse_case(kMinimal + "  tolerence: 1.0e-9\n", "case.yaml", STICKSLIP_TEST_DATA_DIR);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    for (const std::string& key : case_keys_in("analysis"))
      EXPECT_NE(e.message().find(key), std::string::npos) << key << " not in: " << e.message();
  }
  EXPECT_EQ(case_keys_in("damping"), (std::vector<std::string>{"alpha", "beta"}));
  EXPECT_TRUE(case_keys_in("no such section").empty());
  // Dotted entries document a key inside a block (total.split) and are not keys of the section.
  for (const std::string& key : case_keys_in("contacts[]"))
    EXPECT_EQ(key.find('.'), std::string::npos) << key;
}

}  // namespace
}  // namespace stickslip

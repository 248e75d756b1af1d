// describe_case as a case file: summary.json's `inputs` (docs/output-files.md) must be a case that
// `stickslip run` accepts again and that means the same thing. Checked as a fixed point: the text
// of a case, read back by the parser, describes itself with the same text (every key the
// description writes is one the parser accepts for that law and form, and no value is lost).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "io/case_file.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(STICKSLIP_TEST_DATA_DIR) + "/case";
const std::string kSource = std::string(STICKSLIP_TEST_DATA_DIR) + "/../..";

// A case with mesh bodies; `contact` replaces its contact block (indented by 2 under contacts).
std::string mesh_case(const std::string& contact, const std::string& extra = "") {
  return R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}
contacts:
)" + contact +
         R"(
excitation:
  - {body: beam1, node_set: FORCE1, direction: z, amplitude: 50, phase_deg: 30}
analysis:
  frequency: {start_hz: 150, stop_hz: 250, step_hz: 0.5}
)" + extra;
}

// The description of `definition`, read back from a file in `dir`, described again.
std::string described_twice(const CaseDefinition& definition, const fs::path& dir) {
  const std::string text = describe_case(with_absolute_paths(definition));
  const fs::path file = dir / "inputs.yaml";
  std::ofstream(file) << text;
  try {
    return describe_case(read_case_file(file.string()));
  } catch (const InvalidInput& e) {
    ADD_FAILURE() << "refused: " << e.what() << "\n" << text;
    return "";
  }
}

class CaseDescription : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("stickslip_case_description_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "elsewhere");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(CaseDescription, ShippedCasesDescribeThemselvesAsAcceptedCases) {
  std::vector<std::string> files = {kData + "/reference.yaml", kData + "/imported/case.yaml",
                                    kSource + "/examples/01_jenkins_oscillator/case.yaml",
                                    kSource + "/examples/02_two_beam_joint/case.yaml",
                                    kSource + "/bench/cases/reference_sweep.yaml"};
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const CaseDefinition c = read_case_file(file);
    // Read back from another folder: the file paths must not depend on where the case sits.
    EXPECT_EQ(described_twice(c, dir_ / "elsewhere"), describe_case(with_absolute_paths(c)));
  }
}

TEST_F(CaseDescription, EveryLawAndFormDescribesItselfAsAnAcceptedCase) {
  const std::vector<std::string> cases = {
      // friction with a gap instead of a preload, given as totals split by area
      mesh_case("  - name: joint\n    law: friction\n    between: {beam1: CONTACT1, beam2: "
                "CONTACT2}\n    normal: [1, 0, 0]\n    t1: [0, 1, 0]\n    total: {kt: 4e9, kn: "
                "5e9, mu: 0.4, split: area}\n    gap: 1.0e-6"),
      // unilateral gap law with a preload, 1D Jenkins to the ground, cubic and linear springs
      mesh_case("  - name: joint\n    law: gap\n    between: {beam1: CONTACT1, beam2: "
                "CONTACT2}\n    direction: x\n    per_pair: {kn: 5e9, preload: 10}\n"
                "  - name: damper\n    law: jenkins\n    bodies: [beam1, ground]\n    pairs: [3, "
                "4]\n    direction: [0, 0, 1]\n    per_pair: {kt: 1e6, mu: 0.3, preload: 20}\n"
                "  - name: spring\n    law: cubic\n    bodies: [beam1, beam2]\n    pairs: [[5, "
                "6]]\n    direction: y\n    per_pair: {k1: 1e5, k3: 1e12}\n"
                "  - name: lin\n    law: linear\n    between: {beam1: CONTACT1, beam2: CONTACT2}\n"
                "    normal: [1, 0, 0]\n    per_pair: {kt: 1e9, kn: 2e9}"),
      // continuation around a mode, a study, recovery at listed frequencies, modal recovery
      mesh_case("  - name: joint\n    law: friction\n    between: {beam1: CONTACT1, beam2: "
                "CONTACT2}\n    normal: [1, 0, 0]\n    per_pair: {kt: 4e9, kn: 5e9, mu: 0.5, "
                "preload: 150}",
                "  method: continuation\n  harmonics: [1, 3]\n"
                "study: {parameter: contacts.joint.per_pair.preload, values: [50, 150]}\n"
                "recovery: {points: [180, 200.5], method: modal, modes: 12, nodes: [1, 2]}\n"
                "output: {frf: [{body: beam2, node: 7, direction: y}], histories: {joint: [0, "
                "1]}}\n"),
  };
  for (const std::string& text : cases) {
    SCOPED_TRACE(text);
    CaseDefinition c;
    ASSERT_NO_THROW(c = parse_case(text, "case.yaml", dir_.string())) << text;
    EXPECT_EQ(described_twice(c, dir_ / "elsewhere"), describe_case(with_absolute_paths(c)));
  }
}

// A mortar contact with parameters per unit area keeps its coupling, search distance, unpaired
// rule and per_area block (a description without them would still be a fixed point, so they are
// looked for), and a study of a per_area parameter is accepted.
TEST_F(CaseDescription, MortarCouplingAndParametersPerAreaAreDescribed) {
  const std::string text = mesh_case(
      "  - name: joint\n    law: friction\n    between: {beam1: CONTACT1, beam2: "
      "CONTACT2}\n    coupling: mortar\n    search_distance: 0.002\n    unpaired: "
      "skip\n    normal: [1, 0, 0]\n    per_area: {kt: 4e12, kn: 5e12, mu: 0.5, "
      "preload: 1.5e5}",
      "study: {parameter: contacts.joint.per_area.kn, values: [5e12, 1e13]}\n");
  CaseDefinition c;
  ASSERT_NO_THROW(c = parse_case(text, "case.yaml", dir_.string())) << text;
  ASSERT_EQ(c.contacts.size(), 1u);
  EXPECT_EQ(c.contacts[0].coupling, ContactCoupling::kMortar);
  EXPECT_EQ(c.contacts[0].parameters_given, ContactDefinition::Parameters::kPerArea);
  const std::string described = describe_case(with_absolute_paths(c));
  for (const char* key : {"coupling: mortar", "search_distance: 0.002", "unpaired: skip",
                          "per_area: {kt: 4", "contacts.joint.per_area.kn"}) {
    EXPECT_NE(described.find(key), std::string::npos) << key << "\n" << described;
  }
  // (A contact `tolerance` written with coupling: mortar would be refused when read back.)
  EXPECT_EQ(described_twice(c, dir_ / "elsewhere"), described);
}

TEST_F(CaseDescription, FilePathsBecomeAbsolute) {
  const CaseDefinition c = with_absolute_paths(read_case_file(kData + "/imported/case.yaml"));
  for (const auto& [name, m] : c.meshes) {
    if (!m.file.empty()) {
      EXPECT_TRUE(fs::path(m.file).is_absolute()) << m.file;
    }
  }
  for (const auto& [name, b] : c.bodies) {
    if (!b.reduced.stiffness.empty()) {
      EXPECT_TRUE(fs::path(b.reduced.stiffness).is_absolute()) << b.reduced.stiffness;
    }
  }
  EXPECT_TRUE(fs::path(c.output.directory).is_absolute());
}

}  // namespace
}  // namespace stickslip

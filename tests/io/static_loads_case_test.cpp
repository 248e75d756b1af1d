// The case file's static_loads and `preload: computed` (docs/case-file.md, "static_loads[]"):
// what they parse into, and each bad input refused at its line and key.
#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"
#include "io/case_file.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/case";

// Line 1 = "stickslip: 1"; the static_loads entries start on line 16.
std::string pressed_case(const std::string& preload, const std::string& loads) {
  return R"(stickslip: 1
materials:
  steel: {youngs_modulus: 2.0e11, poisson_ratio: 0.3, density: 7800}
meshes:
  joint: {generate: two_beam}
bodies:
  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}
  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}
contacts:
  - name: joint
    law: friction
    between: {beam1: CONTACT1, beam2: CONTACT2}
    normal: [1, 0, 0]
    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: )" +
         preload + R"(}
static_loads:
)" + loads + R"(analysis:
  frequency: {start_hz: 1852, stop_hz: 1856, step_hz: 0.01}
)";
}

CaseDefinition parse(const std::string& text) { return parse_case(text, "case.yaml", kDir); }

void expect_invalid(const std::string& text, int line, const std::string& key,
                    const std::string& message) {
  try {
    parse(text);
    ADD_FAILURE() << "no InvalidInput; expected line " << line << " " << key << ": " << message;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().key, key) << e.what();
    EXPECT_NE(e.message().find(message), std::string::npos)
        << "message '" << e.message() << "' lacks '" << message << "'";
  }
}

TEST(StaticLoadsCase, ForcesTotalsAndPressuresParseWithAComputedPreload) {
  const CaseDefinition c = parse(pressed_case("computed", R"(  - {body: beam2, node_set: FORCE2, total_force: [-4500, 0, 0]}
  - {body: beam1, node: [239, 240], force: [0, 0, 10]}
  - {body: beam1, node_set: [CONTACT1], pressure: 1.5e6}
)"));
  ASSERT_EQ(c.contacts.size(), 1u);
  EXPECT_TRUE(c.contacts[0].preload_computed);
  EXPECT_EQ(c.contacts[0].parameters.preload, 0.0);
  ASSERT_EQ(c.static_loads.size(), 3u);
  EXPECT_EQ(c.static_loads[0].kind, StaticLoadDefinition::Kind::kTotalForce);
  EXPECT_EQ(c.static_loads[0].body, "beam2");
  EXPECT_EQ(c.static_loads[0].nodes.sets, std::vector<std::string>{"FORCE2"});
  EXPECT_EQ(c.static_loads[0].force[0], -4500.0);
  EXPECT_EQ(c.static_loads[1].kind, StaticLoadDefinition::Kind::kForce);
  EXPECT_EQ(c.static_loads[1].nodes.ids, (std::vector<int>{239, 240}));
  EXPECT_EQ(c.static_loads[1].force[2], 10.0);
  EXPECT_EQ(c.static_loads[2].kind, StaticLoadDefinition::Kind::kPressure);
  EXPECT_EQ(c.static_loads[2].pressure, 1.5e6);
  EXPECT_EQ(c.where("static_loads[2]").line, 18);
  // Described as the case file says it.
  const std::string described = describe_case(c);
  EXPECT_NE(described.find("preload: computed"), std::string::npos) << described;
  EXPECT_NE(described.find("total_force"), std::string::npos) << described;
  // ... and it reads back into the same static loads (summary.json's inputs run again).
  const CaseDefinition again = parse(described);
  ASSERT_EQ(again.static_loads.size(), 3u);
  EXPECT_TRUE(again.contacts[0].preload_computed);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(again.static_loads[i].kind, c.static_loads[i].kind) << i;
    EXPECT_EQ(again.static_loads[i].nodes.sets, c.static_loads[i].nodes.sets) << i;
    EXPECT_EQ(again.static_loads[i].nodes.ids, c.static_loads[i].nodes.ids) << i;
    EXPECT_EQ(again.static_loads[i].force, c.static_loads[i].force) << i;
    EXPECT_EQ(again.static_loads[i].pressure, c.static_loads[i].pressure) << i;
  }
  // A study cannot vary a computed preload; it varies the loads that compute it: a force's
  // magnitude (its direction kept) or a pressure.
  EXPECT_THROW(with_parameter(c, "contacts.joint.per_pair.preload", 100), InvalidInput);
  const CaseDefinition scaled = with_parameter(c, "static_loads[0].total_force", 9000);
  EXPECT_EQ(scaled.static_loads[0].force[0], -9000.0);
  EXPECT_EQ(scaled.static_loads[0].force[1], 0.0);
  EXPECT_EQ(with_parameter(c, "static_loads[1].force", 20).static_loads[1].force[2], 20.0);
  EXPECT_EQ(with_parameter(c, "static_loads[2].pressure", -2e5).static_loads[2].pressure, -2e5);
  EXPECT_THROW(with_parameter(c, "static_loads[0].force", 10), InvalidInput);  // total_force
  EXPECT_THROW(with_parameter(c, "static_loads[2].pressure", 0), InvalidInput);
  EXPECT_THROW(with_parameter(c, "static_loads[3].pressure", 1e5), InvalidInput);
  EXPECT_THROW(with_parameter(c, "static_loads[0].total_force", -1), InvalidInput);
  // The typed preload stays, with static loads too.
  const CaseDefinition typed = parse(
      pressed_case("150", "  - {body: beam2, node_set: FORCE2, force: [-10, 0, 0]}\n"));
  EXPECT_FALSE(typed.contacts[0].preload_computed);
  EXPECT_EQ(typed.contacts[0].parameters.preload, 150.0);
}

TEST(StaticLoadsCase, BadEntriesAreRefusedAtTheirLineAndKey) {
  expect_invalid(pressed_case("computed", "  - {body: beam2, node_set: FORCE2}\n"), 16,
                 "static_loads[0]", "expected one of 'force");
  expect_invalid(pressed_case("computed", "  - {body: beam2, node_set: FORCE2, force: [1, 0, 0], "
                                          "pressure: 1e5}\n"),
                 16, "static_loads[0]", "give only one of");
  expect_invalid(pressed_case("computed", "  - {body: beam3, node_set: FORCE2, force: [1, 0, 0]}\n"),
                 16, "static_loads[0].body", "unknown body 'beam3'");
  expect_invalid(pressed_case("computed", "  - {body: beam2, node_set: FORCE2, force: [1, 0]}\n"),
                 16, "static_loads[0].force", "expected [fx, fy, fz]");
  expect_invalid(pressed_case("computed", "  - {body: beam2, node_set: FORCE2, pressure: 0}\n"), 16,
                 "static_loads[0].pressure", "must not be 0");
  expect_invalid(pressed_case("computed", "  - {body: beam2, node: -3, force: [1, 0, 0]}\n"), 16,
                 "static_loads[0].node", "node ids are positive");
  expect_invalid(pressed_case("computed", "  - {body: beam2, node_set: A, torque: 3}\n"), 16,
                 "static_loads[0].torque", "unknown key 'torque'");
}

TEST(StaticLoadsCase, AComputedPreloadNeedsStaticLoadsAndALawWithAPreload) {
  // No static loads: nothing would press the joint.
  std::string none = pressed_case("computed", "");
  none.replace(none.find("static_loads:\n"), 14, "");
  expect_invalid(none, 14, "contacts.joint.per_pair.preload", "needs 'static_loads'");
  // A word other than `computed` is still a number expected.
  expect_invalid(pressed_case("computer", "  - {body: beam2, node_set: FORCE2, force: [1, 0, 0]}\n"),
                 14, "contacts.joint.per_pair.preload", "expected a number");
  // A preload file and a computed preload exclude each other.
  std::string file = pressed_case("computed", "  - {body: beam2, node_set: FORCE2, force: [1, 0, 0]}\n");
  file.replace(file.find("    normal:"), 0, "    preload_file: preloads.csv\n");
  expect_invalid(file, 15, "contacts.joint.per_pair.preload",
                 "give either 'preload' or 'preload_file'");
  // A law without a preload cannot compute one.
  std::string cubic =
      pressed_case("computed", "  - {body: beam2, node_set: FORCE2, force: [1, 0, 0]}\n");
  cubic.replace(cubic.find("law: friction"), 13, "law: jenkins");
  cubic.replace(cubic.find("normal: [1, 0, 0]"), 17, "direction: y");
  cubic.replace(cubic.find("kn: 5.6309e9, "), 14, "");
  expect_invalid(cubic, 14, "contacts.joint.per_pair.preload", "cannot compute its preload");
}

}  // namespace
}  // namespace stickslip

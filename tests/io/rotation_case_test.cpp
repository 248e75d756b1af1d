// `rotation` in the case file: read into RotationDefinition with its defaults, written back by
// describe_case, varied by a study, and every bad value refused at its own line and key.
#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"
#include "io/case_file.h"
#include "minimal_case.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/case";

// The minimal case (its 18 lines), without recovery (line 19), plus the given lines from line 20
// on.
std::string rotating(const std::string& lines) {
  return testing_cases::kMinimalCase + "recovery: {points: none}\n" + lines;
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

TEST(RotationCase, TheRotationIsReadWithItsDefaultsAndWrittenBack) {
  const CaseDefinition c =
      parse(rotating("rotation:\n"
                     "  speed_rpm: 12000\n"
                     "  axis: {point: [0, 0.1, 0], direction: [0, 0, 2]}\n"
                     "  campbell: {speeds_rpm: [0, 6000, 12000], engine_orders: [1, 3]}\n"));
  ASSERT_TRUE(c.rotation.has_value());
  const RotationDefinition& r = *c.rotation;
  EXPECT_EQ(r.speed_rpm, 12000.0);
  EXPECT_TRUE(r.axis_given);
  EXPECT_EQ(r.axis_point[1], 0.1);
  EXPECT_EQ(r.axis_direction[2], 1.0);  // normalised
  EXPECT_TRUE(r.stress_stiffening);     // the defaults
  EXPECT_TRUE(r.spin_softening);
  EXPECT_EQ(r.campbell_speeds_rpm, (std::vector<double>{0, 6000, 12000}));
  EXPECT_EQ(r.engine_orders, (std::vector<int>{1, 3}));
  EXPECT_EQ(c.where("rotation.speed_rpm").line, 21);
  // describe_case writes it back as a case that reads the same.
  const CaseDefinition again = parse(describe_case(c));
  ASSERT_TRUE(again.rotation.has_value());
  EXPECT_EQ(again.rotation->speed_rpm, r.speed_rpm);
  EXPECT_EQ(again.rotation->axis_point, r.axis_point);
  EXPECT_EQ(again.rotation->axis_direction, r.axis_direction);
  EXPECT_EQ(again.rotation->campbell_speeds_rpm, r.campbell_speeds_rpm);
  EXPECT_EQ(again.rotation->engine_orders, r.engine_orders);
  EXPECT_EQ(describe_case(again), describe_case(c));
  const CaseDefinition off = parse(rotating(
      "rotation: {speed_rpm: 0, axis: {point: [0, 0, 0], direction: x}, stress_stiffening: false, "
      "spin_softening: false}\n"));
  EXPECT_FALSE(off.rotation->stress_stiffening);
  EXPECT_FALSE(off.rotation->spin_softening);
  EXPECT_FALSE(parse(describe_case(off)).rotation->spin_softening);
}

TEST(RotationCase, AStudyVariesTheSpeed) {
  const CaseDefinition c =
      parse(rotating("rotation: {speed_rpm: 1000, axis: {point: [0, 0, 0], direction: z}}\n"
                     "study: {parameter: rotation.speed_rpm, values: [0, 5000, 10000]}\n"));
  EXPECT_EQ(with_parameter(c, "rotation.speed_rpm", 5000).rotation->speed_rpm, 5000);
  EXPECT_THROW(with_parameter(c, "rotation.speed_rpm", -1), InvalidInput);
  expect_invalid(rotating("study: {parameter: rotation.speed_rpm, values: [0, 5000]}\n"), 20,
                 "study.parameter", "the case has no 'rotation'");
}

TEST(RotationCase, AComputedPreloadMayBePressedByTheRotationAlone) {
  std::string text =
      rotating("rotation: {speed_rpm: 1000, axis: {point: [0, 0, 0], direction: z}}\n");
  text.replace(text.find("preload: 150}"), 13, "preload: computed}");
  const CaseDefinition c = parse(text);
  EXPECT_TRUE(c.contacts[0].preload_computed);
}

TEST(RotationCase, BadValuesAreRefusedAtTheirKeys) {
  expect_invalid(rotating("rotation: {speed_rpm: -5, axis: {point: [0, 0, 0], direction: z}}\n"),
                 20, "rotation.speed_rpm", ">= 0");
  expect_invalid(rotating("rotation: {axis: {point: [0, 0, 0], direction: z}}\n"), 20,
                 "rotation.speed_rpm", "required key missing");
  expect_invalid(rotating("rotation: {speed_rpm: 5}\n"), 20, "rotation.axis",
                 "the axis of rotation");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: [0, 0, "
                          "0]}\n"),
                 22, "rotation.axis.direction", "");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: z}\n"
                          "  campbell: {speeds_rpm: [0, 300, 200]}\n"),
                 23, "rotation.campbell.speeds_rpm", "must increase");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: z}\n"
                          "  campbell: {speeds_rpm: [100]}\n"),
                 23, "rotation.campbell.speeds_rpm", "at least two");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: z}\n"
                          "  campbell: {speeds_rpm: [0, 100], engine_orders: [0]}\n"),
                 23, "rotation.campbell.engine_orders", "engine order");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: z}\n"
                          "  spin_softening: maybe\n"),
                 23, "rotation.spin_softening", "");
  expect_invalid(rotating("rotation:\n  speed_rpm: 5\n  axis: {point: [0, 0, 0], direction: z}\n"
                          "  speed: 5\n"),
                 23, "rotation.speed", "unknown key 'speed'");
  // A rotating case's hand-off to CalculiX would miss the centrifugal load (line 20: output).
  expect_invalid(rotating("output: {calculix_deck: true}\n"
                          "rotation: {speed_rpm: 5, axis: {point: [0, 0, 0], direction: z}}\n"),
                 20, "output.calculix_deck", "centrifugal load");
  // A rotating case is recovered (its centrifugal body force at harmonic 0): no refusal.
  EXPECT_NO_THROW(parse(testing_cases::kMinimalCase +
                        "rotation: {speed_rpm: 5, axis: {point: [0, 0, 0], direction: z}}\n"));
}

}  // namespace
}  // namespace stickslip

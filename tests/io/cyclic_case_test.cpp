// bodies.B.cyclic in the case file: read into CyclicDefinition with its locations, written back by
// describe_case, and every bad value refused at its own line and key.
#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"
#include "io/case_file.h"
#include "minimal_case.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/case";

// The minimal case with body beam1 a sector of 24; `cyclic_lines` replaces its lines 13–17
// (line 12 is "    cyclic:").
std::string cyclic_case(const std::string& cyclic_lines =
                            "      sectors: 24\n"
                            "      axis: {point: [0, 0, 0.1], direction: z}\n"
                            "      low: LOW\n"
                            "      high: [HIGH, 17]\n"
                            "      tolerance: 1.0e-5\n") {
  const std::string old =
      "  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}\n";
  std::string s = testing_cases::kMinimalCase;
  const size_t at = s.find(old);
  EXPECT_NE(at, std::string::npos);
  s.replace(at, old.size(),
            "  beam1:\n"         // line 7
            "    mesh: joint\n"  // 8
            "    element_set: BEAM1\n"
            "    material: steel\n"
            "    clamp: CLAMP1\n"  // 11
            "    cyclic:\n" +      // 12
                cyclic_lines);
  return s;
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

TEST(CyclicCase, TheSectorIsReadWithItsLocationsAndWrittenBack) {
  const CaseDefinition c = parse(cyclic_case());
  ASSERT_TRUE(c.bodies.at("beam1").cyclic.has_value());
  EXPECT_FALSE(c.bodies.at("beam2").cyclic.has_value());
  const CyclicDefinition& d = *c.bodies.at("beam1").cyclic;
  EXPECT_EQ(d.sectors, 24);
  EXPECT_EQ(d.axis_point, (std::array<double, 3>{0, 0, 0.1}));
  EXPECT_EQ(d.axis_direction, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(d.low.sets, std::vector<std::string>{"LOW"});
  EXPECT_EQ(d.high.sets, std::vector<std::string>{"HIGH"});
  EXPECT_EQ(d.high.ids, std::vector<int>{17});
  EXPECT_EQ(d.tolerance, 1.0e-5);
  EXPECT_EQ(c.where("bodies.beam1.cyclic.sectors").line, 13);
  EXPECT_EQ(c.where("bodies.beam1.cyclic.axis.direction").line, 14);
  EXPECT_EQ(c.where("bodies.beam1.cyclic.high").line, 16);
  // describe_case writes a case that describes itself with the same text.
  const std::string described = describe_case(c);
  EXPECT_NE(described.find("cyclic"), std::string::npos);
  EXPECT_EQ(describe_case(parse(described)), described);
  // The default tolerance, and a direction given as a vector (normalised).
  const CaseDefinition d2 =
      parse(cyclic_case("      sectors: 2\n      axis: {point: [1, 2, 3], direction: [0, 0, -2]}\n"
                        "      low: LOW\n      high: HIGH\n"));
  EXPECT_EQ(d2.bodies.at("beam1").cyclic->tolerance, 1.0e-6);
  EXPECT_EQ(d2.bodies.at("beam1").cyclic->axis_direction, (std::array<double, 3>{0, 0, -1}));
  // A body of the sector without boundaries (a damper): no low, no high, written back so.
  const CaseDefinition d3 =
      parse(cyclic_case("      sectors: 6\n      axis: {point: [0, 0, 0], direction: z}\n"));
  EXPECT_TRUE(d3.bodies.at("beam1").cyclic->low.empty());
  EXPECT_TRUE(d3.bodies.at("beam1").cyclic->high.empty());
  const std::string described3 = describe_case(d3);
  EXPECT_EQ(described3.find("low:"), std::string::npos) << described3;
  EXPECT_EQ(describe_case(parse(described3)), described3);
}

TEST(CyclicCase, BadValuesAreRefusedAtTheirLineAndKey) {
  const std::string axis = "      axis: {point: [0, 0, 0], direction: z}\n";
  expect_invalid(cyclic_case("      sectors: 1\n" + axis + "      low: L\n      high: H\n"), 13,
                 "bodies.beam1.cyclic.sectors", "must be >= 2");
  expect_invalid(cyclic_case("      sectors: 1001\n" + axis + "      low: L\n      high: H\n"), 13,
                 "bodies.beam1.cyclic.sectors", "must be <= 1000");
  expect_invalid(cyclic_case("      sectors: 2.5\n" + axis + "      low: L\n      high: H\n"), 13,
                 "bodies.beam1.cyclic.sectors", "expected an integer");
  // Both boundaries or neither (a body of a sector that crosses no boundary).
  expect_invalid(cyclic_case("      sectors: 6\n" + axis + "      low: L\n"), 15,
                 "bodies.beam1.cyclic.low", "both boundaries (low and high) or neither");
  expect_invalid(cyclic_case("      sectors: 6\n" + axis + "      high: H\n"), 15,
                 "bodies.beam1.cyclic.high", "both boundaries (low and high) or neither");
  expect_invalid(cyclic_case("      sectors: 6\n      low: L\n      high: H\n"), 12,
                 "bodies.beam1.cyclic.axis", "required key missing");
  expect_invalid(cyclic_case("      sectors: 6\n" + axis + "      low: L\n      high: H\n" +
                             "      tolerance: 0\n"),
                 17, "bodies.beam1.cyclic.tolerance", "must be > 0");
  expect_invalid(
      cyclic_case("      sectors: 6\n      axis: {point: [0, 0, 0], direction: [0, 0, 0]}\n"
                  "      low: L\n      high: H\n"),
      14, "bodies.beam1.cyclic.axis.direction", "nonzero");
  expect_invalid(cyclic_case("      sectors: 6\n      axis: {point: [0, 0], direction: z}\n"
                             "      low: L\n      high: H\n"),
                 14, "bodies.beam1.cyclic.axis.point", "3 numbers");
  expect_invalid(
      cyclic_case("      sectors: 6\n      axis: {point: [0, 0, 0], direction: z, angle: 3}\n"
                  "      low: L\n      high: H\n"),
      14, "bodies.beam1.cyclic.axis.angle", "unknown key");
  expect_invalid(cyclic_case("      sectors: 6\n" + axis + "      low: L\n      high: H\n" +
                             "      nodal_diameters: 2\n"),
                 17, "bodies.beam1.cyclic.nodal_diameters", "unknown key");
  // A body given by matrices is no sector (no mesh to rotate).
  std::string reduced = testing_cases::kMinimalCase;
  const std::string old =
      "  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}\n";
  reduced.replace(reduced.find(old), old.size(),
                  "  beam2: {reduced: {stiffness: imported/k.hb, mass: imported/m.hb}, cyclic: "
                  "{sectors: 2}}\n");
  expect_invalid(reduced, 8, "bodies.beam2.cyclic", "not allowed with 'reduced'");
}

}  // namespace
}  // namespace stickslip

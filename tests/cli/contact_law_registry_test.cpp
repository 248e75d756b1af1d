// A contact law registered by the program (contact/contact_law.h) is one registration: the case
// file accepts it with its own keys and rules, describe_case writes it back, and the model
// builder makes its elements and stuck springs. The law here is written in this test: a 1D
// spring of stiffness 2·kd (a cubic spring without cubic term), stuck stiffness 2·kd.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <fmt/core.h>
#include <Eigen/Eigenvalues>

#include "cli/pipeline.h"
#include "cli_test_support.h"
#include "contact/contact_law.h"
#include "contact/springs.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/ansys_mapping.h"
#include "io/case_file.h"

namespace stickslip {
namespace {

using namespace cli_test;

constexpr double kKd = 1.5e6;  // N/m

void register_doubled_spring() {
  static const bool registered = [] {
    ContactLaw law;
    law.name = "doubled_spring";
    law.parameters = {{"kd", LawParameter::Rule::kPositive}};
    law.stuck_stiffness = [](const LawValues& v) {
      return Eigen::VectorXd::Constant(1, 2 * v.at("kd")).eval();
    };
    law.make_element = [](const LawValues& v) -> ElementPtr {
      return std::make_shared<CubicSpring>(CubicSpringParameters{2 * v.at("kd"), 0.0});
    };
    register_contact_law(law);
    return true;
  }();
  (void)registered;
}

std::string case_text(const std::string& parameters) {
  return fmt::format(R"(stickslip: 1
bodies:
  b: {{reduced: {{stiffness: k.hb, mass: m.hb}}}}
contacts:
  - name: c
    law: doubled_spring
    bodies: [b, ground]
    pairs: [5]
    direction: x
    per_pair: {{{}}}
excitation:
  - {{body: b, node: 5, direction: x, amplitude: 1}}
analysis:
  frequency: {{start_hz: 10, stop_hz: 20, step_hz: 5}}
)",
                     parameters);
}

TEST(ContactLawRegistry, ALawAddedInTheTestIsParsedDescribedAndBuilt) {
  register_doubled_spring();
  const fs::path dir = fresh_dir("law_registry");
  // One node (id 5) with its three DOFs coupled like a chain of springs, unit masses.
  Eigen::MatrixXd K(3, 3);
  K << 2, -1, 0, -1, 2, -1, 0, -1, 2;
  K *= 1e6;
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(3, 3);
  ReducedBody body;
  body.K = K;
  body.M = M;
  for (int r = 0; r < 3; ++r) {
    ReducedDof d;
    d.node_id = 5;
    d.direction = r;
    body.dofs.push_back(d);
  }
  write_ansys_reduced_body((dir / "k.hb").string(), (dir / "m.hb").string(), body);

  const CaseDefinition def =
      parse_case(case_text(fmt::format("kd: {}", kKd)), "case.yaml", dir.string());
  ASSERT_EQ(def.contacts.size(), 1u);
  EXPECT_EQ(def.contacts[0].law, "doubled_spring");
  EXPECT_FALSE(def.contacts[0].uses_frame);
  EXPECT_EQ(def.contacts[0].parameters.value("kd"), kKd);
  // describe_case writes the law's key back, and its text reads as the same case.
  const CaseDefinition again = parse_case(describe_case(def), "described.yaml", dir.string());
  EXPECT_EQ(again.contacts[0].parameters.value("kd"), kKd);

  // The model builder: the law's element and stuck stiffness for the pair.
  const PreparedModel model = prepare_model(def, nullptr);
  ASSERT_EQ(model.pairs.size(), 1u);
  EXPECT_EQ(model.pairs[0].element->name(), "cubic_spring");
  ASSERT_EQ(model.pair_info[0].stuck_stiffness.size(), 1);
  EXPECT_EQ(model.pair_info[0].stuck_stiffness(0), 2 * kKd);
  Eigen::MatrixXd f;
  model.pairs[0].element->march(Eigen::MatrixXd::Constant(1, 4, 1e-6), nullptr, f, nullptr);
  EXPECT_DOUBLE_EQ(f(0, 0), 2 * kKd * 1e-6);
  // Stuck frequencies: K plus the spring 2·kd on DOF x, by a dense eigen-solve here.
  Eigen::MatrixXd stuck = K;
  stuck(0, 0) += 2 * kKd;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(stuck);
  const Eigen::VectorXd expected = eig.eigenvalues().cwiseSqrt() / (2 * kPi);
  const Eigen::VectorXd hz = stuck_frequencies_hz(model, def);
  ASSERT_EQ(hz.size(), 3);
  EXPECT_LT((hz - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.maxCoeff());
}

TEST(ContactLawRegistry, TheParserAppliesTheRegisteredRulesAndRequiredKeys) {
  register_doubled_spring();
  const fs::path dir = fresh_dir("law_registry_rules");
  const auto error = [&](const std::string& parameters) -> std::string {
    try {
      parse_case(case_text(parameters), "case.yaml", dir.string());
    } catch (const InvalidInput& e) {
      return e.what();
    }
    return "no error";
  };
  // The matrices are not read by the parser: the files only need to exist.
  for (const char* file : {"k.hb", "m.hb", "k.mapping"}) std::ofstream(dir / file) << "";
  EXPECT_EQ(error("kd: 1"), "no error");
  EXPECT_NE(error("kd: -1").find("contacts.c.per_pair.kd"), std::string::npos) << error("kd: -1");
  EXPECT_NE(error("kd: -1").find("must be > 0"), std::string::npos) << error("kd: -1");
  EXPECT_NE(error("k: 1").find("kd"), std::string::npos) << error("k: 1");  // not its key
  EXPECT_THROW(register_contact_law(contact_law("doubled_spring", false)), InvalidInput);
}

}  // namespace
}  // namespace stickslip

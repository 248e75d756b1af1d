// The body-reduction seam (model/body_reduction.h): the analyses of a study share one reduction
// (the same K, M and T objects, not copies), a studied material reduces again, and matrices
// given in memory give the same model as the same matrices read from files.
#include <string>

#include <fmt/core.h>
#include <gtest/gtest.h>

#include "cli/recovery_stage.h"
#include "cli_test_support.h"
#include "core/errors.h"
#include "io/ansys_mapping.h"
#include "io/case_file.h"
#include "model/body_reduction.h"
#include "model/case_model.h"

namespace stickslip {
namespace {

using namespace cli_test;

std::string beam_case(double youngs_modulus, double preload) {
  return fmt::format(R"(stickslip: 1
materials:
  steel: {{youngs_modulus: {}, poisson_ratio: 0.3, density: 7800}}
meshes:
  joint: {{generate: two_beam, arrangement: butt, element: C3D8, box: [4, 2, 2], end_block: [1, 2, 1]}}
bodies:
  beam1: {{mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1, modes: 3}}
  beam2: {{mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2, modes: 3}}
contacts:
  - name: joint
    law: friction
    between: {{beam1: CONTACT1, beam2: CONTACT2}}
    normal: [1, 0, 0]
    per_pair: {{kt: 1.0e8, kn: 1.0e8, mu: 0.5, preload: {}}}
excitation:
  - {{body: beam1, node_set: FORCE1, direction: z, amplitude: 1}}
analysis:
  frequency: {{start_hz: 100, stop_hz: 200, step_hz: 50}}
)",
                     youngs_modulus, preload);
}

TEST(BodyReduction, AnalysesOfAStudyShareOneReductionWithoutCopies) {
  const fs::path dir = fresh_dir("body_reduction_share");
  ModelCache cache;
  const CaseDefinition a = parse_case(beam_case(2e11, 100), "a.yaml", dir.string());
  const CaseDefinition b = parse_case(beam_case(2e11, 50), "b.yaml", dir.string());
  const CaseDefinition c = parse_case(beam_case(1e11, 100), "c.yaml", dir.string());
  const PreparedModel ma = prepare_model(a, nullptr, &cache);
  const PreparedModel mb = prepare_model(b, nullptr, &cache);  // another preload: same bodies
  ASSERT_EQ(ma.bodies.size(), 2u);
  for (size_t i = 0; i < ma.bodies.size(); ++i) {
    ASSERT_TRUE(ma.bodies[i].K && ma.bodies[i].M && ma.bodies[i].T);
    EXPECT_EQ(ma.bodies[i].K.get(), mb.bodies[i].K.get());  // the same object
    EXPECT_EQ(ma.bodies[i].T.get(), mb.bodies[i].T.get());
    EXPECT_EQ(mb.bodies[i].seconds_reduction, 0.0);
    EXPECT_EQ(ma.bodies[i].reduced.K, mb.bodies[i].reduced.K);
  }
  const PreparedModel mc = prepare_model(c, nullptr, &cache);  // another material: reduced again
  for (size_t i = 0; i < mc.bodies.size(); ++i) {
    EXPECT_NE(ma.bodies[i].K.get(), mc.bodies[i].K.get());
    // Half the Young's modulus: half the full stiffness, the same mass.
    EXPECT_NEAR((*ma.bodies[i].K - 2.0 * *mc.bodies[i].K).norm(), 0.0,
                1e-12 * ma.bodies[i].K->norm());
  }
}

TEST(BodyReduction, MatricesGivenInMemoryGiveTheModelOfTheSameMatricesInFiles) {
  const fs::path dir = fresh_dir("body_reduction_given");
  Eigen::MatrixXd K(3, 3);
  K << 2, -1, 0, -1, 2, -1, 0, -1, 2;
  K *= 1e6;
  auto body = std::make_shared<ReducedBody>();
  body->K = K;
  body->M = Eigen::MatrixXd::Identity(3, 3);
  for (int r = 0; r < 3; ++r) {
    ReducedDof d;
    d.node_id = 5;
    d.direction = r;
    body->dofs.push_back(d);
  }
  write_ansys_reduced_body((dir / "k.hb").string(), (dir / "m.hb").string(), *body);
  const std::string text = R"(stickslip: 1
bodies:
  b: {reduced: {stiffness: k.hb, mass: m.hb}}
contacts:
  - name: c
    law: jenkins
    bodies: [b, ground]
    pairs: [5]
    direction: x
    per_pair: {kt: 1.0e6, mu: 0.5, preload: 20}
excitation:
  - {body: b, node: 5, direction: x, amplitude: 5}
analysis:
  frequency: {start_hz: 100, stop_hz: 200, step_hz: 50}
)";
  const CaseDefinition def = parse_case(text, "case.yaml", dir.string());
  const PreparedModel from_files = prepare_model(def, nullptr);
  const GivenReduction given({{"b", body}});
  const PreparedModel in_memory =
      prepare_model(def, resolve_case_bodies(def, nullptr), given, nullptr);
  // The Harwell–Boeing files hold the values to round-off of their printed digits.
  constexpr double kFileDigits = 1e-14;
  EXPECT_TRUE(from_files.K.isApprox(in_memory.K, kFileDigits));
  EXPECT_TRUE(from_files.M.isApprox(in_memory.M, kFileDigits));
  EXPECT_EQ(from_files.pairs[0].dofs_a, in_memory.pairs[0].dofs_a);
  // A given mass that is not positive definite is refused at the body's key.
  auto bad = std::make_shared<ReducedBody>(*body);
  bad->M(2, 2) = -1.0;
  try {
    prepare_model(def, resolve_case_bodies(def, nullptr), GivenReduction({{"b", bad}}), nullptr);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().key, "bodies.b.reduced.mass") << e.what();
    EXPECT_NE(e.message().find("not positive definite"), std::string::npos) << e.what();
  }
}

// A mesh body whose reduced model is given in memory without its full K and M (a program that
// has only the reduced matrices) is solved, but its recovery on the mesh is refused at the body's
// key instead of dereferencing matrices it does not have.
TEST(BodyReduction, AMeshBodyGivenWithoutFullMatricesIsNotRecoveredOnItsMesh) {
  const fs::path dir = fresh_dir("body_reduction_no_full");
  const CaseDefinition def = parse_case(beam_case(2e11, 100), "case.yaml", dir.string());
  const PreparedModel reduced = prepare_model(def, nullptr);
  std::map<std::string, std::shared_ptr<const ReducedBody>> bodies;
  for (const PreparedBody& b : reduced.bodies)
    bodies[b.name] = std::make_shared<ReducedBody>(b.reduced);
  const PreparedModel model =
      prepare_model(def, resolve_case_bodies(def, nullptr), GivenReduction(bodies), nullptr);
  ASSERT_FALSE(model.bodies[0].K);
  EXPECT_TRUE(model.K.isApprox(reduced.K, 1e-14));  // the same reduced model
  const SolvedCase solved = solve_case(model, def, nullptr);
  ASSERT_FALSE(solved.response.points.empty());
  try {
    run_recovery(dir, def, model, solved.response, {0}, [](const std::string&) {});
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().key, "bodies.beam1") << e.what();
    EXPECT_NE(e.message().find("cannot be recovered"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace stickslip

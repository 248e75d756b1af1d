#include "io/case_file.h"
#include "minimal_case.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <functional>

#include <complex>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include "core/errors.h"

namespace stickslip {
namespace {

const std::string kDir = std::string(STICKSLIP_TEST_DATA_DIR) + "/case";

// Exact decimal values written in the files parse to the nearest double: compare exactly where the
// file gives the number, with a tolerance only where the parser computes (unit vectors, polar).
constexpr double kComputed = 1e-12;  // a few ulps of O(1) products of sin/cos/sqrt

// A minimal valid case; the line numbers matter to the tests below (line 1 = "stickslip: 1").
const std::string& kMinimal = testing_cases::kMinimalCase;

// kMinimal with `old` (which must occur once) replaced by `replacement`.
std::string edited(const std::string& old, const std::string& replacement) {
  const size_t at = kMinimal.find(old);
  EXPECT_NE(at, std::string::npos) << old;
  EXPECT_EQ(kMinimal.find(old, at + 1), std::string::npos) << old;
  std::string s = kMinimal;
  if (at != std::string::npos) s.replace(at, old.size(), replacement);
  return s;
}

CaseDefinition parse(const std::string& text) { return parse_case(text, "case.yaml", kDir); }

// Parses `text` expecting InvalidInput at `line` with `key`, and `message` in its message.
void expect_invalid(const std::string& text, int line, const std::string& key,
                    const std::string& message) {
  try {
    parse(text);
    ADD_FAILURE() << "no InvalidInput; expected line " << line << " " << key << ": " << message;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, "case.yaml") << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().key, key) << e.what();
    EXPECT_NE(e.message().find(message), std::string::npos)
        << "message '" << e.message() << "' lacks '" << message << "'";
  }
}

void expect_invalid_file(const std::string& file, int line, const std::string& key,
                         const std::string& message) {
  const std::string path = kDir + "/bad/" + file;
  try {
    read_case_file(path);
    ADD_FAILURE() << "no InvalidInput for " << file;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, path) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().key, key) << e.what();
    EXPECT_NE(e.message().find(message), std::string::npos)
        << "message '" << e.message() << "' lacks '" << message << "'";
    // The full text starts with "file:line: key: ".
    const std::string prefix = path + ":" + std::to_string(line) + ": ";
    EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  }
}

// ----------------------------------------------------------------------------- valid files ---

TEST(CaseFile, ReferenceCaseParsesIntoTheExpectedDefinition) {
  const CaseDefinition c = read_case_file(kDir + "/reference.yaml");
  EXPECT_EQ(c.version, 1);
  EXPECT_EQ(c.title, "two-beam friction joint");
  EXPECT_EQ(c.base_dir, kDir);

  ASSERT_EQ(c.materials.count("steel"), 1u);
  EXPECT_EQ(c.materials.at("steel").youngs_modulus, 2.0e11);
  EXPECT_EQ(c.materials.at("steel").poisson_ratio, 0.3);
  EXPECT_EQ(c.materials.at("steel").density, 7800.0);

  ASSERT_EQ(c.meshes.count("joint"), 1u);
  const MeshDefinition& mesh = c.meshes.at("joint");
  EXPECT_EQ(mesh.source, MeshDefinition::Source::kGenerate);
  EXPECT_EQ(mesh.two_beam.arrangement, TwoBeamOptions::Arrangement::kButt);
  EXPECT_EQ(mesh.two_beam.element, ElementType::kC3D8I);
  EXPECT_FALSE(mesh.two_beam.coarse);
  EXPECT_EQ(mesh.two_beam.box, (std::array<int, 3>{25, 5, 8}));
  EXPECT_EQ(mesh.two_beam.end_block, (std::array<int, 3>{5, 5, 4}));
  EXPECT_EQ(mesh.two_beam.beam_length, 0.25);  // default (docs/conventions.md geometry)

  ASSERT_EQ(c.bodies.size(), 2u);
  const BodyDefinition& beam2 = c.bodies.at("beam2");
  EXPECT_EQ(beam2.source, BodyDefinition::Source::kMesh);
  EXPECT_EQ(beam2.mesh, "joint");
  EXPECT_EQ(beam2.element_set, "BEAM2");
  EXPECT_EQ(beam2.material, "steel");
  EXPECT_EQ(beam2.clamp.sets, std::vector<std::string>{"CLAMP2"});
  EXPECT_EQ(beam2.masters.sets, (std::vector<std::string>{"CONTACT2", "FORCE2"}));
  EXPECT_TRUE(beam2.masters.ids.empty());
  EXPECT_EQ(beam2.modes, 60);
  EXPECT_EQ(beam2.modal_damping_ratio, 0.0);

  ASSERT_EQ(c.contacts.size(), 1u);
  const ContactDefinition& joint = c.contacts[0];
  EXPECT_EQ(joint.name, "joint");
  EXPECT_EQ(joint.law, "friction");
  EXPECT_EQ(joint.body_a, "beam1");
  EXPECT_EQ(joint.body_b, "beam2");
  EXPECT_EQ(joint.nodes_a.sets, std::vector<std::string>{"CONTACT1"});
  EXPECT_EQ(joint.nodes_b.sets, std::vector<std::string>{"CONTACT2"});
  EXPECT_EQ(joint.tolerance, 1.0e-6);
  EXPECT_EQ(joint.normal, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(joint.t1, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(joint.parameters_given, ContactDefinition::Parameters::kPerPair);
  EXPECT_EQ(joint.parameters.kt, 4.467e9);
  EXPECT_EQ(joint.parameters.kn, 5.6309e9);
  EXPECT_EQ(joint.parameters.mu, 0.5);
  EXPECT_EQ(joint.parameters.preload, 150.0);
  EXPECT_EQ(joint.gap, 0.0);
  EXPECT_TRUE(joint.pairs.empty());

  ASSERT_EQ(c.excitation.size(), 2u);
  EXPECT_EQ(c.excitation[0].body, "beam1");
  EXPECT_EQ(c.excitation[0].nodes.sets, std::vector<std::string>{"FORCE1"});
  EXPECT_EQ(c.excitation[0].harmonic, 1);
  EXPECT_EQ(c.excitation[0].force[2], std::complex<double>(50, 0));
  EXPECT_EQ(c.excitation[0].force[0], std::complex<double>(0, 0));
  EXPECT_EQ(c.excitation[1].force[2], std::complex<double>(-50, 0));  // direction -z

  EXPECT_EQ(c.damping.alpha, 5.0);
  EXPECT_EQ(c.damping.beta, 0.0);

  const AnalysisDefinition& a = c.analysis;
  EXPECT_EQ(a.frequency.kind, FrequencyDefinition::Kind::kAroundMode);
  EXPECT_EQ(a.frequency.around_mode, 4);
  EXPECT_EQ(a.frequency.half_width_hz, 2.0);
  EXPECT_EQ(a.frequency.step_hz, 0.01);
  EXPECT_EQ(a.method, SweepMethod::kStepped);
  EXPECT_EQ(a.harmonics, std::vector<int>{1});
  EXPECT_EQ(a.time_samples, 64);
  EXPECT_EQ(a.static_coupling, StaticChoice::kUncoupled);
  EXPECT_EQ(a.tolerance, 1.0e-8);
  EXPECT_EQ(a.max_iterations, 30);
  EXPECT_EQ(a.initial_guess, InitialGuessChoice::kStuck);

  EXPECT_EQ(c.study.parameter, "contacts.joint.per_pair.preload");
  EXPECT_EQ(c.study.values, (std::vector<double>{150, 80, 50}));

  EXPECT_EQ(c.recovery.points, RecoveryPoints::kPeak);
  EXPECT_EQ(c.recovery.method, RecoveryMethod::kDirect);
  EXPECT_EQ(c.recovery.fields,
            (std::vector<RecoveryField>{RecoveryField::kDisplacement, RecoveryField::kStress}));

  EXPECT_EQ(c.output.directory, kDir + "/results");  // resolved against the case file
  EXPECT_TRUE(c.output.vtu);
  EXPECT_TRUE(c.output.plots);
  EXPECT_EQ(c.output.histories.at("joint"), std::vector<int>{0});
  ASSERT_EQ(c.output.frf.size(), 2u);
  EXPECT_EQ(c.output.frf[1].node, 239);
  EXPECT_EQ(c.output.frf[1].direction, 1);

  // Lines of the file (counted in tests/data/case/reference.yaml).
  EXPECT_EQ(c.where("stickslip").line, 4);
  EXPECT_EQ(c.where("materials.steel.density").line, 8);
  EXPECT_EQ(c.where("meshes.joint.box").line, 16);
  EXPECT_EQ(c.where("bodies.beam2.modes").line, 33);
  EXPECT_EQ(c.where("contacts.joint.per_pair.kn").line, 41);
  EXPECT_EQ(c.where("contacts.joint.normal").line, 40);
  EXPECT_EQ(c.where("excitation[1].amplitude").line, 45);
  EXPECT_EQ(c.where("analysis.frequency.step_hz").line, 50);
  EXPECT_EQ(c.where("study.values").line, 61);
  EXPECT_EQ(c.where("contacts.joint.per_pair.kn").key, "contacts.joint.per_pair.kn");
}

TEST(CaseFile, FileAlternativesResolveAgainstTheCaseDirectory) {
  const std::string dir = kDir + "/imported";
  const CaseDefinition c = read_case_file(dir + "/case.yaml");
  EXPECT_EQ(c.materials.at("aluminium").youngs_modulus, 7.0e10);  // 7.0E+10
  EXPECT_EQ(c.materials.at("aluminium").density, 2.7e3);

  const MeshDefinition& part = c.meshes.at("part");
  EXPECT_EQ(part.source, MeshDefinition::Source::kFile);
  EXPECT_EQ(part.file, dir + "/model.inp");
  EXPECT_EQ(part.format, MeshFileFormat::kInp);

  const BodyDefinition& disk = c.bodies.at("disk");
  EXPECT_EQ(disk.clamp.ids, (std::vector<int>{1, 2}));
  EXPECT_EQ(disk.masters.ids, std::vector<int>{7});
  EXPECT_EQ(disk.masters.sets, std::vector<std::string>{"NALL"});
  EXPECT_EQ(disk.modes, 0);
  EXPECT_TRUE(disk.element_set.empty());

  const BodyDefinition& blade = c.bodies.at("blade");
  EXPECT_EQ(blade.source, BodyDefinition::Source::kReduced);
  EXPECT_EQ(blade.reduced.stiffness, dir + "/k.hb");
  EXPECT_EQ(blade.reduced.mass, dir + "/m.hb");
  EXPECT_EQ(blade.reduced.mapping, dir + "/k.mapping");
  EXPECT_EQ(blade.reduced.format, ReducedFileFormat::kHarwellBoeing);
  EXPECT_EQ(blade.modal_damping_ratio, 0.002);

  ASSERT_EQ(c.contacts.size(), 3u);
  const ContactDefinition& root = c.contacts[0];
  EXPECT_EQ(root.body_a, "disk");
  EXPECT_EQ(root.body_b, "blade");
  EXPECT_EQ(root.pairs_file, dir + "/pairs.csv");
  EXPECT_EQ(root.preload_file, dir + "/preload.csv");
  // The CSV files are read at parse time; their records keep their own lines.
  EXPECT_EQ(root.pairs, (std::vector<std::array<int, 2>>{{1, 101}, {2, 102}}));
  EXPECT_EQ(root.preloads, (std::vector<std::pair<int, double>>{{1, 120.0}, {2, 80.0}}));
  EXPECT_EQ(c.where("contacts.root.pairs[1]").file, dir + "/pairs.csv");
  EXPECT_EQ(c.where("contacts.root.pairs[1]").line, 2);
  EXPECT_EQ(c.where("contacts.root.preloads[1]").file, dir + "/preload.csv");
  EXPECT_EQ(c.where("contacts.root.preloads[1]").line, 4);  // after a comment and a header
  EXPECT_EQ(root.parameters_given, ContactDefinition::Parameters::kTotal);
  EXPECT_EQ(root.split, PreloadSplit::kArea);
  EXPECT_EQ(root.parameters.kt, 1.0e8);
  EXPECT_EQ(root.parameters.mu, 0.3);
  EXPECT_NEAR(root.normal[2], -1.0, kComputed);  // normalised [0, 0, -2]
  EXPECT_EQ(root.t1, (std::array<double, 3>{0, 1, 0}));

  const ContactDefinition& tip = c.contacts[1];
  EXPECT_EQ(tip.law, "gap");
  EXPECT_EQ(tip.body_b, "ground");
  ASSERT_EQ(tip.pairs.size(), 1u);
  EXPECT_EQ(tip.pairs[0], (std::array<int, 2>{10, 0}));
  EXPECT_EQ(c.where("contacts.tip.pairs[0]").line, 25);
  EXPECT_EQ(tip.direction, (std::array<double, 3>{0, 1, 0}));
  EXPECT_EQ(tip.parameters.kn, 1e7);
  EXPECT_EQ(tip.gap, 1.0e-5);

  const ContactDefinition& cubic = c.contacts[2];
  EXPECT_EQ(cubic.pairs[0], (std::array<int, 2>{7, 10}));
  EXPECT_EQ(cubic.parameters.k3, -1.5e12);  // softening is allowed
  EXPECT_EQ(cubic.direction, (std::array<double, 3>{1, 0, 0}));

  ASSERT_EQ(c.excitation.size(), 2u);
  EXPECT_FALSE(c.excitation[0].by_direction);
  EXPECT_EQ(c.excitation[0].harmonic, 3);
  EXPECT_EQ(c.excitation[0].force[0], std::complex<double>(1, -2));
  EXPECT_EQ(c.excitation[0].force[2], std::complex<double>(3.5, 0));
  EXPECT_EQ(c.excitation[1].nodes.ids, (std::vector<int>{7, 8}));
  EXPECT_EQ(c.excitation[1].force[2], std::complex<double>(0, 2));
  EXPECT_EQ(c.excitation[1].amplitude, 2.0);
  EXPECT_NEAR(c.excitation[1].phase_deg, 90.0, kComputed * 90);

  const AnalysisDefinition& a = c.analysis;
  EXPECT_EQ(a.frequency.kind, FrequencyDefinition::Kind::kRange);
  EXPECT_EQ(a.frequency.start_hz, 100.0);
  EXPECT_EQ(a.frequency.stop_hz, 300.0);
  EXPECT_EQ(a.frequency.min_step_hz, 0.01);
  EXPECT_EQ(a.frequency.max_step_hz, 2.0);
  EXPECT_EQ(a.method, SweepMethod::kContinuation);
  EXPECT_EQ(a.harmonics, (std::vector<int>{1, 3}));
  EXPECT_EQ(a.time_samples, 14);  // exactly 2(2*3+1)
  EXPECT_EQ(a.static_coupling, StaticChoice::kCoupled);
  EXPECT_EQ(a.max_points, 500);
  EXPECT_EQ(a.initial_guess, InitialGuessChoice::kFree);

  EXPECT_EQ(c.recovery.points, RecoveryPoints::kList);
  EXPECT_EQ(c.recovery.frequencies_hz, (std::vector<double>{150, 250.5}));
  EXPECT_EQ(c.recovery.method, RecoveryMethod::kModal);
  EXPECT_EQ(c.recovery.modes, 40);
  EXPECT_EQ(c.recovery.fields, std::vector<RecoveryField>{RecoveryField::kStress});
  EXPECT_EQ(c.recovery.nodes, std::vector<int>{7});

  EXPECT_EQ(c.output.directory, "/tmp/out");  // absolute: kept
  EXPECT_FALSE(c.output.vtu);
  EXPECT_TRUE(c.output.apdl_macro);
  EXPECT_TRUE(c.output.calculix_deck);
  EXPECT_TRUE(c.output.quiet);
}

TEST(CaseFile, OmittedKeysTakeTheStructDefaults) {
  const CaseDefinition c = parse(kMinimal);
  const AnalysisDefinition defaults;
  EXPECT_EQ(c.analysis.method, defaults.method);
  EXPECT_EQ(c.analysis.harmonics, defaults.harmonics);
  EXPECT_EQ(c.analysis.time_samples, defaults.time_samples);
  EXPECT_EQ(c.analysis.tolerance, defaults.tolerance);
  EXPECT_EQ(c.analysis.predictor, PredictorChoice::kSecant);
  EXPECT_EQ(c.bodies.at("beam1").modes, BodyDefinition{}.modes);
  EXPECT_EQ(c.contacts[0].tolerance, ContactDefinition{}.tolerance);
  EXPECT_EQ(c.recovery.points, RecoveryDefinition{}.points);
  EXPECT_EQ(c.meshes.at("joint").two_beam.box, TwoBeamDefinition{}.box);
  EXPECT_FALSE(c.study.active());
  EXPECT_EQ(c.output.directory, kDir + "/results");
  // A default reports the block it belongs to.
  EXPECT_EQ(c.where("analysis.time_samples").line, 17);
  EXPECT_EQ(c.where("contacts.joint.tolerance").line, 10);
  EXPECT_EQ(c.where("damping.alpha").line, 0);
}

TEST(CaseFile, WithParameterSetsTheStudyValue) {
  const CaseDefinition c = read_case_file(kDir + "/reference.yaml");
  const CaseDefinition c80 = with_parameter(c, "contacts.joint.per_pair.preload", 80);
  EXPECT_EQ(c80.contacts[0].parameters.preload, 80.0);
  EXPECT_EQ(c.contacts[0].parameters.preload, 150.0);  // the original is unchanged
  const CaseDefinition f = with_parameter(c, "excitation[1].amplitude", 20);
  EXPECT_EQ(f.excitation[1].force[2], std::complex<double>(-20, 0));  // direction -z kept
  EXPECT_EQ(with_parameter(c, "damping.alpha", 2).damping.alpha, 2.0);
  EXPECT_EQ(with_parameter(c, "materials.steel.youngs_modulus", 7e10)
                .materials.at("steel")
                .youngs_modulus,
            7e10);
  EXPECT_THROW(with_parameter(c, "contacts.joint.per_pair.k", 1), InvalidInput);  // not friction
  EXPECT_THROW(with_parameter(c, "contacts.joint.total.kt", 1), InvalidInput);    // given per pair
  EXPECT_THROW(with_parameter(c, "contacts.joint.per_pair.mu", -0.1), InvalidInput);
  EXPECT_THROW(with_parameter(c, "analysis.time_samples", 10), InvalidInput);
  EXPECT_THROW(with_parameter(c, "excitation[7].amplitude", 1), InvalidInput);
}

TEST(CaseFile, DescribeCaseListsTheResolvedValues) {
  const CaseDefinition c = read_case_file(kDir + "/reference.yaml");
  const std::string text = describe_case(c);
  for (const std::string& s :
       {std::string("kn: 5630900000"), std::string("around_mode: 4"),
        std::string("parameter: contacts.joint.per_pair.preload"),
        std::string("directory: ") + kDir + "/results", std::string("time_samples: 64")}) {
    EXPECT_NE(text.find(s), std::string::npos) << s << " not in\n" << text;
  }
}

TEST(CaseFile, DescribeCaseIsYamlWithExactNumbers) {
  const CaseDefinition c = read_case_file(kDir + "/imported/case.yaml");
  const YAML::Node d = YAML::Load(describe_case(c));
  EXPECT_EQ(d["materials"]["aluminium"]["poisson_ratio"].as<double>(), 0.33);
  EXPECT_EQ(d["contacts"][1]["gap"].as<double>(), 1.0e-5);
  EXPECT_EQ(d["contacts"][1]["bodies"][1].as<std::string>(), "ground");
  EXPECT_EQ(d["contacts"][0]["total"]["split"].as<std::string>(), "area");
  EXPECT_EQ(d["excitation"][0]["force"][0][1].as<double>(), -2.0);
  EXPECT_EQ(d["analysis"]["harmonics"][1].as<int>(), 3);
  EXPECT_EQ(d["analysis"]["frequency"]["min_step_hz"].as<double>(), 0.01);
  EXPECT_EQ(d["recovery"]["points"][1].as<double>(), 250.5);
}

// law linear, 3D: springs kt, kt, kn in the frame normal/t1, per pair or as totals; the 1D form
// (k along direction) is unchanged. Study parameters and describe_case follow the form given.
TEST(CaseFile, LinearLawIn3DTakesKtKnAndTheContactFrame) {
  std::string text = edited(
      "normal: [1, 0, 0]\n    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, "
      "preload: 150}",
      "normal: [1, 0, 0]\n    t1: [0, 0, 1]\n    per_pair: {kt: 1.5e9, kn: "
      "2.5e9}");
  text.replace(text.find("law: friction"), 13, "law: linear");
  const CaseDefinition c = parse(text);
  const ContactDefinition& d = c.contacts[0];
  EXPECT_TRUE(d.uses_frame);
  EXPECT_EQ(d.parameters.kt, 1.5e9);
  EXPECT_EQ(d.parameters.kn, 2.5e9);
  EXPECT_EQ(d.parameters.k, 0.0);
  EXPECT_EQ(d.normal, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(d.t1, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(with_parameter(c, "contacts.joint.per_pair.kn", 7e9).contacts[0].parameters.kn, 7e9);
  EXPECT_THROW(with_parameter(c, "contacts.joint.per_pair.k", 1), InvalidInput);  // 1D key
  const YAML::Node y = YAML::Load(describe_case(c));
  EXPECT_EQ(y["contacts"][0]["law"].as<std::string>(), "linear");
  EXPECT_EQ(y["contacts"][0]["normal"][0].as<double>(), 1.0);
  EXPECT_EQ(y["contacts"][0]["per_pair"]["kn"].as<double>(), 2.5e9);
  EXPECT_FALSE(y["contacts"][0]["per_pair"]["k"]);
  EXPECT_FALSE(y["contacts"][0]["direction"]);

  std::string total = edited("per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: 150}",
                             "total: {kt: 3.0e9, kn: 4.0e9, split: area}");
  total.replace(total.find("law: friction"), 13, "law: linear");
  const CaseDefinition t = parse(total);
  EXPECT_TRUE(t.contacts[0].uses_frame);
  EXPECT_EQ(t.contacts[0].parameters_given, ContactDefinition::Parameters::kTotal);
  EXPECT_EQ(t.contacts[0].split, PreloadSplit::kArea);
  EXPECT_EQ(t.contacts[0].parameters.kt, 3.0e9);

  std::string one_d = edited(
      "normal: [1, 0, 0]\n    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: "
      "0.5, preload: 150}",
      "direction: y\n    per_pair: {k: 2.0e9}");
  one_d.replace(one_d.find("law: friction"), 13, "law: linear");
  const CaseDefinition o = parse(one_d);
  EXPECT_FALSE(o.contacts[0].uses_frame);
  EXPECT_EQ(o.contacts[0].parameters.k, 2.0e9);
  EXPECT_EQ(o.contacts[0].direction, (std::array<double, 3>{0, 1, 0}));
  EXPECT_THROW(with_parameter(o, "contacts.joint.per_pair.kt", 1), InvalidInput);  // 3D key
}

// ----------------------------------------------------------------------- bad input, one by one ---

TEST(CaseFileErrors, UnknownTopLevelKeyIsRejectedWithASuggestion) {
  expect_invalid_file("unknown_key.yaml", 8, "analisys", "did you mean 'analysis'?");
}

TEST(CaseFileErrors, UnknownNestedKeyIsRejectedWithItsLine) {
  expect_invalid(edited("    normal: [1, 0, 0]\n", "    normal: [1, 0, 0]\n    tolerence: 1e-6\n"),
                 14, "contacts.joint.tolerence", "did you mean 'tolerance'?");
}

TEST(CaseFileErrors, UnknownKeyFarFromEveryKnownKeyHasNoSuggestion) {
  try {
    parse(edited("analysis:\n", "colour: blue\nanalysis:\n"));
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().line, 17);
    EXPECT_EQ(e.message().find("did you mean"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("known keys: stickslip, title"), std::string::npos);
  }
}

TEST(CaseFileErrors, ParameterOfAnotherLawIsRejected) {
  expect_invalid(edited("mu: 0.5, preload: 150}", "mu: 0.5, k: 3}"), 14,
                 "contacts.joint.per_pair.k", "unknown key 'k' for law friction");
}

TEST(CaseFileErrors, QuotedNumberIsAString) {
  expect_invalid_file("wrong_type.yaml", 4, "materials.steel.youngs_modulus",
                      "expected a number, got the string \"2.0e11\"");
}

TEST(CaseFileErrors, TextWhereANumberIsExpected) {
  expect_invalid(edited("density: 7800", "density: heavy"), 3, "materials.steel.density",
                 "expected a number, got 'heavy'");
}

TEST(CaseFileErrors, ScalarWhereAListIsExpected) {
  expect_invalid(edited("joint: {generate: two_beam}", "joint: {generate: two_beam, box: 25}"), 5,
                 "meshes.joint.box", "expected a list, got '25'");
}

TEST(CaseFileErrors, ListWhereAMapIsExpected) {
  expect_invalid(edited("per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: 150}",
                        "per_pair: [4.467e9, 5.6309e9]"),
                 14, "contacts.joint.per_pair", "expected a map of keys, got a list");
}

// Beam 2's own mesh density and the coupling choice: rules at their keys, and both written back
// by describe_case only when given (the default's fingerprints stay).
TEST(CaseFileErrors, BeamTwoDivisionsAndCouplingKeysFollowTheirRules) {
  const std::string mesh = "joint: {generate: two_beam}";
  expect_invalid(edited(mesh,
                        "joint: {generate: two_beam, box: [8, 2, 4], end_block: [2, 2, 2], "
                        "beam2_box: [12, 3, 6], beam2_end_block: [3, 2, 3]}"),
                 5, "meshes.joint.beam2_end_block",
                 "needs beam2_end_block[1] (y) = beam2_box[1], got 2 and 3");
  expect_invalid(edited(mesh, "joint: {generate: two_beam, coarse: true, beam2_box: [8, 5, 12]}"),
                 5, "meshes.joint.coarse", "has no beam2_box or beam2_end_block");
  const std::string normal = "    normal: [1, 0, 0]\n";
  expect_invalid(edited(normal, normal + "    coupling: nodes\n    search_distance: 0.01\n"), 15,
                 "contacts.joint.search_distance", "with coupling: nodes");
  expect_invalid(edited(normal, normal + "    coupling: mortar\n    tolerance: 0.01\n"), 15,
                 "contacts.joint.tolerance", "with coupling: mortar");
  // Given: written back and read again the same; not given: not written.
  const CaseDefinition given = parse(edited(
      mesh, "joint: {generate: two_beam, beam2_box: [25, 8, 12], beam2_end_block: [5, 8, 6]}"));
  const CaseDefinition nodes = parse(edited(normal, normal + "    coupling: nodes\n"));
  EXPECT_EQ(parse(kMinimal).contacts[0].coupling, ContactCoupling::kAuto);
  EXPECT_EQ(nodes.contacts[0].coupling, ContactCoupling::kNodes);
  EXPECT_EQ(describe_case(parse(kMinimal)).find("coupling"), std::string::npos);
  EXPECT_EQ(describe_case(parse(kMinimal)).find("beam2_"), std::string::npos);
  const CaseDefinition again = parse(describe_case(nodes));
  EXPECT_EQ(again.contacts[0].coupling, ContactCoupling::kNodes);
  const CaseDefinition given_again = parse(describe_case(given));
  ASSERT_TRUE(given_again.meshes.at("joint").two_beam.beam2_box.has_value());
  EXPECT_EQ(*given_again.meshes.at("joint").two_beam.beam2_box, (std::array<int, 3>{25, 8, 12}));
  EXPECT_EQ(*given_again.meshes.at("joint").two_beam.beam2_end_block,
            (std::array<int, 3>{5, 8, 6}));
}

TEST(CaseFileErrors, IntegerExpected) {
  expect_invalid(edited("  frequency:", "  harmonics: 1.5\n  frequency:"), 18, "analysis.harmonics",
                 "expected an integer, got '1.5'");
}

TEST(CaseFileErrors, MissingRequiredKey) {
  expect_invalid(edited("poisson_ratio: 0.3, density: 7800", "poisson_ratio: 0.3"), 3,
                 "materials.steel.density", "required key missing");
}

TEST(CaseFileErrors, MissingAnalysis) {
  const std::string text = kMinimal.substr(0, kMinimal.find("analysis:"));
  expect_invalid(text, 1, "analysis", "required key missing");
}

TEST(CaseFileErrors, MissingVersionAndWrongVersion) {
  expect_invalid(edited("stickslip: 1\n", "title: x\n"), 1, "stickslip", "required key missing");
  expect_invalid(edited("stickslip: 1\n", "stickslip: 2\n"), 1, "stickslip",
                 "unsupported format version 2");
}

TEST(CaseFileErrors, NegativeStiffness) {
  expect_invalid(edited("kt: 4.467e9", "kt: -4.467e9"), 14, "contacts.joint.per_pair.kt",
                 "must be > 0, got -4467000000");
}

TEST(CaseFileErrors, NegativeFrictionCoefficient) {
  expect_invalid(edited("mu: 0.5", "mu: -0.1"), 14, "contacts.joint.per_pair.mu",
                 "must be >= 0, got -0.1");
}

TEST(CaseFileErrors, NegativePreload) {
  expect_invalid(edited("preload: 150", "preload: -1"), 14, "contacts.joint.per_pair.preload",
                 "must be >= 0");
}

TEST(CaseFileErrors, MaterialOutOfRange) {
  expect_invalid(edited("poisson_ratio: 0.3", "poisson_ratio: 0.5"), 3,
                 "materials.steel.poisson_ratio", "must be in (-1, 0.5)");
}

TEST(CaseFileErrors, EmptyFrequencyRange) {
  expect_invalid(edited("stop_hz: 1856", "stop_hz: 1852"), 18, "analysis.frequency.stop_hz",
                 "the frequency range is empty or inverted");
}

TEST(CaseFileErrors, InvertedFrequencyRange) {
  expect_invalid(edited("stop_hz: 1856", "stop_hz: 1800"), 18, "analysis.frequency.stop_hz",
                 "stop_hz = 1800 must be > start_hz = 1852");
}

TEST(CaseFileErrors, StepNotPositive) {
  expect_invalid(edited("step_hz: 0.01", "step_hz: 0"), 18, "analysis.frequency.step_hz",
                 "must be > 0, got 0");
  expect_invalid(edited("step_hz: 0.01", "step_hz: -0.01"), 18, "analysis.frequency.step_hz",
                 "must be > 0");
}

TEST(CaseFileErrors, RangeAndAroundModeTogether) {
  expect_invalid(edited("step_hz: 0.01}", "step_hz: 0.01, around_mode: 4}"), 18,
                 "analysis.frequency.start_hz", "not allowed with 'around_mode'");
}

TEST(CaseFileErrors, TooFewTimeSamples) {
  expect_invalid(edited("  frequency:", "  harmonics: 3\n  time_samples: 12\n  frequency:"), 19,
                 "analysis.time_samples", "must be >= 2(2H+1) = 14 for highest harmonic H = 3");
  expect_invalid(edited("  frequency:", "  harmonics: [1, 5]\n  time_samples: 21\n  frequency:"),
                 19, "analysis.time_samples", "= 22");
}

// Upper bounds (docs/case-file.md, "Limits"): each key is refused just above its bound, at its
// line with the rule, and accepted at the bound.
TEST(CaseFileErrors, TimeSamplesAboveTheirUpperBound) {
  const auto with = [](const std::string& lines) {
    return edited("  frequency:", lines + "  frequency:");
  };
  // H = 1: 64(2H+1) = 192 < 4096, so 4096 is the bound.
  expect_invalid(with("  time_samples: 6400000\n"), 18, "analysis.time_samples",
                 "must be <= min(65536, max(4096, 64(2H+1))) = 4096 for highest harmonic H = 1, "
                 "got 6400000");
  EXPECT_EQ(parse(with("  time_samples: 4096\n")).analysis.time_samples, 4096);
  expect_invalid(with("  time_samples: 4097\n"), 18, "analysis.time_samples", "= 4096");
  // H = 100: 64 * 201 = 12864.
  EXPECT_EQ(parse(with("  harmonics: 100\n  time_samples: 12864\n")).analysis.time_samples, 12864);
  expect_invalid(with("  harmonics: [1, 100]\n  time_samples: 12865\n"), 19,
                 "analysis.time_samples", "= 12864 for highest harmonic H = 100");
  // H = 1000: 64 * 2001 > 65536, so 2^16 is the bound.
  EXPECT_EQ(parse(with("  harmonics: 1000\n  time_samples: 65536\n")).analysis.time_samples, 65536);
  expect_invalid(with("  harmonics: 1000\n  time_samples: 65537\n"), 19, "analysis.time_samples",
                 "= 65536");
}

TEST(CaseFileErrors, MaxPointsAboveItsUpperBound) {
  const auto with = [](const std::string& value) {
    return edited("  frequency:",
                  "  method: continuation\n  max_points: " + value + "\n  frequency:");
  };
  expect_invalid(with("1000000000"), 19, "analysis.max_points",
                 "must be <= 1000000 (points of one continuation, each solved and written), got "
                 "1000000000");
  expect_invalid(with("1000001"), 19, "analysis.max_points", "must be <= 1000000");
  EXPECT_EQ(parse(with("1000000")).analysis.max_points, 1000000);
}

TEST(CaseFileErrors, SteppedSweepOfMoreThanAMillionPoints) {
  // 4 Hz window: step 1e-9 Hz would be 4e9 points.
  expect_invalid(edited("step_hz: 0.01", "step_hz: 1e-9"), 18, "analysis.frequency.step_hz",
                 "the stepped sweep would have 4000000000 points (window 4 Hz / step_hz + 1): at "
                 "most 1000000 are accepted");
  expect_invalid(edited("step_hz: 0.01", "step_hz: 3.9e-6"), 18, "analysis.frequency.step_hz",
                 "1025642 points");
  EXPECT_NO_THROW(parse(edited("step_hz: 0.01", "step_hz: 4.1e-6")));  // 975610 points
  // The window around a mode: 2 x half_width_hz.
  expect_invalid(edited("{start_hz: 1852, stop_hz: 1856, step_hz: 0.01}",
                        "{around_mode: 4, half_width_hz: 1, step_hz: 1e-7}"),
                 18, "analysis.frequency.step_hz", "(window 2 Hz / step_hz + 1)");
  // Continuation: step_hz is the initial step only; max_points bounds the points.
  EXPECT_NO_THROW(
      parse(edited("  frequency: {start_hz: 1852, stop_hz: 1856, step_hz: 0.01}",
                   "  method: continuation\n  frequency: {start_hz: 1852, stop_hz: 1856, "
                   "step_hz: 1e-9}")));
}

TEST(CaseFileErrors, BodyModesAboveTheLargestReducedBody) {
  expect_invalid(edited("clamp: CLAMP1}", "clamp: CLAMP1, modes: 20001}"), 7, "bodies.beam1.modes",
                 "must be <= 20000 (the largest reduced body");
  EXPECT_EQ(
      parse(edited("clamp: CLAMP1}", "clamp: CLAMP1, modes: 20000}")).bodies.at("beam1").modes,
      20000);
}

TEST(CaseFileErrors, RecoveryModesAboveTheirUpperBound) {
  const std::string tail = "recovery: {method: modal, modes: ";
  expect_invalid(kMinimal + tail + "10001}\n", 19, "recovery.modes",
                 "must be <= 10000 (full-model modes of the modal recovery), got 10001");
  EXPECT_EQ(parse(kMinimal + tail + "10000}\n").recovery.modes, 10000);
}

TEST(CaseFileErrors, GeneratedBeamOfMoreThanAMillionElements) {
  const auto with = [](const std::string& keys) {
    return edited("joint: {generate: two_beam}", "joint: {generate: two_beam, " + keys + "}");
  };
  expect_invalid(with("box: [100, 5, 2000]"), 5, "meshes.joint.box",
                 "box [100, 5, 2000] and end_block [5, 5, 4] make more than 1000000 elements per "
                 "beam");
  // Counts whose product overflows 64 bits are refused the same way.
  expect_invalid(with("box: [2147483647, 5, 2147483647], end_block: [2147483647, 5, 4]"), 5,
                 "meshes.joint.end_block", "make more than 1000000 elements per beam");
  EXPECT_NO_THROW(parse(with("box: [100, 5, 1990]")));  // 995000 + 100 elements
}

TEST(CaseFileErrors, HarmonicListNotIncreasing) {
  expect_invalid(edited("  frequency:", "  harmonics: [1, 3, 3]\n  frequency:"), 18,
                 "analysis.harmonics", "strictly increasing");
}

TEST(CaseFileErrors, UnknownMaterial) {
  expect_invalid(
      edited("element_set: BEAM2, material: steel", "element_set: BEAM2, material: stel"), 8,
      "bodies.beam2.material", "unknown material 'stel' (did you mean 'steel'?)");
}

TEST(CaseFileErrors, UnknownMesh) {
  expect_invalid(edited("beam1: {mesh: joint", "beam1: {mesh: jont"), 7, "bodies.beam1.mesh",
                 "unknown mesh 'jont' (did you mean 'joint'?)");
}

TEST(CaseFileErrors, UnknownBodyInContact) {
  expect_invalid(edited("{beam1: CONTACT1, beam2: CONTACT2}", "{beam1: CONTACT1, beam3: CONTACT2}"),
                 12, "contacts.joint.between.beam3", "unknown body 'beam3'");
}

TEST(CaseFileErrors, UnknownBodyInExcitation) {
  expect_invalid(edited("{body: beam1, node_set: FORCE1", "{body: bean1, node_set: FORCE1"), 16,
                 "excitation[0].body", "unknown body 'bean1' (did you mean 'beam1'?)");
}

TEST(CaseFileErrors, BothPerPairAndTotal) {
  expect_invalid(edited("    per_pair:", "    total: {kt: 1, kn: 1, mu: 0.1}\n    per_pair:"), 14,
                 "contacts.joint.total", "give either 'per_pair' or 'total', not both");
}

TEST(CaseFileErrors, BothPreloadAndGap) {
  expect_invalid(edited("    normal: [1, 0, 0]\n", "    normal: [1, 0, 0]\n    gap: 1e-6\n"), 14,
                 "contacts.joint.gap", "give either a preload or a gap, not both");
}

TEST(CaseFileErrors, BothPreloadAndPreloadFile) {
  expect_invalid(edited("    normal: [1, 0, 0]\n",
                        "    normal: [1, 0, 0]\n    preload_file: imported/preload.csv\n"),
                 15, "contacts.joint.per_pair.preload",
                 "give either 'preload' or 'preload_file', not both");
}

TEST(CaseFileErrors, NoContactNodes) {
  expect_invalid(edited("    between: {beam1: CONTACT1, beam2: CONTACT2}\n", ""), 10,
                 "contacts.joint.between", "give 'between' (node sets), 'pairs' or 'pairs_file'");
}

TEST(CaseFileErrors, FrictionNeedsANormal) {
  expect_invalid(edited("    normal: [1, 0, 0]\n", ""), 10, "contacts.joint.normal",
                 "required key missing");
  expect_invalid(edited("normal: [1, 0, 0]", "normal: [0, 0, 0]"), 13, "contacts.joint.normal",
                 "must be a nonzero vector");
}

TEST(CaseFileErrors, DuplicateContactName) {
  const std::string second =
      "  - {name: joint, law: linear, bodies: [beam1, beam2], pairs: [[1, 2]], direction: x,"
      " per_pair: {k: 1}}\nexcitation:\n";
  expect_invalid(edited("excitation:\n", second), 15, "contacts.joint.name",
                 "duplicate contact name 'joint'");
}

TEST(CaseFileErrors, ExcitationHarmonicNotSolved) {
  expect_invalid(edited("amplitude: 50}", "amplitude: 50, harmonic: 2}"), 16,
                 "excitation[0].harmonic", "harmonic 2 is not solved");
}

TEST(CaseFileErrors, ExcitationNeedsOneNodeKey) {
  expect_invalid(
      edited("node_set: FORCE1, direction: z", "node_set: FORCE1, node: 239, direction: z"), 16,
      "excitation[0].node", "give either 'node_set' or 'node', not both");
}

TEST(CaseFileErrors, ReducedBodyHasNoCoordinatesForCoincidence) {
  const std::string reduced =
      "  beam2: {reduced: {stiffness: imported/k.hb, mass: imported/m.hb}}\n";
  expect_invalid(
      edited("  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}\n",
             reduced),
      12, "contacts.joint.between.beam2", "list the pairs instead");
}

TEST(CaseFileErrors, MissingMeshFileNamesTheResolvedPath) {
  expect_invalid_file("missing_mesh_file.yaml", 6, "meshes.part.file",
                      "file not found: " + kDir + "/bad/no_such_mesh.inp");
}

TEST(CaseFileErrors, MissingMatrixFile) {
  const std::string reduced =
      "  beam3: {reduced: {stiffness: imported/k.hb, mass: imported/mass.hb}}\n";
  expect_invalid(edited("contacts:\n", reduced + "contacts:\n"), 9, "bodies.beam3.reduced.mass",
                 "file not found");
}

TEST(CaseFileErrors, MissingDefaultMapping) {
  // m.hb has no m.mapping next to it.
  const std::string reduced =
      "  beam3: {reduced: {stiffness: imported/m.hb, mass: imported/m.hb}}\n";
  expect_invalid(edited("contacts:\n", reduced + "contacts:\n"), 9, "bodies.beam3.reduced.mapping",
                 "m.mapping");
}

TEST(CaseFileErrors, MissingPairsFile) {
  expect_invalid(edited("    between: {beam1: CONTACT1, beam2: CONTACT2}\n",
                        "    bodies: [beam1, beam2]\n    pairs_file: pairs.csv\n"),
                 13, "contacts.joint.pairs_file", "file not found: " + kDir + "/pairs.csv");
}

TEST(CaseFileErrors, YamlSyntaxErrorReportsYamlCppsLine) {
  // The unclosed flow map of line 3 is noticed at the next key, line 4.
  expect_invalid_file("syntax_error.yaml", 4, "", "YAML syntax error");
}

TEST(CaseFileErrors, DuplicateKeyIsRejected) {
  expect_invalid_file("duplicate_key.yaml", 12, "analysis.harmonics",
                      "duplicate key (first given on line 10)");
}

TEST(CaseFileErrors, DuplicateNameIsRejected) {
  expect_invalid(edited("contacts:\n",
                        "  beam1: {reduced: {stiffness: imported/k.hb, mass: "
                        "imported/m.hb}}\ncontacts:\n"),
                 9, "bodies.beam1", "duplicate");
}

TEST(CaseFileErrors, StudyParameterMustBeANumericKey) {
  expect_invalid(kMinimal + "study: {parameter: analysis.harmonics, values: [1, 3]}\n", 19,
                 "study.parameter", "not a numeric key that a study can vary");
}

TEST(CaseFileErrors, StudyValueMustObeyTheKeysRule) {
  expect_invalid(
      kMinimal + "study: {parameter: contacts.joint.per_pair.preload, values: [1, -5]}\n", 19,
      "study.values", "'contacts.joint.per_pair.preload' = -5: must be >= 0");
}

TEST(CaseFileErrors, BadChoiceListsTheOptions) {
  expect_invalid(edited("law: friction", "law: frictoin"), 11, "contacts.joint.law",
                 "must be one of cubic | friction | gap | jenkins | linear, got 'frictoin' (did "
                 "you mean 'friction'?)");
}

TEST(CaseFileErrors, HistoriesNameAContact) {
  expect_invalid(
      kMinimal + "output:\n  histories: {jiont: [0]}\n", 20, "output.histories.jiont",
      "unknown key 'jiont' (histories are keyed by contact name) (did you mean 'joint'?)");
}

TEST(CaseFileErrors, ReducedBodyHasNoNodeSets) {
  const std::string text =
      edited("  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}\n",
             "  beam2: {reduced: {stiffness: imported/k.hb, mass: imported/m.hb}}\n");
  const std::string contact = "    between: {beam1: CONTACT1, beam2: CONTACT2}\n";
  std::string t = text;
  t.replace(t.find(contact), contact.size(), "    bodies: [beam1, beam2]\n    pairs: [[1, 10]]\n");
  t.replace(t.find("{body: beam1, node_set: FORCE1"), 30, "{body: beam2, node_set: FORCE2");
  expect_invalid(t, 17, "excitation[0].node_set", "give node ids");
}

TEST(CaseFileErrors, FrameChecks) {
  expect_invalid(edited("normal: [1, 0, 0]", "normal: [1, 0, 0]\n    t1: -x"), 14,
                 "contacts.joint.t1", "must not be parallel to the normal");
  expect_invalid(edited("law: friction", "law: jenkins"), 13, "contacts.joint.normal",
                 "not allowed for law jenkins");
  std::string linear = edited(
      "normal: [1, 0, 0]\n    per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: "
      "0.5, preload: 150}",
      "direction: w\n    per_pair: {k: 1.0e9}");
  linear.replace(linear.find("law: friction"), 13, "law: linear");
  expect_invalid(linear, 13, "contacts.joint.direction", "must be one of x | y | z");
}

// law linear: the 1D keys (k, direction) and the 3D keys (kt, kn, normal, t1) never mix; the
// error names the 1D key, its line, and the 3D key it clashes with.
TEST(CaseFileErrors, LinearLawDoesNotMix1DAnd3DKeys) {
  const std::string params = "per_pair: {kt: 4.467e9, kn: 5.6309e9, mu: 0.5, preload: 150}";
  const auto linear = [&](const std::string& frame, const std::string& per_pair) {
    std::string text = edited("normal: [1, 0, 0]\n    " + params, frame + "\n    " + per_pair);
    text.replace(text.find("law: friction"), 13, "law: linear");
    return text;
  };
  // Line 13: the frame key; line 14: the parameters.
  expect_invalid(linear("direction: x", "per_pair: {kt: 1.0e9, kn: 2.0e9}"), 13,
                 "contacts.joint.direction", "not both: 'direction' here, 'kt' on line 14");
  expect_invalid(linear("normal: z", "per_pair: {k: 1.0e9}"), 14, "contacts.joint.per_pair.k",
                 "not both: 'k' here, 'normal' on line 13");
  expect_invalid(linear("direction: x", "per_pair: {k: 1.0e9, kn: 2.0e9}"), 13,
                 "contacts.joint.direction", "'direction' here, 'kn' on line 14");
  expect_invalid(linear("t1: x", "total: {k: 1.0e9}"), 14, "contacts.joint.total.k",
                 "'t1' on line 13");
  // 3D without its frame or one of its stiffnesses.
  std::string no_frame = edited("normal: [1, 0, 0]\n    " + params, "per_pair: {kt: 1, kn: 2}");
  no_frame.replace(no_frame.find("law: friction"), 13, "law: linear");
  expect_invalid(no_frame, 10, "contacts.joint.normal", "required key missing");
  expect_invalid(linear("normal: z", "per_pair: {kt: 1.0e9}"), 14, "contacts.joint.per_pair.kn",
                 "required key missing");
  expect_invalid(linear("normal: z", "per_pair: {kt: 1.0e9, kn: -2}"), 14,
                 "contacts.joint.per_pair.kn", "must be > 0");
}

TEST(CaseFileErrors, KeysThatDoNotApply) {
  expect_invalid(edited("    between: {beam1: CONTACT1, beam2: CONTACT2}\n",
                        "    bodies: [beam1, beam2]\n    pairs: [[1, 2]]\n    tolerance: 1e-3\n"),
                 14, "contacts.joint.tolerance", "not allowed with listed pairs");
  expect_invalid(edited("joint: {generate: two_beam}", "joint: {generate: two_beam, format: inp}"),
                 5, "meshes.joint.format", "not allowed with 'generate'");
  expect_invalid(edited("clamp: CLAMP2}", "clamp: CLAMP2, reduced: {stiffness: x, mass: y}}"), 8,
                 "bodies.beam2.mesh", "not allowed with 'reduced'");
  expect_invalid(kMinimal + "recovery: {method: direct, modes: 20}\n", 19, "recovery.modes",
                 "not allowed unless method is modal");
}

TEST(CaseFile, SweepBenchmarkCaseIsTheReferenceCaseWithoutItsOtherOutputs) {
  // bench/cases/reference_sweep.yaml times issue 4's reference sweep (docs/performance.md): it must
  // stay the reference case, with only recovery, VTU, plots and the FRF node changed.
  CaseDefinition reference = read_case_file(kDir + "/reference.yaml");
  const CaseDefinition bench = read_case_file(std::string(STICKSLIP_TEST_DATA_DIR) +
                                              "/../../bench/cases/reference_sweep.yaml");
  reference.recovery.points = RecoveryPoints::kNone;
  reference.output.vtu = false;
  reference.output.plots = false;
  for (ResponseDofDefinition& dof : reference.output.frf) dof.node = 11;
  reference.output.directory = bench.output.directory;
  EXPECT_EQ(describe_case(bench), describe_case(reference));
}

// Each choice of the analysis and recovery blocks: the name read into its enum, and describe_case
// writing the same name back (the text is the file's; the enum is what the program switches on).
TEST(CaseFile, EveryChoiceIsReadIntoItsValueAndWrittenBackByName) {
  const auto check = [](const std::string& extra, const std::string& written,
                        const std::function<bool(const CaseDefinition&)>& holds) {
    const CaseDefinition c = parse(kMinimal + extra);
    EXPECT_TRUE(holds(c)) << extra;
    EXPECT_NE(describe_case(c).find(written), std::string::npos) << extra << describe_case(c);
  };
  check("  aft: sampled\n", "aft: sampled",
        [](const CaseDefinition& c) { return c.analysis.aft == AftChoice::kSampled; });
  check("  aft: event\n", "aft: event", [](const CaseDefinition& c) {
    return c.analysis.aft == AftChoice::kEvent && c.analysis.aft_given;
  });
  check("  aft: event_planar\n", "aft: event_planar",
        [](const CaseDefinition& c) { return c.analysis.aft == AftChoice::kEventPlanar; });
  check("  static: coupled\n", "static: coupled", [](const CaseDefinition& c) {
    return c.analysis.static_coupling == StaticChoice::kCoupled;
  });
  check("  initial_guess: free\n", "initial_guess: free", [](const CaseDefinition& c) {
    return c.analysis.initial_guess == InitialGuessChoice::kFree;
  });
  check("  method: continuation\n", "method: continuation",
        [](const CaseDefinition& c) { return c.analysis.method == SweepMethod::kContinuation; });
  check("recovery: {points: all, method: modal}\n", "points: all", [](const CaseDefinition& c) {
    return c.recovery.points == RecoveryPoints::kAll && c.recovery.method == RecoveryMethod::kModal;
  });
  check("recovery: {points: none, method: expansion}\n", "method: expansion",
        [](const CaseDefinition& c) {
          return c.recovery.points == RecoveryPoints::kNone &&
                 c.recovery.method == RecoveryMethod::kExpansion;
        });
  check("recovery: {fields: [stress]}\n", "fields: [stress]", [](const CaseDefinition& c) {
    return c.recovery.fields == std::vector<RecoveryField>{RecoveryField::kStress};
  });
  // Support directions: rows 0, 1, 2 named x, y, z, or t1, t2, n in a local frame.
  const std::string beam1 =
      "  beam1: {mesh: joint, element_set: BEAM1, material: steel, clamp: CLAMP1}\n";
  const CaseDefinition held = parse(
      edited(beam1,
             "  beam1: {mesh: joint, element_set: BEAM1, material: steel, supports: [{nodes: "
             "CLAMP1, directions: [z, x]}, {nodes: FORCE1, directions: n, normal: [0, 0, 1]}]}\n"));
  const std::vector<SupportDefinition>& s = held.bodies.at("beam1").supports;
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].directions, (std::vector<int>{2, 0}));
  EXPECT_EQ(s[1].directions, (std::vector<int>{2}));
  EXPECT_NE(describe_case(held).find("directions: [z, x]"), std::string::npos);
  EXPECT_NE(describe_case(held).find("directions: [n]"), std::string::npos);
  // Not given: the default, and no `aft` written (event without the fall-back warning).
  const CaseDefinition plain = parse(kMinimal);
  EXPECT_FALSE(plain.analysis.aft_given);
  EXPECT_EQ(describe_case(plain).find("aft:"), std::string::npos);
  EXPECT_STREQ(case_name(PreloadSplit::kArea), "area");
  EXPECT_STREQ(case_name(ReducedFileFormat::kAbaqusMatrix), "abaqus_matrix");
  EXPECT_STREQ(case_name(MeshFileFormat::kCdb), "cdb");
  EXPECT_STREQ(case_name(TwoBeamOptions::Arrangement::kLap), "lap");
}

TEST(CaseFile, PredictorIsAStepSweepChoice) {
  EXPECT_EQ(parse(kMinimal + "  predictor: previous\n").analysis.predictor,
            PredictorChoice::kPrevious);
  expect_invalid(kMinimal + "  predictor: tangent\n", 19, "analysis.predictor",
                 "must be one of secant | previous, got 'tangent'");
  expect_invalid(kMinimal + "  method: continuation\n  predictor: secant\n", 20,
                 "analysis.predictor", "not allowed with method continuation");
}

TEST(CaseFileErrors, NonConformingTwoBeamMesh) {
  expect_invalid(
      edited("joint: {generate: two_beam}", "joint: {generate: two_beam, box: [25, 5, 4]}"), 5,
      "meshes.joint.box", "box[2] (z) > end_block[2]");
}

TEST(CaseFileErrors, IntegerOutOfRange) {
  expect_invalid(edited("amplitude: 50}", "amplitude: 50, harmonic: 99999999999}"), 16,
                 "excitation[0].harmonic", "integer out of range");
}

TEST(CaseFileErrors, NamesCannotBreakDottedPaths) {
  expect_invalid(edited("  - name: joint", "  - name: a.b"), 10, "contacts.a.b.name",
                 "names may not contain '.'");
}

TEST(CaseFileErrors, NamesCannotLeaveTheOutputFolder) {
  // Body and contact names become folder and file names of the results (recovery/<body>/).
  expect_invalid(edited("  - name: joint", "  - name: ../etc"), 10, "contacts.../etc.name",
                 "names may not contain");
  expect_invalid(edited("  - name: joint", "  - name: /tmp/x"), 10, "contacts./tmp/x.name",
                 "names may not contain '.', '[', ']' or '/'");
}

TEST(CaseFileErrors, DeeplyNestedInputIsAnError) {
  // yaml-cpp's depth guard (or the type check) stops it; never a crash.
  const std::string deep = std::string(5000, '[') + std::string(5000, ']');
  EXPECT_THROW(parse(kMinimal + "title: " + deep + "\n"), InvalidInput);
}

TEST(CaseFileErrors, ItemsOfBlockListsAreReportedOnTheirOwnLine) {
  expect_invalid(edited("  frequency:", "  harmonics:\n    - 1\n    - 3\n    - x\n  frequency:"),
                 21, "analysis.harmonics", "expected an integer, got 'x'");
  expect_invalid(edited("    between: {beam1: CONTACT1, beam2: CONTACT2}\n",
                        "    bodies: [beam1, beam2]\n    pairs:\n      - [1, 2]\n      - [3]\n"),
                 15, "contacts.joint.pairs", "expected a pair of node ids");
}

TEST(CaseFileErrors, QuotedIntegerIsAString) {
  expect_invalid(edited("stickslip: 1\n", "stickslip: \"1\"\n"), 1, "stickslip",
                 "expected an integer, got the string \"1\"");
}

TEST(CaseFileErrors, StudyCannotAddAGapToAPreloadedContact) {
  expect_invalid(kMinimal + "study: {parameter: contacts.joint.gap, values: [1e-6]}\n", 19,
                 "study.parameter", "give either a preload or a gap");
}

// A malformed CSV file referenced by the case: its own file and line, the case key.
void expect_invalid_csv(const std::string& key_line, const std::string& csv, int line,
                        const std::string& key, const std::string& message) {
  std::string text = kMinimal;
  const std::string between = "    between: {beam1: CONTACT1, beam2: CONTACT2}\n";
  text.replace(text.find(between), between.size(), key_line);
  try {
    parse(text);
    ADD_FAILURE() << "no InvalidInput for " << csv;
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, kDir + "/bad/" + csv) << e.what();
    EXPECT_EQ(e.where().line, line) << e.what();
    EXPECT_EQ(e.where().key, key) << e.what();
    EXPECT_NE(e.message().find(message), std::string::npos) << e.what();
  }
}

TEST(CaseFileErrors, MalformedPairsFile) {
  const std::string bodies = "    bodies: [beam1, beam2]\n";
  expect_invalid_csv(bodies + "    pairs_file: bad/pairs_bad_id.csv\n", "pairs_bad_id.csv", 3,
                     "contacts.joint.pairs_file", "field 2: expected a positive node id, got 'x7'");
  expect_invalid_csv(bodies + "    pairs_file: bad/pairs_twice.csv\n", "pairs_twice.csv", 3,
                     "contacts.joint.pairs_file", "pair 1,101 listed twice");
}

TEST(CaseFileErrors, NegativePreloadInPreloadFile) {
  std::string text = edited("mu: 0.5, preload: 150}", "mu: 0.5}");
  text.replace(text.find("    normal:"), 0, "    preload_file: bad/preload_negative.csv\n");
  try {
    parse(text);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(e.where().file, kDir + "/bad/preload_negative.csv");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().key, "contacts.joint.preload_file");
    EXPECT_NE(e.message().find("the preload must be a number >= 0 (N), got '-3'"),
              std::string::npos)
        << e.what();
  }
}

TEST(CaseFileErrors, EmptyAndUnreadableFiles) {
  expect_invalid("", 0, "", "the case file is empty");
  expect_invalid("- 1\n- 2\n", 1, "(document)", "expected a map of keys");
  EXPECT_THROW(read_case_file(kDir + "/no_such_case.yaml"), InvalidInput);
}

// Seeded random edits of the reference case (characters inserted, deleted, replaced; lines deleted
// or repeated): every result either parses or throws InvalidInput with a location in the file,
// never another exception.
void random_edits(const std::string& dir, const std::string& file, unsigned seed) {
  std::ifstream in(dir + "/" + file);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string original = buffer.str();
  ASSERT_FALSE(original.empty());
  const std::string alphabet = ":{}[],-#'\"\n \t0123456789.eE+abxyz!&*|>~@";
  std::mt19937 rng(seed);
  constexpr int kEdits = 1500;  // about 0.7 s in a -O2 build
  int valid = 0, invalid = 0;
  for (int trial = 0; trial < kEdits; ++trial) {
    std::string text = original;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const size_t at = rng() % text.size();
      const char c = alphabet[rng() % alphabet.size()];
      switch (rng() % 5) {
        case 0:
          text.insert(at, 1, c);
          break;
        case 1:
          text.erase(at, 1);
          break;
        case 2:
          text[at] = c;
          break;
        case 3: {  // delete the line holding `at`
          const size_t begin = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at);
          const size_t end = text.find('\n', at + 1);
          text.erase(begin, end == std::string::npos ? std::string::npos : end - begin);
          break;
        }
        default: {  // repeat the line holding `at`
          const size_t begin = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at);
          const size_t end = text.find('\n', at + 1);
          if (end != std::string::npos) text.insert(end, text.substr(begin, end - begin));
          break;
        }
      }
    }
    try {
      parse_case(text, "case.yaml", dir);
      ++valid;
    } catch (const InvalidInput& e) {
      ++invalid;
      EXPECT_EQ(e.where().file, "case.yaml") << e.what();
      EXPECT_FALSE(e.message().empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not InvalidInput: " << e.what() << "\nfor:\n" << text;
    }
  }
  EXPECT_GT(invalid, kEdits / 4);  // most edits break something
  EXPECT_GT(valid, 0);             // and some (comments, spaces) do not
}

TEST(CaseFileErrors, RandomEditsGiveInvalidInputOrAValidCase) {
  random_edits(kDir, "reference.yaml", 20261121);
  random_edits(kDir + "/imported", "case.yaml", 6);
}

// ------------------------------------------------------------------------ docs/case-file.md ---

std::string read_docs() {
  const std::string path = std::string(STICKSLIP_TEST_DATA_DIR) + "/../../docs/case-file.md";
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(CaseFileDocs, TheAnnotatedExampleIsTheReferenceCase) {
  const std::string docs = read_docs();
  const size_t begin = docs.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const size_t end = docs.find("```\n", begin + 8);
  ASSERT_NE(end, std::string::npos);
  const CaseDefinition from_docs =
      parse_case(docs.substr(begin + 8, end - begin - 8), "case-file.md", kDir);
  EXPECT_EQ(describe_case(from_docs), describe_case(read_case_file(kDir + "/reference.yaml")));
}

// Every key the parser knows (as listed by its unknown-key message) is documented.
TEST(CaseFileDocs, EveryKnownKeyIsDocumented) {
  const std::string docs = read_docs();
  const std::string reduced =
      "  beam2: {reduced: {stiffness: imported/k.hb, mass: imported/m.hb, "
      "zzzz: 1}}\n";
  const std::vector<std::string> cases{
      kMinimal + "zzzz: 1\n",
      edited("density: 7800}", "density: 7800, zzzz: 1}"),
      edited("{generate: two_beam}", "{generate: two_beam, zzzz: 1}"),
      edited("clamp: CLAMP1}", "clamp: CLAMP1, zzzz: 1}"),
      edited("  beam2: {mesh: joint, element_set: BEAM2, material: steel, clamp: CLAMP2}\n",
             reduced),
      edited("    normal: [1, 0, 0]\n", "    normal: [1, 0, 0]\n    zzzz: 1\n"),
      edited("preload: 150}", "preload: 150, zzzz: 1}"),
      edited("per_pair: {kt: 4.467e9", "total: {zzzz: 1, kt: 4.467e9"),
      edited("amplitude: 50}", "amplitude: 50, zzzz: 1}"),
      kMinimal + "damping: {zzzz: 1}\n",
      edited("  frequency:", "  zzzz: 1\n  frequency:"),
      edited("step_hz: 0.01}", "step_hz: 0.01, zzzz: 1}"),
      kMinimal + "study: {zzzz: 1}\n",
      kMinimal + "recovery: {zzzz: 1}\n",
      kMinimal + "output: {zzzz: 1}\n",
      kMinimal + "output: {frf: [{zzzz: 1}]}\n",
  };
  int keys = 0;
  for (const std::string& text : cases) {
    try {
      parse(text);
      ADD_FAILURE() << "accepted:\n" << text;
    } catch (const InvalidInput& e) {
      const std::string marker = "known keys: ";
      const size_t at = e.message().find(marker);
      ASSERT_NE(at, std::string::npos) << e.what();
      std::stringstream list(e.message().substr(at + marker.size()));
      std::string key;
      while (std::getline(list, key, ',')) {
        if (!key.empty() && key[0] == ' ') key.erase(0, 1);
        EXPECT_NE(docs.find("`" + key + "`"), std::string::npos)
            << "'" << key << "' (" << e.where().key << ") is not in docs/case-file.md";
        ++keys;
      }
    }
  }
  EXPECT_GT(keys, 80);  // the sections above hold about a hundred keys
}

}  // namespace
}  // namespace stickslip

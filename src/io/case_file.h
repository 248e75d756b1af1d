// The YAML case file (docs/case-file.md is the reference of every key): parsed into PLAIN DATA.
//
// CaseDefinition says what the user asked for, in the file's own terms and units (SI; frequencies
// in Hz, fields named *_hz; phases in degrees): materials, meshes (generated or read), bodies
// (a mesh part, or reduced matrices plus a mapping), contacts, excitation, damping, analysis,
// an optional parameter study, recovery and output. Defaults are written once, in the structs
// below. Nothing here loads meshes or matrices: the `run` pipeline (src/cli) maps the definition
// onto the library and reports later problems (a node set missing from a mesh, ...) through
// CaseDefinition::where().
//
// Checked at parse time, each throwing InvalidInput{file, line, dotted key} with the rule:
// YAML syntax (yaml-cpp's line), unknown keys (with a suggestion when a known key is close),
// duplicate keys, wrong types (a quoted string or text where a number is expected, a scalar
// where a list or map is expected), missing required keys, value ranges (kt, kn, k > 0,
// E > 0, −1 < ν < 0.5, ρ > 0, μ ≥ 0, preload ≥ 0, gap ≥ 0, frequency range not empty and
// increasing, step > 0, time_samples ≥ 2(2H+1), ...), references (material, mesh, body, contact
// names), mutually exclusive keys (per_pair/total, preload/gap, node/node_set, ...), and the
// existence of every file the case references (relative paths resolved against the directory of
// the case file; the struct holds the resolved paths). The small CSV files (pairs_file,
// preload_file) are read and checked too; meshes and matrices are not loaded.
//
// Locations: `locations` maps the dotted path of every key read from the file to where it was
// read, e.g. "contacts.joint.per_pair.kt", "bodies.beam1.modes", "excitation[0].amplitude"
// (contacts by name, excitation by 0-based position). where(path) gives the location of the
// path or of its nearest recorded ancestor, so a default value reports the block it belongs to.
#pragma once

#include <array>
#include <complex>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "fe/element.h"
#include "io/two_beam_model.h"
#include "mesh/mesh.h"

namespace stickslip {

inline constexpr int kCaseFormatVersion = 1;  // the value of the required key `stickslip`
// Largest harmonic a case may ask for (analysis.harmonics). Far above any practical HBM order
// (the AFT then needs time_samples >= 2(2H+1) = 40002); it bounds what a typo or a corrupted
// file can make the parser allocate and keeps 2(2H+1) far from int overflow.
inline constexpr int kMaxHarmonic = 10000;
// Upper bounds of the other integer keys that size an allocation or a loop (docs/case-file.md,
// "Limits"); each is far beyond what an analysis needs and stops a typo (time_samples: 6400000,
// max_points: 1e9) at its line instead of in the allocator or after hours.
// analysis.time_samples <= min(kMaxTimeSamples, max(kTimeSamplesFloor, 64 (2 H_max + 1))).
inline constexpr int kTimeSamplesPerHarmonic = 64;
inline constexpr int kTimeSamplesFloor = 4096;
inline constexpr int kMaxTimeSamples = 65536;
// analysis.max_points, and the points of a stepped sweep (window / step_hz + 1).
inline constexpr int kMaxFrequencyPoints = 1000000;
// Load steps of the static contact problem at most (analysis.static_increments).
inline constexpr int kMaxStaticIncrements = 10000;
// recovery.modes (full-model modes of the modal recovery).
inline constexpr int kMaxRecoveryModes = 10000;
// Elements of one generated beam (box plus end block).
inline constexpr long long kMaxGeneratedElements = 1000000;
// Every number of a case file and of its preload_file is 0 or has a magnitude in [1e-30, 1e30].
// Far beyond any physical value in SI units (E = 2e11 Pa, kn = 5.6e9 N/m, k3 = 1e20 N/m³ are
// inside), and small enough that products and squares of a few of them (norms of the loads, the
// mass matrix's Cholesky factor, ω² M) stay finite doubles: a preload of 1e300 N had made the
// residual scale infinite, a density of 1e300 the mass matrix "not positive definite".
inline constexpr double kMaxNumberMagnitude = 1e30;
inline constexpr double kMinNumberMagnitude = 1e-30;
// Size of a case file, bytes. yaml-cpp builds the whole tree in memory, several times the size of
// the text (a 1 GB list took 5.8 GB); a large case (10⁴ listed pairs) is well under 1 MB, and long
// lists belong in pairs_file / preload_file (read line by line).
inline constexpr std::uintmax_t kMaxCaseFileBytes = std::uintmax_t{16} << 20;
// bodies.<name>.modes: at most kMaxReducedBodyDofs (io/ansys_mapping.h), the size of the largest
// reduced body.

// The case file's choices as types: each is spelled in the file as case_name() gives it, mapped
// from text once here (parse_case) and back once (describe_case); the rest of the program switches
// on the value.
enum class MeshFileFormat { kInp, kMsh, kCdb };                                 // meshes.M.format
enum class ReducedFileFormat { kHarwellBoeing, kMatrixMarket, kAbaqusMatrix };  // reduced.format
enum class PreloadSplit { kEqual, kArea };                              // contacts.C.total.split
enum class ContactCoupling { kAuto, kNodes, kMortar, kNodeToSurface };  // contacts.C.coupling
enum class UnpairedChoice { kError, kSkip };                            // contacts.C.unpaired
enum class SweepMethod { kStepped, kContinuation, kNonlinearMode };     // analysis.method
enum class AftChoice { kEvent, kSampled, kEventPlanar };                // analysis.aft
enum class StaticChoice { kUncoupled, kCoupled };                       // analysis.static
enum class InitialGuessChoice { kStuck, kFree };                        // analysis.initial_guess
enum class PredictorChoice { kSecant, kPrevious };                      // analysis.predictor
enum class RecoveryPoints { kPeak, kAll, kNone, kList };                // recovery.points
enum class RecoveryMethod { kDirect, kModal, kExpansion };              // recovery.method
enum class RecoveryField { kDisplacement, kStress };                    // recovery.fields
const char* case_name(MeshFileFormat v);
const char* case_name(ReducedFileFormat v);
const char* case_name(PreloadSplit v);
const char* case_name(ContactCoupling v);
const char* case_name(UnpairedChoice v);
const char* case_name(SweepMethod v);
const char* case_name(AftChoice v);
const char* case_name(StaticChoice v);
const char* case_name(InitialGuessChoice v);
const char* case_name(PredictorChoice v);
const char* case_name(RecoveryPoints v);
const char* case_name(RecoveryMethod v);
const char* case_name(RecoveryField v);
const char* case_name(TwoBeamOptions::Arrangement v);

struct MaterialDefinition {
  double youngs_modulus = 0.0;  // E, Pa (required, > 0)
  double poisson_ratio = 0.0;   // ν (required, −1 < ν < 0.5)
  double density = 0.0;         // ρ, kg/m³ (required, > 0)
};

// The reference two-beam model (io/two_beam_model.h, TwoBeamOptions), in the file's terms.
struct TwoBeamDefinition {
  TwoBeamOptions::Arrangement arrangement = TwoBeamOptions::Arrangement::kButt;  // butt | lap
  ElementType element = ElementType::kC3D8I;  // C3D8 | C3D8I | C3D20 | C3D20R (upper case)
  bool coarse = false;                        // thesis_coarse: 7x5x1 + 4x5x4, 240 nodes per beam
  std::array<int, 3> box{25, 5, 8};           // elements of the large box along x, y, z
  std::array<int, 3> end_block{5, 5, 4};      // elements of the end block along x, y, z
  // Beam 2's own box and end block (a contact face meshed unlike beam 1's); unset: box, end_block.
  std::optional<std::array<int, 3>> beam2_box, beam2_end_block;
  double beam_length = 0.25;  // L, m
  double width = 0.05;        // W, m
  double thickness = 0.03;    // T, m
  double end_length = 0.05;   // e, m
};

struct MeshDefinition {
  enum class Source { kGenerate, kFile };
  Source source = Source::kGenerate;
  std::string generate = "two_beam";  // kGenerate: the generator (only two_beam)
  TwoBeamDefinition two_beam;         // kGenerate
  std::string file;                   // kFile: resolved path of a .inp, .msh or .cdb file
  MeshFileFormat format = MeshFileFormat::kInp;    // kFile: inp | msh | cdb (from the extension
                                                   // unless given)
  ElementType hexahedron8 = ElementType::kC3D8I;   // msh: 8-node hexahedra (C3D8 | C3D8I)
  ElementType hexahedron20 = ElementType::kC3D20;  // msh: 20-node hexahedra (C3D20 | C3D20R)
};

// A node selection: node sets by name and/or external node ids, in the order given.
struct NodeSelection {
  std::vector<std::string> sets;
  std::vector<int> ids;
  bool empty() const { return sets.empty() && ids.empty(); }
};

// A support (bodies.B.supports[i]): the displacement of each node along each direction is zero.
// Directions are global axes x, y, z, or, with a local frame (`normal`, optional `t1` hint, the
// contact frames' rule: core/frame.h), its rows t1, t2, n.
// Or, with from_mesh, every *BOUNDARY line of the body's .inp mesh (Mesh::boundaries).
struct SupportDefinition {
  bool from_mesh = false;  // the mesh's *BOUNDARY lines (then nothing else)
  NodeSelection nodes;     // required
  // Required, none twice: 0, 1, 2 = x, y, z (global axes), or t1, t2, n (the rows of the local
  // frame: then named t1 | t2 | n in the file).
  std::vector<int> directions;
  bool local_frame = false;  // `normal` given
  std::array<double, 3> normal{0, 0, 0};
  std::array<double, 3> t1{0, 0, 0};  // 0 = automatic
};

struct ReducedMatricesDefinition {
  std::string stiffness;  // resolved path (required)
  std::string mass;       // resolved path (required)
  std::string mapping;    // resolved path; HB default: stiffness with .mapping
  ReducedFileFormat format = ReducedFileFormat::kHarwellBoeing;  // harwell_boeing |
                                                                 // matrix_market | abaqus_matrix
};

// bodies.B.cyclic: the body is one sector of N (fe/cyclic.h; docs/cyclic.md). Sector j + 1 is
// sector j rotated by 2π/N about the axis (right-handed about `axis_direction`); the `low`
// boundary's nodes rotated by 2π/N land on the `high` boundary's within `tolerance`.
struct CyclicDefinition {
  int sectors = 0;                                // N (required, 2 ≤ N ≤ kMaxCyclicSectors)
  std::array<double, 3> axis_point{0, 0, 0};      // m (required)
  std::array<double, 3> axis_direction{0, 0, 1};  // unit vector (required)
  NodeSelection low, high;                        // required
  double tolerance = 1.0e-6;                      // m, > 0: matching distance
};
// bodies.B.cyclic.sectors: one modal analysis per nodal diameter 0..N/2; 1000 is far above any
// bladed disk (tens to ~200 blades) and stops a typo before N/2 eigen-solves.
inline constexpr int kMaxCyclicSectors = 1000;

enum class ReductionSolver { kDirect, kPetsc };

struct BodyDefinition {
  enum class Source { kMesh, kReduced };
  Source source = Source::kMesh;
  // kMesh: a part of a mesh, reduced by Craig–Bampton.
  std::string mesh;         // name in CaseDefinition::meshes (required)
  std::string element_set;  // elements of the body; empty = the whole mesh
  std::string material;     // name in CaseDefinition::materials; empty: the mesh file's material
                            // of the body's elements (*SOLID SECTION / MPDATA)
  NodeSelection clamp;      // nodes fixed in x, y, z
  std::vector<SupportDefinition> supports;  // nodes held in some directions
  NodeSelection masters;  // boundary (master) nodes kept as physical DOFs by the reduction
  int modes = 60;         // fixed-interface modes kept (≥ 0)
  // Consistent-mass rule (fe/element.h): `exact` (kExact, default) or `calculix` (kStiffnessRule:
  // CalculiX's matrices; differs for C3D20R and C3D4 only).
  MassIntegration mass_rule = MassIntegration::kExact;
  // Who reduces it (docs/distributed-reduction.md): kDirect, CHOLMOD and Lanczos in this process
  // (reduction/craig_bampton.h), or kPetsc, PETSc and SLEPc, over the processes of mpirun when
  // they reduce together (model/petsc_reduction.h). Not with cyclic.
  ReductionSolver reduction_solver = ReductionSolver::kDirect;
  // Both sources: ζ added on every fixed-interface (modal) DOF, in [0, 1).
  double modal_damping_ratio = 0.0;
  ReducedMatricesDefinition reduced;       // kReduced
  std::optional<CyclicDefinition> cyclic;  // kMesh: one sector of a cyclic structure
};

// Contact parameters; which apply depends on the law (docs/case-file.md; the laws and their keys:
// contact/contact_law.h). Per pair, or totals over all pairs of the contact (kt, kn, k, k1, k3,
// preload split; mu, gap not).
struct ContactParametersDefinition {
  double kt = 0.0;                      // tangential stiffness, N/m (friction, jenkins, 3D linear)
  double kn = 0.0;                      // normal stiffness, N/m (friction, gap, 3D linear)
  double mu = 0.0;                      // friction coefficient (friction, jenkins)
  double preload = 0.0;                 // N0, N, compression positive (friction, jenkins, gap)
  double k = 0.0;                       // stiffness, N/m (1D linear)
  double k1 = 0.0;                      // linear part, N/m (cubic)
  double k3 = 0.0;                      // cubic coefficient, N/m³ (cubic)
  std::map<std::string, double> other;  // keys of registered laws that have no field above
  // The field of a parameter key (kt, ..., or a registered law's key in `other`).
  double* field(const std::string& key);
  double value(const std::string& key) const;  // 0 for a key not given
};

struct ContactDefinition {
  std::string name;  // unique (required)
  std::string law;   // a registered law (contact/contact_law.h): friction | jenkins | gap |
                     // cubic | linear, or one registered by the program (required)
  // The two bodies, A then B (B may be "ground" for a node-to-ground element).
  std::string body_a, body_b;
  // Pairs found by coincidence between two node selections (`between`) ...
  NodeSelection nodes_a, nodes_b;
  double tolerance = 1.0e-6;  // m: coincidence distance
  // ... or listed: (node id on A, node id on B; 0 for ground), from `pairs` or read from
  // `pairs_file` at parse time (locations "contacts.C.pairs[i]" then point into that file).
  std::vector<std::array<int, 2>> pairs;
  std::string pairs_file;  // resolved path (read_pairs_csv format)
  // Frame: unit normal out of A into B (friction); optional first tangent hint (0 = none).
  // 1D laws act along `direction` instead.
  std::array<double, 3> normal{0, 0, 0};
  std::array<double, 3> t1{0, 0, 0};
  std::array<double, 3> direction{0, 0, 0};
  // The law's variant (contact_law(law, uses_frame)): true = it acts on the rows (t1, t2, n) of
  // the frame `normal`/`t1` (friction; law linear's springs kt, kt, kn), false = along
  // `direction` (1D). A law registered both ways (linear) is chosen by the keys given.
  bool uses_frame = false;
  // `between` pairs: `nodes` (coincident nodes, within `tolerance`) or `mortar` (the nodes of the
  // two selections are surfaces: one contact point per node of A's faces, tied to B's nodes by
  // the mortar weights of mesh/mortar.h); `auto`: nodes when the two selections coincide node for
  // node (each node of either one exactly one partner in the other), else mortar.
  ContactCoupling coupling = ContactCoupling::kAuto;
  double search_distance = 0.0;  // m, mortar: how far B may lie from A's faces (0: automatic)
  UnpairedChoice unpaired =
      UnpairedChoice::kError;  // mortar: points not wholly over B: error | skip
  // per_pair: each pair's values; total: split over the pairs (`split`); per_area: the law's
  // split keys per unit area (kt, kn in N/m³, preload in Pa) times each pair's area.
  enum class Parameters { kPerPair, kTotal, kPerArea };
  Parameters parameters_given = Parameters::kPerPair;
  ContactParametersDefinition parameters;
  PreloadSplit split = PreloadSplit::kEqual;  // total: equal | area
  std::string preload_file;  // resolved path (read_preloads_csv format), read at parse time:
  std::vector<std::pair<int, double>>
      preloads;      // (node id on A, N0 in N), "contacts.C.preloads[i]"
  double gap = 0.0;  // g0, m (≥ 0): initial gap instead of a preload
  // `preload: computed` (friction and gap laws): no typed N0 (parameters.preload = 0, and no
  // balancing load); the pairs' static state comes from the static contact problem under
  // `static_loads` (docs/case-file.md, "static_loads").
  bool preload_computed = false;
  // `neighbour: next | previous` (a cyclic body, listed pairs with body_a == body_b): node B of
  // each pair is the given node of the next (+1) or previous (−1) sector; 0: an ordinary contact.
  int neighbour = 0;
};

struct ExcitationDefinition {
  std::string body;     // required
  NodeSelection nodes;  // node_set or node(s): the force acts on EACH node
  int harmonic = 1;     // k ≥ 0 (0 = static force); 0 or an analysis harmonic
  // Given as direction + amplitude (+ phase_deg, or complex), or as a force vector:
  bool by_direction = true;
  std::array<double, 3> direction{0, 0, 0};  // unit vector (by_direction)
  double amplitude = 0.0;                    // N (by_direction; the modulus when `complex`)
  double phase_deg = 0.0;                    // degrees (by_direction)
  // Complex amplitude of the force vector on each node, N: f(t) = Re(F e^{ikΩt}), so
  // amplitude A and phase φ give A cos(kΩt + φ) along the direction (docs/conventions.md
  // convention).
  std::array<std::complex<double>, 3> force{};
  // `engine_order` (a cyclic body only, required there): EO ≥ 0, sector j loaded with this force
  // rotated to it and times e^{+ik EO 2πj/N} (docs/cyclic.md); −1 = not given.
  int engine_order = -1;
};

// A static (harmonic-0) load on a body given by a mesh, applied to the full body and to its reduced
// model (the loaded nodes become master nodes, so harmonic 0 is exact: Craig–Bampton's static
// constraint modes). Exactly one of the three kinds:
//   kForce:      `force` on EACH selected node (N, global axes);
//   kTotalForce: `force` is the total, split over the selected nodes in proportion to their
//                consistent nodal areas ∫ N_i dA on the faces of the selection (a uniform traction
//                over that surface; mesh/surface_area.h);
//   kPressure:   `pressure` p (Pa, > 0 pushes into the body) on the faces of the selection, each
//                node receiving −p ∫ N_i n dA, n the face's outward normal.
struct StaticLoadDefinition {
  enum class Kind { kForce, kTotalForce, kPressure };
  std::string body;     // required; a body given by a mesh
  NodeSelection nodes;  // node_set or node(s)
  Kind kind = Kind::kForce;
  std::array<double, 3> force{0, 0, 0};  // N (kForce, kTotalForce)
  double pressure = 0.0;                 // Pa (kPressure)
};

// `rotation`: the whole structure spins at speed_rpm about the axis (fe/rotation.h,
// docs/rotation.md): the centrifugal load on every mesh body (a static, harmonic-0 load) and, by
// the two flags, the stress stiffening of its prestress and the spin softening in every body's
// stiffness. `campbell` asks `stickslip modes` for the Campbell diagram over speeds_rpm.
struct RotationDefinition {
  double speed_rpm = 0.0;   // ≥ 0 (required)
  bool axis_given = false;  // false: the cyclic body's axis (a case without one must give it)
  std::array<double, 3> axis_point{0, 0, 0};      // m
  std::array<double, 3> axis_direction{0, 0, 1};  // unit vector
  bool stress_stiffening = true;
  bool spin_softening = true;
  std::vector<double> campbell_speeds_rpm;  // increasing, ≥ 0; empty: no Campbell diagram
  std::vector<int> engine_orders;           // ≥ 1: the lines drawn on the diagram
};

struct DampingDefinition {
  double alpha = 0.0;  // s⁻¹, C = α M + β K
  double beta = 0.0;   // s
};

struct FrequencyDefinition {
  enum class Kind { kRange, kAroundMode };
  Kind kind = Kind::kRange;
  double start_hz = 0.0, stop_hz = 0.0;  // kRange: start < stop
  int around_mode = 0;                   // kAroundMode: 1-based mode of the stuck assembly
  double half_width_hz = 0.0;            // kAroundMode: window ± half_width_hz (> 0)
  double step_hz = 0.0;                  // stepped: the step; continuation: the initial step
  double min_step_hz = 0.0;              // continuation; 0 = automatic
  double max_step_hz = 0.0;              // continuation; 0 = automatic
  bool downward = false;                 // `sweep: down`: from the high end to the low end
};

// analysis.amplitude (method nonlinear_mode): modal amplitudes a (√kg·m, the mode's coordinate
// with the mode mass-normalised), `points` of them evenly spaced in ln a from start to stop.
struct AmplitudeDefinition {
  double start = 0.0, stop = 0.0;  // 0 < start < stop
  int points = 50;                 // >= 2
};

struct AnalysisDefinition {
  FrequencyDefinition frequency;               // required, except with nonlinear_mode
  SweepMethod method = SweepMethod::kStepped;  // stepped | continuation | nonlinear_mode
  int mode = 0;                                // nonlinear_mode: 1-based mode of the stuck assembly
  AmplitudeDefinition amplitude;               // nonlinear_mode
  // stepped/continuation with analysis.nonlinear_mode {mode, amplitude} (in `mode` and
  // `amplitude` above): the nonlinear mode is computed too and the forced response predicted
  // from it (single nonlinear mode theory, hbm/nonlinear_mode.h predict_forced_response).
  bool predict_from_mode = false;
  std::vector<int> harmonics{1};      // the dynamic harmonics (≥ 1, increasing); `harmonics: H`
                                      // gives 1..H. Harmonic 0 is always kept (static part).
  int time_samples = 64;              // N per period, ≥ 2(2 H_max + 1)
  AftChoice aft = AftChoice::kEvent;  // event | sampled | event_planar (hbm/aft.h AftMethod)
  bool aft_given = false;  // `aft` written in the file (then event warns where it falls back)
  StaticChoice static_coupling = StaticChoice::kUncoupled;  // key `static`: uncoupled | coupled
  int static_increments = 0;  // load steps of the static problem (≥ 1); 0: automatic
  double tolerance = 1.0e-8;  // Newton, relative residual (> 0)
  int max_iterations = 30;    // Newton iterations per point (≥ 1)
  int max_points = 10000;     // continuation: points at most (≥ 2)
  InitialGuessChoice initial_guess = InitialGuessChoice::kStuck;  // stuck | free
  PredictorChoice predictor = PredictorChoice::kSecant;  // stepped: secant | previous (guess
                                                         // per point)
  bool stability = false;  // Hill's method on every converged point (hbm/hill_stability.h)
  int max_harmonic() const { return harmonics.empty() ? 0 : harmonics.back(); }
};

struct StudyDefinition {
  std::string parameter;       // dotted path of a numeric key, e.g. contacts.joint.per_pair.preload
  std::vector<double> values;  // one analysis per value (empty: no study)
  bool active() const { return !parameter.empty(); }
};

struct RecoveryDefinition {
  RecoveryPoints points = RecoveryPoints::kPeak;    // peak | all | none | list (frequencies_hz)
  std::vector<double> frequencies_hz;               // points: list
  RecoveryMethod method = RecoveryMethod::kDirect;  // direct | modal | expansion
  int modes = 100;                                  // modal: full-model modes (≥ 1)
  std::vector<RecoveryField> fields{RecoveryField::kDisplacement, RecoveryField::kStress};
  std::vector<int> nodes;  // node ids whose recovered response is written
  bool annulus = false;    // a cyclic sector: also the whole annulus (VTU)
};

struct ResponseDofDefinition {
  std::string body;
  int node = 0;       // external id
  int direction = 0;  // 0 = x, 1 = y, 2 = z
};

struct OutputDefinition {
  std::string directory = "results";  // resolved against the case file's directory
  bool vtu = true;
  bool plots = true;
  bool log_amplitude = false;  // amplitude (FRF) plots on a logarithmic axis
  bool apdl_macro = false;     // contact forces as an ANSYS APDL macro
  bool calculix_deck = false;  // contact forces in a CalculiX *STEADY STATE DYNAMICS deck
  std::map<std::string, std::vector<int>> histories;  // contact -> 0-based pair indices
  std::vector<ResponseDofDefinition> frf;             // DOFs whose FRF is plotted
  bool quiet = false;
};

struct CaseDefinition {
  std::string file;      // name used in messages
  std::string base_dir;  // directory relative paths were resolved against
  int version = kCaseFormatVersion;
  std::string title;
  std::map<std::string, MaterialDefinition> materials;
  std::map<std::string, MeshDefinition> meshes;
  std::map<std::string, BodyDefinition> bodies;
  std::vector<ContactDefinition> contacts;  // in file order
  std::vector<ExcitationDefinition> excitation;
  std::vector<StaticLoadDefinition> static_loads;  // "static_loads[i]"
  std::optional<RotationDefinition> rotation;      // "rotation"
  DampingDefinition damping;
  AnalysisDefinition analysis;
  StudyDefinition study;
  RecoveryDefinition recovery;
  OutputDefinition output;

  std::map<std::string, SourceLocation> locations;  // dotted path -> where it was read
  // Location of `path` or its nearest recorded ancestor (key = path); file only if none.
  SourceLocation where(const std::string& path) const;
};

// Reads and checks a case file (relative paths resolved against its directory).
CaseDefinition read_case_file(const std::string& path);
// Same, from text: name_for_messages names it in errors, base_dir resolves relative paths.
CaseDefinition parse_case(const std::string& yaml_text, const std::string& name_for_messages,
                          const std::string& base_dir);

// Small CSV files a case may reference. One record per line; fields separated by commas,
// semicolons or blanks; blank lines and lines starting with '#' are ignored; a first record that
// is not numeric is a header and skipped. Errors name the file and line.
//   pairs file:   node_a,node_b   (positive node ids; with allow_ground, node_b may be omitted
//                                  or 0 for a node-to-ground element). No pair twice.
//   preload file: node_a,preload  (node id of the pair's A node, N0 ≥ 0 in N). No node twice.
// `lines` (optional) receives the line of each record.
std::vector<std::array<int, 2>> read_pairs_csv(const std::string& path, bool allow_ground,
                                               std::vector<int>* lines = nullptr);
std::vector<std::pair<int, double>> read_preloads_csv(const std::string& path,
                                                      std::vector<int>* lines = nullptr);

// Returns `definition` with the numeric key at dotted `path` set to `value` (the study
// mechanism): materials.M.{youngs_modulus,poisson_ratio,density},
// contacts.C.{per_pair|total}.{kt,kn,mu,preload,k,k1,k3}, contacts.C.gap, damping.{alpha,beta},
// bodies.B.modal_damping_ratio, excitation[i].amplitude (scales the force to that magnitude),
// static_loads[i].{force,total_force} (the vector scaled to that magnitude, N ≥ 0; the key the
// entry gives), static_loads[i].pressure (≠ 0) and rotation.speed_rpm (≥ 0).
// Throws InvalidInput (at `where`) for an unknown path or a value that breaks the key's rule.
CaseDefinition with_parameter(const CaseDefinition& definition, const std::string& path,
                              double value, const SourceLocation& where = {});

// The folder of one study value under the output folder: the parameter's last key and the value
// with 6 significant digits ("preload_150", "youngs_modulus_2e+11"). The parser refuses a study
// whose values do not all have folders of their own.
std::string study_folder_name(const std::string& parameter, double value);

// The definition as canonical YAML with every default filled in (for summary.json and logs). It
// is a case file that read_case_file accepts and that describes itself with the same text
// (relative file paths in it are read against the folder of the file it is saved in: see
// with_absolute_paths).
std::string describe_case(const CaseDefinition& definition);
// The definition with its file paths (meshes, matrices, mappings, pairs and preload files, the
// output folder) made absolute against the current working directory and normalised.
CaseDefinition with_absolute_paths(const CaseDefinition& definition);

}  // namespace stickslip

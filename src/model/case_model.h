// The model of a case: a CaseDefinition (io/case_file.h; read from YAML, or built in C++) mapped
// onto the library. The `run` pipeline and every stage command build their model here.
//
//   meshes -> bodies (sub-mesh of an element set, K and M, clamps) -> Craig–Bampton onto the
//   master nodes (contact, forced, listed and FRF nodes) -> one block-diagonal reduced linear
//   model (all its modes, damping C = αM + βK) -> contact pairs and excitation on the reduced
//   DOFs -> HarmonicBalanceSystem -> frequency response.
//
// Bodies given as reduced matrices (Harwell–Boeing or Matrix Market, + an ANSYS mapping) skip the
// mesh and reduction steps; their master nodes are the physical DOFs of the mapping, named by
// external node number.
//
// Damping: C_r = αM_r + βK_r per body, plus 2ζω_j M_r(j,j) on each fixed-interface (modal) DOF j
// of a body with modal_damping_ratio ζ > 0 (reduced_body.h, reduced_damping). Without ζ the
// assembled model keeps the diagonal modal damping c_r = α + βω_r²; with it the full modal damping
// matrix ΦᵀCΦ of the assembly is passed to the harmonic balance (non-proportional damping).
//
// Contact laws: those of the registry (contact/contact_law.h: friction, jenkins, gap, cubic,
// linear, and any the program registers), each pair's element made by its law's factory; every
// element enters the harmonic balance alike and its force is reported and recovered like a
// contact force.
// Totals (`total:`) are split over the pairs equally or, with split: area, in proportion to the
// tributary area of each pair's A node on the A body's contact face (mesh/surface_area.h: faces
// of the A body whose nodes are all A nodes of the contact; automatic rule); the B body's face is
// used when A is given by matrices. `per_area` values are multiplied by the same areas.
// Contacts with `coupling: mortar` (mesh/mortar.h): one pair per node of A's surface, tied to the
// B nodes of its mortar weights (PreparedPair below); their area is the point's ∫ N_i dA.
// Problems of the case that only show once meshes are loaded (a set missing from a mesh, contact
// nodes not coincident, a master node that is clamped) throw InvalidInput at the case-file line
// of the key that asked for them.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "contact/nonlinear_element.h"
#include "continuation/sweep.h"
#include "core/types.h"
#include "fe/cyclic.h"
#include "fe/dof_map.h"
#include "fe/material.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "hbm/nonlinear_mode.h"
#include "io/case_file.h"
#include "linalg/modal.h"
#include "mesh/mesh.h"
#include "mesh/mortar.h"
#include "reduction/reduced_body.h"

namespace stickslip {

using ProgressFn = std::function<void(const std::string&)>;

// Warnings of model building (a mesh file's lines that are not used, a material of the mesh
// file that the case's replaces): "stickslip: warning: <text>" on stderr unless a sink is set
// (a program's own channel, a test that collects them). Empty: back to stderr.
using WarningFn = std::function<void(const std::string&)>;
void set_model_warning_sink(WarningFn sink);
void model_warning(const std::string& text);

// The bodies of a case resolved on their meshes, before any reduction: the meshes loaded
// (generated or read; `progress`, may be null, gets "mesh <name>" for each) and cut to each body's
// element set, node selections turned into node indices (mesh bodies) or node ids (bodies given by
// matrices, whose files are not read here), contact pairs matched, and the master nodes of each
// body (contact, forced, listed and FRF nodes). Selection problems throw InvalidInput at the
// case-file line of their key.
struct CaseBody {
  std::string name;
  bool from_mesh = false;
  Mesh mesh;                   // from_mesh: the body's part of its mesh, with its sets
  IsotropicMaterial material;  // from_mesh
  std::vector<int> clamp;      // from_mesh: clamped node indices
  std::vector<NodeSupport> supports;  // from_mesh: bodies.B.supports, per node (global axes)
  std::vector<int> masters;    // sorted node indices (mesh) or ids (matrices)
  // The dotted case key that first asked for each master (a contact pair, an excitation entry,
  // bodies.B.masters, an output.frf entry), for messages about that node.
  std::map<int, std::string> master_keys;
  // bodies.B.cyclic (from_mesh): the sector's symmetry and its boundary, each low node with the
  // high node it reaches rotated by 2π/N (node indices; match_cyclic_boundaries).
  std::optional<CyclicSymmetry> cyclic;
  std::vector<std::pair<int, int>> cyclic_pairs;
  int node_id(int node) const { return from_mesh ? mesh.node_ids[node] : node; }
};
// The constraints of a mesh body on `mesh` (its mesh, which may have been moved out of `body`):
// its clamp, supports and the mesh's equations (DofMap).
DofMap body_constraints(const CaseBody& body, const Mesh& mesh);

struct CaseContact {
  int body_a = 0;                               // index in CaseBodies::bodies
  int body_b = -1;                              // -1 = ground
  std::vector<std::pair<int, int>> node_pairs;  // node indices (ids for matrices); -1 = ground
  // coupling: mortar: one point per pair (node_pairs[i] = (its A node, its B node of largest
  // weight)); its B nodes (all masters) and weights, area and gap (mesh/mortar.h). Empty for
  // node-to-node contacts.
  std::vector<MortarPoint> mortar;
  std::vector<int> mortar_faces_b;  // element index of each face of B's surface (faces_b order)
  std::vector<int> skipped;         // unpaired: skip: A nodes left out (node indices)
};
struct CaseBodies {
  std::vector<CaseBody> bodies;                    // CaseDefinition::bodies order
  std::vector<CaseContact> contacts;               // CaseDefinition::contacts order
  std::vector<std::vector<int>> excitation_nodes;  // per excitation entry: as CaseBody::masters
  // Per static_loads entry: its nodes (indices in the body's mesh; each once for total_force and
  // pressure), all master nodes of the body.
  std::vector<std::vector<int>> static_load_nodes;
};
struct ModelCache;
// `cache` (may be null): meshes whose fingerprint (mesh_fingerprint) is in it are not loaded again;
// those loaded are stored in it.
CaseBodies resolve_case_bodies(const CaseDefinition& definition, const ProgressFn& progress,
                               ModelCache* cache = nullptr);

// The fingerprint of what loading mesh `name` depends on: its definition (generated: every
// generator option; file: path, format, element types and the file's bytes).
std::string mesh_fingerprint(const CaseDefinition& definition, const std::string& name);

// Per body of `bodies` (resolve_case_bodies(definition, ...)): the fingerprint of what its
// Craig–Bampton reduction depends on (mesh, element set, material, clamps, master nodes, modes);
// empty for bodies given by matrices. Damping, contact laws and their parameters, excitation
// amplitudes and the analysis do not enter: two analyses whose bodies have the same fingerprints
// share one reduction (`run` and `reduce` with a study, ModelCache).
std::vector<std::string> reduction_fingerprints(const CaseDefinition& definition,
                                                const CaseBodies& bodies);

struct PreparedBody {
  std::string name;
  bool from_mesh = false;
  Mesh mesh;                   // the body's own mesh (from_mesh)
  IsotropicMaterial material;  // from_mesh
  DofMap constraints;          // clamped DOFs of `mesh` (from_mesh)
  // Full stiffness and mass of `mesh` (from_mesh; null when the body's reduction did not provide
  // them, e.g. StoredReduction without full matrices). Shared, never copied: the model cache and
  // every analysis of a study that uses the same reduction hold the same matrices.
  std::shared_ptr<const SparseMatrix> K, M;
  ReducedBody reduced;         // K_r, M_r and what each reduced DOF is
  // Expansion basis, full DOFs x reduced (from_mesh; null when not made or not read). Shared.
  std::shared_ptr<const Eigen::MatrixXd> T;
  // A cyclic sector under engine-order excitation (model/cyclic_forced_response.h): its symmetry
  // and boundary pairs (CaseBody::cyclic, cyclic_pairs), for the recovery.
  std::optional<CyclicSymmetry> cyclic;
  std::vector<std::pair<int, int>> cyclic_pairs;
  int offset = 0;              // first DOF of this body in the assembled reduced model
  // (external node id, direction) -> DOF of the assembled reduced model.
  std::map<std::pair<int, int>, int> master_dof;
  double seconds_reduction = 0.0;
  int global_dof(int node_id, int direction) const;  // -1 if not a master DOF
};

// What the analyses of one study share (`run`, `reduce`, `solve`, `recover`, `export`): the last
// mesh loaded under each mesh name and the last reduction of each mesh body, with the fingerprints
// they were made for (mesh_fingerprint, reduction_fingerprints). An analysis finds them here when
// its fingerprints are the same (a studied contact, damping, excitation or analysis parameter) and
// makes them again, replacing them, when they are not (a studied material re-reduces the bodies
// made of it, and only those). One entry per name bounds the memory to one copy of each body; the
// large matrices are shared with the models built from them (shared_ptr), never copied.
struct ModelCache {
  std::map<std::string, std::pair<std::string, Mesh>> meshes;  // name -> (fingerprint, mesh)
  // Per mesh body name, for the reduction fingerprint it was made for: what a reduction made
  // (CraigBamptonReduction: all of it; the stage commands' StoredReduction, which reads reduce's
  // files: the full K and M and the basis T, once a stage asked for them — reduced files with
  // the same fingerprint hold the same reduction, so T is read once).
  struct Body {
    std::string fingerprint;
    bool reduced_here = false;  // constraints, reduced, K, M, T and seconds of a Craig–Bampton run
    DofMap constraints;
    ReducedBody reduced;
    std::shared_ptr<const SparseMatrix> K, M;  // null until made
    std::shared_ptr<const Eigen::MatrixXd> T;  // null until made or read
  };
  std::map<std::string, Body> bodies;
  // The cache entry of `name` for `fingerprint`: emptied first when it held another fingerprint.
  Body& body(const std::string& name, const std::string& fingerprint);
};

// A contact point. Node-to-node: ContactPair dofs_a = node A's DOFs, dofs_b = node B's, frame R
// (m x 3). Mortar (coupling: mortar): dofs_a = node A's DOFs, then (quadratic faces) those of the
// point's other A nodes, then those of each partner node of B; dofs_b empty; frame
// R [a_1 I, a_2 I, ..., −Φ_1 I, −Φ_2 I, ...] (a_1 node A's weight, 1 on linear faces), so that
// u = R (Σ_j a_j x_Aj − Σ_k Φ_k x_Bk), R the point's own frame (its surface normal; 1D laws: the
// contact's direction): the first three columns are a_1 R, and the first three rows of
// PairResponse::force_global divided by weight_a are the point's force on B (global axes), which
// reaches B's nodes as Φ_k times it and A's as −a_j times it.
struct PreparedPair {
  int contact = 0;    // index in CaseDefinition::contacts
  int node_a_id = 0;  // external ids (0 = ground)
  int node_b_id = 0;  // mortar: the partner node of largest weight
  double share = 1.0;  // fraction of the contact's totals this pair carries (1 with per_pair)
  // Tributary area of the node the share came from, m² (split: area and per_area), or the
  // mortar point's area ∫ N_i dA over A's surface (always).
  double area = 0.0;
  bool mortar = false;
  double weight_a = 1.0;          // mortar: a_1, node A's weight in the point (1: linear faces)
  std::vector<int> partner_ids;   // mortar: B's node ids, increasing
  std::vector<double> weights;    // mortar: Φ_k of each partner
  std::vector<int> partner_elements;  // mortar: element ids of the B faces it overlaps
  // mortar: the point's A nodes (ids, node A first) and their weights a_j: node A with 1 on
  // linear faces; on quadratic faces a mid-edge node's point also has its edge's corners.
  std::vector<int> point_ids_a;
  std::vector<double> point_weights_a;
  double gap = 0.0;  // mortar: the point's geometric gap, m (> 0 open; the law's initial gap
                     // with the contact's `gap` unless a preload is typed)
  ContactParametersDefinition parameters;  // this pair's parameters (totals already split)
  Eigen::VectorXd stuck_stiffness;         // stiffness of its local rows when stuck, N/m
};

struct PreparedModel {
  std::vector<PreparedBody> bodies;
  int num_dofs = 0;         // assembled reduced DOFs
  LinearModel linear;       // all modes of the assembled reduced model
  Eigen::MatrixXd K, M, C;  // assembled reduced matrices (block diagonal); C = the damping
  std::vector<ContactPair> pairs;
  std::vector<PreparedPair> pair_info;
  Excitation excitation;
  HarmonicBalanceOptions hbm;
  // A cyclic sector under engine-order excitation (model/cyclic_forced_response.h): the linear
  // model of each dynamic harmonic; `linear` is then diameter 0's. Empty otherwise.
  std::optional<TravellingWave> wave;
  double seconds_prepare = 0.0;
  int body_index(const std::string& name) const;  // -1 if absent
};

class BodyReduction;  // model/body_reduction.h

// Cyclic sectors (bodies.B.cyclic): the forced response under engine-order excitation is
// model/cyclic_forced_response.h (prepare_model reduces the sector per nodal diameter and sets
// PreparedModel::wave); the modes per nodal diameter are model/cyclic_modes.h.

// Builds the reduced model of the case. `progress` (may be null) receives one line per stage.
// `cache` (may be null): meshes and reductions of earlier analyses of the same study, reused when
// their fingerprints match and stored otherwise (ModelCache); a reused body has
// seconds_reduction 0. Everything else (the assembled reduced model and its modes, damping,
// contact pairs, preload loads, excitation, options) is built from `definition` every time.
// Bodies are reduced by Craig–Bampton (mesh bodies) or read (bodies given by matrices):
// CraigBamptonReduction.
PreparedModel prepare_model(const CaseDefinition& definition, const ProgressFn& progress,
                            ModelCache* cache = nullptr);
// The same from bodies already resolved by resolve_case_bodies(definition, ...) (consumed), each
// body given its reduced model by `reduction` (model/body_reduction.h).
PreparedModel prepare_model(const CaseDefinition& definition, CaseBodies resolved,
                            const BodyReduction& reduction, const ProgressFn& progress);

// Stiffness of the assembled reduced model with every contact stuck: model.K plus, per pair,
// BᵀkB with B its relative-displacement rows and k its stuck stiffness (friction pairs as springs
// (kt, kt, kn) in their frame, 1D laws by their tangent at rest: PreparedPair::stuck_stiffness).
Eigen::MatrixXd stuck_stiffness_matrix(const PreparedModel& model);

// The nodal forces (N, global axes) of one static_loads entry on `nodes` (indices in `mesh`, as
// CaseBodies::static_load_nodes): `force` on each node; `total_force` split in proportion to the
// consistent nodal areas ∫ N_i dA of the nodes' faces (a uniform traction); `pressure` through
// pressure_nodal_forces (mesh/surface_area.h). InvalidInput (without a location) when the nodes
// hold no face for total_force or pressure.
std::vector<Eigen::Vector3d> static_load_forces(const Mesh& mesh, const std::vector<int>& nodes,
                                                const StaticLoadDefinition& load);

// Modes of the assembled reduced model with every contact stuck (stuck_stiffness_matrix and
// model.M, dense_modes: eigenvalues ω² ascending, modes M-normalised); InvalidInput at `bodies`
// when the reduced mass matrix is not positive definite. `stiffness` (optional) receives the
// stuck stiffness matrix the modes were computed from.
ModalResult stuck_modes(const PreparedModel& model, const CaseDefinition& definition,
                        Eigen::MatrixXd* stiffness = nullptr);
// Their natural frequencies, Hz (ascending; negative round-off of ω² as 0).
Eigen::VectorXd stuck_frequencies_hz(const PreparedModel& model, const CaseDefinition& definition);

// The frequency window of the analysis, Hz: as given (start_hz/stop_hz), or around_mode's stuck
// mode ± half_width_hz (stuck_frequencies_hz).
struct SweepWindow {
  double start_hz = 0.0, stop_hz = 0.0;
  int stuck_mode = 0;          // around_mode (1-based); 0 when the window was given in Hz
  double stuck_mode_hz = 0.0;  // that mode's frequency
};
// The analysis frequencies (Hz) of a stepped sweep, or [start, stop] for continuation; `window`
// (may be null) receives the window they cover.
std::vector<double> analysis_frequencies_hz(const PreparedModel& model,
                                            const CaseDefinition& definition,
                                            SweepWindow* window = nullptr);

// "sweep window 185.2 to 189.2 Hz around stuck mode 4 at 187.2 Hz (all contacts stuck)", for
// the log.
std::string describe_window(const SweepWindow& window);
struct SolvedCase {
  std::unique_ptr<HarmonicBalanceSystem> system;
  FrequencyResponse response;
  std::vector<double> frequencies_hz;  // the requested grid (stepped) or range (continuation)
  SweepWindow window;
  double seconds_solve = 0.0;
  bool warn_aft_fallback = false;  // `analysis.aft: event` given: warn where it fell back
  // analysis.nonlinear_mode (model/nonlinear_mode_case.h): the nonlinear mode, solved without the
  // dynamic excitation, and the forced response predicted from it (hbm/nonlinear_mode.h
  // predict_forced_response); empty otherwise. seconds_solve includes the mode's time.
  NonlinearModeResult mode;
  std::vector<ForcedResponsePrediction> prediction;
  double seconds_mode = 0.0;
};

// What the sweep reports as it goes (each may be empty): start(label, points) once (points: the
// number of a stepped sweep, 0 for continuation), on_point after every frequency point (the
// sweep's / continuation's on_point callback), finish() when the solve ends.
struct SweepProgress {
  std::function<void(const std::string& label, int points)> start;
  ProgressCallback on_point;
  std::function<void()> finish;
};

// Computes the frequency response of a stepped sweep in place of frequency_response(system,
// options) (hbm/frequency_response.h), e.g. spread over processes (cli/distributed_run.h).
using SweepRunner = std::function<FrequencyResponse(const HarmonicBalanceSystem& system,
                                                    const FrequencyResponseOptions& options)>;

// `progress` (may be null) receives one line per stage; `sweep` (may be null) the points;
// `runner` (may be null) computes a stepped sweep's response.
SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& definition,
                      const ProgressFn& progress, const SweepProgress* sweep = nullptr,
                      const SweepRunner* runner = nullptr);

}  // namespace stickslip

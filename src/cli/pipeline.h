// The `run` pipeline: a CaseDefinition (io/case_file.h) mapped onto the library.
//
//   meshes -> bodies (sub-mesh of an element set, K and M, clamps) -> Craig–Bampton onto the
//   master nodes (contact, forced, listed and FRF nodes) -> one block-diagonal reduced linear
//   model (all its modes, damping C = αM + βK) -> contact pairs and excitation on the reduced
//   DOFs -> HarmonicBalanceSystem -> frequency response.
//
// Bodies given as reduced matrices (+ mapping) skip the mesh and reduction steps; their master
// nodes are the physical DOFs of the mapping, named by external node number.
// Problems of the case that only show once meshes are loaded (a set missing from a mesh, contact
// nodes not coincident, a master node that is clamped) throw InvalidInput at the case-file line
// of the key that asked for them.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/dof_map.h"
#include "fe/material.h"
#include "hbm/frequency_response.h"
#include "hbm/harmonic_balance.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "reduction/reduced_body.h"

namespace stickslip {

struct PreparedBody {
  std::string name;
  bool from_mesh = false;
  Mesh mesh;                   // the body's own mesh (from_mesh)
  IsotropicMaterial material;  // from_mesh
  DofMap constraints;          // clamped DOFs of `mesh` (from_mesh)
  SparseMatrix K, M;           // full stiffness and mass of `mesh` (from_mesh)
  ReducedBody reduced;         // K_r, M_r and what each reduced DOF is
  Eigen::MatrixXd T;           // expansion basis, full DOFs x reduced (from_mesh)
  int offset = 0;              // first DOF of this body in the assembled reduced model
  // (external node id, direction) -> DOF of the assembled reduced model.
  std::map<std::pair<int, int>, int> master_dof;
  double seconds_reduction = 0.0;
  int global_dof(int node_id, int direction) const;  // -1 if not a master DOF
};

struct PreparedPair {
  int contact = 0;    // index in CaseDefinition::contacts
  int node_a_id = 0;  // external ids (0 = ground)
  int node_b_id = 0;
};

struct PreparedModel {
  std::vector<PreparedBody> bodies;
  int num_dofs = 0;      // assembled reduced DOFs
  LinearModel linear;    // all modes of the assembled reduced model
  Eigen::MatrixXd K, M;  // assembled reduced matrices (block diagonal)
  std::vector<ContactPair> pairs;
  std::vector<PreparedPair> pair_info;
  std::vector<Eigen::Matrix3d> pair_frames;  // 3D contacts: rows t1, t2, n (identity otherwise)
  Excitation excitation;
  HarmonicBalanceOptions hbm;
  double seconds_prepare = 0.0;
  int body_index(const std::string& name) const;  // -1 if absent
};

// Builds the reduced model of the case. `progress` (may be null) receives one line per stage.
PreparedModel prepare_model(const CaseDefinition& definition,
                            const std::function<void(const std::string&)>& progress);

// Natural frequencies (Hz, ascending) of the assembled reduced model with every contact stuck:
// friction pairs as springs (kt, kt, kn) in their frame, 1D laws by their tangent at rest.
Eigen::VectorXd stuck_frequencies_hz(const PreparedModel& model, const CaseDefinition& definition);

// The analysis frequencies (Hz) of a stepped sweep, or [start, stop] for continuation.
std::vector<double> analysis_frequencies_hz(const PreparedModel& model,
                                            const CaseDefinition& definition);

struct SolvedCase {
  std::unique_ptr<HarmonicBalanceSystem> system;
  FrequencyResponse response;
  std::vector<double> frequencies_hz;  // the requested grid (stepped) or range (continuation)
  double seconds_solve = 0.0;
};

SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& definition,
                      const std::function<void(const std::string&)>& progress);

}  // namespace stickslip

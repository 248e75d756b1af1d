// The loads and points of the full-model recovery (docs/conventions.md, "Full-model recovery"), computed
// from a solved model: which frequency points to recover, and the loads of each body at a point
// (excitation, static and preload loads, and the harmonic contact forces the nonlinear solve
// found, in global axes). The recovery of a body at a point: model/body_recovery.h; its files:
// cli/recovery_stage.h.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "hbm/frequency_response.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "model/case_model.h"

namespace stickslip {

// Indices of the points to recover (recovery.points: peak | all | none | frequencies).
// `response` needs omega, converged and master of every point.
std::vector<int> recovery_points(const CaseDefinition& definition, const PreparedModel& model,
                                 const FrequencyResponse& response);

// Loads of one body at one point on its reduced DOFs (body.reduced.size() x harmonics; rows of
// modal DOFs are zero): the excitation and static preload loads on its master DOFs plus the
// contact forces it receives (force_global of each pair: +f on B, -f on A). Harmonic 0 is made
// exactly real.
Eigen::MatrixXcd master_loads(const PreparedModel& model, const PreparedBody& body,
                              const std::vector<int>& harmonics, const FrequencyPoint& point);

// The same loads of one mesh body in its full DOF numbering (3 num_nodes x harmonics).
Eigen::MatrixXcd recovery_loads(const PreparedModel& model, const PreparedBody& body,
                                const std::vector<int>& harmonics, const FrequencyPoint& point);

// The same loads of a body given by matrices on the node numbers of its mapping: a mesh of its
// master nodes (no coordinates, no elements; node ids of the mapping, ascending) and the loads in
// that mesh's DOF numbering (3 num_nodes x harmonics). For the APDL macro of the thesis's route.
std::pair<Mesh, Eigen::MatrixXcd> mapped_master_loads(const PreparedModel& model,
                                                      const PreparedBody& body,
                                                      const std::vector<int>& harmonics,
                                                      const FrequencyPoint& point);

}  // namespace stickslip

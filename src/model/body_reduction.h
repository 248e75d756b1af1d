// Where each body's reduced model comes from: one interface, chosen by whoever builds the model
// (prepare_model), instead of rewriting the case.
//
//   CraigBamptonReduction  mesh bodies reduced by Craig–Bampton onto their master nodes (full K,
//                          M and the basis T kept for the recovery); bodies given by matrices
//                          read from their files (Harwell–Boeing or Matrix Market + mapping)
//   GivenReduction         the reduced matrices of some bodies given in memory (a C++ program,
//                          later Python); the other bodies as CraigBamptonReduction
//   StoredReduction        (cli/commands.h) the files `stickslip reduce` wrote
//
// reduce() gets a body whose name, from_mesh, mesh and material are set from the resolved case
// (resolve_case_bodies) and fills in its reduced model: `reduced` (K_r, M_r and each reduced DOF:
// node id and direction of physical DOFs; for mesh bodies also node index and full DOF), and for
// mesh bodies `constraints`, and K, M, T as far as the reduction provides them (shared, never
// copied), and seconds_reduction. Problems of the input throw InvalidInput at the case-file key
// they come from.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "model/case_model.h"
#include "reduction/reduced_body.h"

namespace stickslip {

class BodyReduction {
 public:
  virtual ~BodyReduction() = default;
  virtual void reduce(const CaseDefinition& definition, const CaseBody& resolved,
                      PreparedBody& body, const ProgressFn& progress) const = 0;
};

class CraigBamptonReduction final : public BodyReduction {
 public:
  // `cache` (may be null): a body whose reduction fingerprint (reduction_fingerprints) matches
  // the cached one is not reduced again (its matrices are shared); one reduced here is stored.
  // `fingerprints`: per body of the resolved case, in its order (needed with a cache).
  explicit CraigBamptonReduction(ModelCache* cache = nullptr,
                                 std::vector<std::string> fingerprints = {});
  void reduce(const CaseDefinition& definition, const CaseBody& resolved, PreparedBody& body,
              const ProgressFn& progress) const override;

 private:
  ModelCache* cache_;
  std::vector<std::string> fingerprints_;
};

class GivenReduction final : public BodyReduction {
 public:
  // Per body name, its reduced matrices: dofs name node ids and directions (physical) or modal
  // DOFs; K symmetric positive semi-definite, M positive definite (InvalidInput at the body's key
  // otherwise). A mesh body given here keeps its mesh for the recovery; physical DOFs then get
  // their node index and full DOF from the mesh's node ids.
  explicit GivenReduction(std::map<std::string, std::shared_ptr<const ReducedBody>> bodies);
  void reduce(const CaseDefinition& definition, const CaseBody& resolved, PreparedBody& body,
              const ProgressFn& progress) const override;

 private:
  std::map<std::string, std::shared_ptr<const ReducedBody>> bodies_;
};

// A body given by matrices in the case file: its files read (Harwell–Boeing or Matrix Market)
// and checked physical (M positive definite, K positive semi-definite; InvalidInput at
// bodies.<name>.reduced.mass / .stiffness).
ReducedBody read_matrix_body(const CaseDefinition& definition, const std::string& name);
// The physical check of reduced matrices, naming the files `mass_file` / `stiffness_file` and the
// case keys bodies.<name>.reduced.mass / .stiffness.
void check_reduced_matrices(const CaseDefinition& definition, const std::string& name,
                            const ReducedBody& body, const std::string& stiffness_file,
                            const std::string& mass_file);
// Gives the physical DOFs of `body.reduced` their node index and full DOF in `body.mesh` (by node
// id; InvalidInput naming the body when an id is not in its mesh).
void attach_reduced_dofs_to_mesh(PreparedBody& body);

}  // namespace stickslip

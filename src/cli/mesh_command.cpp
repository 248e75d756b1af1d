// `stickslip mesh CASE -o DIR`: the meshes of the case's bodies as the case builds them (generated
// or read, cut to the body's element set), written to DIR/mesh/<body>.inp (nodes, elements and
// the body's node and element sets: a case can read it back with `meshes: {X: {file: ...}}`) and
// DIR/mesh/<body>.vtu for ParaView, with point data "clamped" (1 on clamped nodes) and "master"
// (1 on the master nodes the reduction keeps: contact, forced, listed and FRF nodes).
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/progress.h"
#include "core/errors.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "io/inp_writer.h"
#include "io/vtu_writer.h"

namespace stickslip {

int run_mesh(const StageCommand& command) {
  namespace fs = std::filesystem;
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  const fs::path dir = stage_output_dir(base, command.output_dir) / "mesh";
  const CaseBodies bodies = resolve_case_bodies(base, progress);
  create_output_folder(dir);
  int written = 0;
  for (const CaseBody& body : bodies.bodies) {
    if (!body.from_mesh) {
      progress("body " + body.name + " is given by reduced matrices: no mesh");
      continue;
    }
    const std::string inp = (dir / (body.name + ".inp")).string();
    const std::string vtu = (dir / (body.name + ".vtu")).string();
    write_inp(inp, body.mesh);
    VtuData data;
    Eigen::MatrixXd clamped = Eigen::MatrixXd::Zero(1, body.mesh.num_nodes());
    Eigen::MatrixXd master = Eigen::MatrixXd::Zero(1, body.mesh.num_nodes());
    for (int n : body.clamp) clamped(0, n) = 1;
    for (int n : body.masters) master(0, n) = 1;
    data.point_data.push_back({"clamped", clamped});
    data.point_data.push_back({"master", master});
    write_vtu(vtu, body.mesh, data);
    progress(fmt::format("{}: {} nodes, {} elements, {} clamped, {} master nodes -> {}, {}",
                         body.name, body.mesh.num_nodes(), body.mesh.num_elements(),
                         body.clamp.size(), body.masters.size(), inp, vtu));
    ++written;
  }
  if (written == 0) {
    throw InvalidInput(base.where("bodies"), "no body is given by a mesh: nothing to write");
  }
  return 0;
}

}  // namespace stickslip

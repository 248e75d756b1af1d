#include <cstdio>
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "io/ansys_mapping.h"
#include "io/case_file.h"

namespace stickslip {

int run_reduce(const ReduceCommand& command) {
  const CaseDefinition def = read_case_file(command.case_file);
  const auto progress = [&](const std::string& line) {
    if (!command.quiet) std::fprintf(stderr, "stickslip: %s\n", line.c_str());
  };
  const PreparedModel model = prepare_model(def, progress);
  const std::filesystem::path dir(command.output_dir);
  std::filesystem::create_directories(dir);
  for (const PreparedBody& body : model.bodies) {
    if (!body.from_mesh) continue;
    const std::string k = (dir / (body.name + "_K.hb")).string();
    const std::string m = (dir / (body.name + "_M.hb")).string();
    write_ansys_reduced_body(k, m, body.reduced);
    progress(fmt::format("{}: {} reduced DOFs ({} physical) -> {}, {}", body.name,
                         body.reduced.size(), body.reduced.num_physical(), k, m));
  }
  return 0;
}

}  // namespace stickslip

// End-to-end: a body given by matrices whose mapping file has more rows than the largest reduced
// body (kMaxReducedBodyDofs, io/ansys_mapping.h: K_r and M_r are held dense) stops `stickslip
// solve` with the mapping's file and line, the count, the bytes and the limit, in both matrix
// formats, before the matrices are read (here they are 2 x 2: were they read first, the message
// would be the size mismatch instead).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace {

using namespace stickslip::cli_test;

void write_mapping(const fs::path& file, int rows) {
  std::ofstream map(file);
  map << "Matrix Eqn   Node   DOF\n";
  for (int k = 1; k <= rows; ++k)
    map << k << " " << (k + 2) / 3 << " U"
        << "XYZ"[(k - 1) % 3] << "\n";
}

std::string blade_case(const std::string& reduced) {
  return R"(stickslip: 1
bodies:
  blade: {reduced: )" +
         reduced + R"(}
contacts:
  - name: root
    law: friction
    bodies: [blade, ground]
    pairs: [1]
    normal: z
    per_pair: {kt: 1.0e8, kn: 2.0e8, mu: 0.3, preload: 10}
excitation:
  - {body: blade, node: 1, direction: y, amplitude: 1}
analysis:
  frequency: {start_hz: 100, stop_hz: 110, step_hz: 1}
output: {plots: false, vtu: false}
)";
}

TEST(ReducedBodyLimit, AMappingOfTooManyRowsStopsTheSolveNamingItsLine) {
  const fs::path dir = fresh_dir("reduced_body_limit");
  write_mapping(dir / "big.mapping", 25000);
  std::ofstream(dir / "k.mtx") << "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n"
                                  "1 1 1.0e6\n2 2 1.0e6\n";
  std::ofstream(dir / "m.mtx") << "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n"
                                  "1 1 1.0\n2 2 1.0\n";
  // A Harwell–Boeing pair is not needed: the mapping is read, and refused, first.
  std::ofstream(dir / "k.hb") << "not read\n";
  std::ofstream(dir / "m.hb") << "not read\n";
  const std::string expected =
      (dir / "big.mapping").string() +
      ":20002: equation: the mapping has 25000 equations: a reduced body of 25000 DOFs needs "
      "dense K and M of 5 GB each (n² x 8 bytes): at most 20000 DOFs (3.2 GB each) are accepted";
  for (const std::string reduced : {"{stiffness: k.mtx, mass: m.mtx, mapping: big.mapping}",
                                    "{stiffness: k.hb, mass: m.hb, mapping: big.mapping}"}) {
    SCOPED_TRACE(reduced);
    const fs::path file = write_case(dir, "case", blade_case(reduced));
    const fs::path log = dir / "solve.log";
    EXPECT_NE(run("solve " + file.string() + " -o " + (dir / "out").string(), log), 0);
    EXPECT_NE(slurp(log).find(expected), std::string::npos) << slurp(log);
  }
}

}  // namespace

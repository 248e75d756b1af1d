// How bytes reach each file reader of src/io, shared by the libFuzzer harnesses (fuzz/*.cpp,
// clang only) and by the GoogleTest that replays the seed corpora and the regression inputs
// (tests/io/fuzz_regression_test.cpp, any compiler).
//
// Contract under test: for ANY byte string, a reader either returns or throws
// stickslip::InvalidInput. Everything else (a crash, a sanitizer report, a hang, another exception
// such as std::bad_alloc or std::out_of_range, a huge allocation driven by a size field that the
// data never backs) is a bug in the reader.
//
// Readers that take a stream are fed an std::istringstream named kStreamName. Readers that only
// take a path (the CSV files of a case, the dense binary format) get the bytes written to a
// temporary file first. The case-file parser resolves relative file names against
// Context::case_base_dir, so an input can reference real small files (pairs.csv, k.hb, ...).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/ansys_mapping.h"
#include "io/case_file.h"
#include "io/cdb_reader.h"
#include "io/harwell_boeing.h"
#include "io/inp_reader.h"
#include "io/matrix_market.h"
#include "io/msh_lines.h"

namespace stickslip::fuzz {

inline constexpr const char* kStreamName = "fuzz-input";

struct Context {
  std::string case_base_dir;  // directory the case file's relative paths are resolved against
};

// The bytes in a temporary file (one name per process, overwritten by every call), for path-only
// readers. Returns the path. /dev/shm (memory) when there is one: rewriting a file in /tmp per
// input took ~3 ms here, which limited the CSV harness to ~200 inputs/s.
inline std::string bytes_to_temp_file(std::string_view bytes) {
  static const std::string path = [] {
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm", ec)
                                          ? std::filesystem::path("/dev/shm")
                                          : std::filesystem::temp_directory_path();
    return (dir / ("stickslip_fuzz_" + std::to_string(static_cast<long long>(::getpid())) + ".bin"))
        .string();
  }();
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

inline void feed_inp(std::string_view bytes, const Context&) {
  std::istringstream in{std::string(bytes)};
  (void)read_inp(in, kStreamName);
}

// The ANSYS CDB reader with its optional outputs (warnings, materials by number) requested, so
// that their code paths run too.
inline void feed_cdb(std::string_view bytes, const Context&) {
  std::istringstream in{std::string(bytes)};
  std::vector<std::string> warnings;
  std::map<int, DeckMaterial> materials;
  (void)read_cdb(in, kStreamName, &warnings, &materials);
}

inline void feed_harwell_boeing(std::string_view bytes, const Context&) {
  std::istringstream in{std::string(bytes)};
  (void)read_harwell_boeing(in, kStreamName);
}

// Both Matrix Market readers share the header code; each rejects the other's format.
inline void feed_matrix_market(std::string_view bytes, const Context&) {
  try {
    std::istringstream in{std::string(bytes)};
    (void)read_matrix_market(in, kStreamName);
  } catch (const InvalidInput&) {
  }
  std::istringstream in{std::string(bytes)};
  (void)read_matrix_market_dense(in, kStreamName);
}

inline void feed_dense_binary(std::string_view bytes, const Context&) {
  std::istringstream in{std::string(bytes)};
  (void)read_dense_binary(in, kStreamName);
}

inline void feed_ansys_mapping(std::string_view bytes, const Context&) {
  std::istringstream in{std::string(bytes)};
  (void)read_ansys_mapping(in, kStreamName);
}

inline void feed_case_file(std::string_view bytes, const Context& context) {
  (void)parse_case(std::string(bytes), kStreamName, context.case_base_dir);
}

// pairs_file (with and without ground pairs) and preload_file of a case.
inline void feed_case_csv(std::string_view bytes, const Context&) {
  const std::string path = bytes_to_temp_file(bytes);
  struct RemoveAtExit {
    const std::string& path;
    ~RemoveAtExit() {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
  } remove_at_exit{path};
  for (const bool allow_ground : {false, true}) {
    try {
      (void)read_pairs_csv(path, allow_ground);
    } catch (const InvalidInput&) {
    }
  }
  (void)read_preloads_csv(path);
}

// Our scan of ASCII Gmsh files for node and element lines and duplicate tags (the mesh itself is
// read by libgmsh, not fuzzed here).
inline void feed_msh_lines(std::string_view bytes, const Context&) {
  const std::string path = bytes_to_temp_file(bytes);
  struct RemoveAtExit {
    const std::string& path;
    ~RemoveAtExit() {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
  } remove_at_exit{path};
  (void)scan_msh_lines(path);
}

struct Target {
  const char* name;  // fuzz/corpus/<name>, tests/data/fuzz_regressions/<name>, fuzz_<name>
  void (*feed)(std::string_view bytes, const Context& context);
};

inline const std::vector<Target>& targets() {
  static const std::vector<Target> all{
      {"inp", feed_inp},
      {"harwell_boeing", feed_harwell_boeing},
      {"matrix_market", feed_matrix_market},
      {"dense_binary", feed_dense_binary},
      {"ansys_mapping", feed_ansys_mapping},
      {"case_file", feed_case_file},
      {"case_csv", feed_case_csv},
      {"msh_lines", feed_msh_lines},
      {"cdb", feed_cdb},
  };
  return all;
}

}  // namespace stickslip::fuzz

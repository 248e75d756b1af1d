// Helpers shared by the end-to-end tests of the stickslip program: run it, read its files.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace stickslip::cli_test {

namespace fs = std::filesystem;

inline const std::string kProgram = std::string(STICKSLIP_BINARY_DIR) + "/src/cli/stickslip";

// Runs a shell command with stdout and stderr to `log`; returns its exit code (-1 if killed).
inline int shell(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs the program with `args`.
inline int run(const std::string& args, const fs::path& log) {
  return shell(kProgram + " " + args, log);
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// An empty folder under the system's temporary directory.
inline fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("stickslip_cli_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Rows of a CSV file (no quoting) as maps column -> text.
inline std::vector<std::map<std::string, std::string>> read_csv(const fs::path& p) {
  const auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string cell;
    while (std::getline(ss, cell, ',')) out.push_back(cell);
    return out;
  };
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
    rows.push_back(row);
  }
  return rows;
}

}  // namespace stickslip::cli_test

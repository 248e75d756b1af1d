#include "cli/processes.h"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "cli/mpi_plugin_api.h"
#include "core/errors.h"
#include "io/gmsh_plugin.h"
#include "io/plugin_loader.h"
#include "model/petsc_reduction.h"

#ifndef STICKSLIP_MPI_PLUGIN_BUILD_PATH
#define STICKSLIP_MPI_PLUGIN_BUILD_PATH ""
#endif

namespace stickslip {
namespace {

constexpr const char* kPluginFile = "libstickslip_mpi.so";

// Tags of checkpoint()'s message (the protocols of cli/distributed_run.h use others).
constexpr int kCheckpointErrorTag = 900;

const MpiPluginApi* g_api = nullptr;
Processes* g_processes = nullptr;

int environment_integer(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr || *value == '\0') return -1;
  char* end = nullptr;
  const long n = std::strtol(value, &end, 10);
  return *end == '\0' && n >= 0 && n < (1L << 30) ? static_cast<int>(n) : -1;
}

const MpiPluginApi* load(std::string& failures) {
  // RTLD_GLOBAL: Open MPI loads its own components with dlopen and they need libmpi's symbols.
  const PluginSearch search{kPluginFile, "STICKSLIP_MPI_PLUGIN", STICKSLIP_MPI_PLUGIN_BUILD_PATH,
                            "an MPI plugin of this version of stickslip",
                            /*global_symbols=*/true};
  return static_cast<const MpiPluginApi*>(open_plugin(
      search,
      [](void* handle) -> const void* {
        using Entry = const MpiPluginApi* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, "stickslip_mpi_plugin_api"));
        const MpiPluginApi* api = entry != nullptr ? entry() : nullptr;
        return api != nullptr && api->abi == kMpiPluginAbi ? api : nullptr;
      },
      failures));
}

[[noreturn]] void mpi_failed(const char* what) {
  throw std::runtime_error(std::string("MPI: ") + what + ": " + g_api->last_error());
}

}  // namespace

int launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const int n = environment_integer(name);
    if (n >= 1) return n;
  }
  return 1;
}

int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"}) {
    const int n = environment_integer(name);
    if (n >= 0) return n;
  }
  return 0;
}

std::string describe_failure(std::exception_ptr error, int* exit_code) {
  try {
    std::rethrow_exception(error);
  } catch (const PeerError& e) {
    *exit_code = e.exit_code();
    return e.what();
  } catch (const InvalidInput& e) {
    *exit_code = 2;
    return std::string("stickslip: error: ") + e.what();
  } catch (const std::filesystem::filesystem_error& e) {
    // A file-system refusal that no stage turned into an InvalidInput: still the user's files.
    *exit_code = 2;
    return "stickslip: error: " + e.path1().string() + ": " + e.code().message();
  } catch (const GmshUnavailable& e) {
    // Not the input's fault and not a bug: the installation lacks a plugin.
    *exit_code = 5;
    return std::string("stickslip: error: ") + e.what();
  } catch (const MpiUnavailable& e) {
    *exit_code = 5;
    return std::string("stickslip: error: ") + e.what();
  } catch (const PetscUnavailable& e) {
    *exit_code = 5;
    return std::string("stickslip: error: ") + e.what();
  } catch (const std::exception& e) {
    *exit_code = 3;
    return std::string("stickslip: internal error: ") + e.what();
  } catch (...) {
    *exit_code = 3;
    return "stickslip: internal error: an unknown exception";
  }
}

Processes& start_processes() {
  static std::once_flag once;
  static Processes world;
  static std::string failure;
  std::call_once(once, [] {
    std::string failures;
    g_api = load(failures);
    if (g_api == nullptr) {
      failure = "this run was started with " + std::to_string(launcher_world_size()) +
                " processes (mpirun), which needs MPI, whose plugin (" + kPluginFile +
                ") could not be loaded; tried:" + failures +
                "\n(build stickslip with -DSTICKSLIP_MPI=ON and libopenmpi-dev, set "
                "STICKSLIP_MPI_PLUGIN to the plugin's path, or run without mpirun)";
      return;
    }
    if (g_api->initialize(&world.rank_, &world.size_) != 0) {
      failure = std::string("MPI could not be initialised: ") + g_api->last_error();
      g_api = nullptr;
      return;
    }
    g_processes = &world;
  });
  if (g_processes == nullptr) throw MpiUnavailable(failure);
  return *g_processes;
}

Processes* processes() { return g_processes; }

void Processes::send(int dest, int tag, const std::string& bytes) {
  if (g_api->send(dest, tag, bytes.data(), bytes.size()) != 0) mpi_failed("send");
}

Processes::Message Processes::receive(int source) {
  Message m;
  void* data = nullptr;
  std::uint64_t size = 0;
  if (g_api->receive(source, &m.from, &m.tag, &data, &size) != 0) mpi_failed("receive");
  if (data != nullptr) {
    m.bytes.assign(static_cast<const char*>(data), size);
    g_api->release(data);
  }
  return m;
}

bool Processes::pending(int source) {
  int waiting = 0;
  if (g_api->pending(source, &waiting) != 0) mpi_failed("probe");
  return waiting != 0;
}

void Processes::progress() noexcept { g_api->progress(); }

void Processes::checkpoint(std::exception_ptr error) {
  int lowest = 0;
  if (g_api->all_min(error ? rank_ : size_, &lowest) != 0) mpi_failed("all-reduce");
  if (lowest == size_) return;  // nobody failed
  if (lowest == rank_ && rank_ == 0) std::rethrow_exception(error);
  if (lowest == rank_) {
    int code = 0;
    Packer p;
    p.put(describe_failure(error, &code));
    p.put(static_cast<std::int64_t>(code));
    send(0, kCheckpointErrorTag, p.bytes());
    throw PeerStopped();
  }
  if (rank_ != 0) throw PeerStopped();
  const Message m = receive(lowest);
  Unpacker u(m.bytes);
  const std::string text = u.text();
  const int code = static_cast<int>(u.integer());
  throw PeerError(text + " (process " + std::to_string(lowest) + ")", code);
}

void Processes::finish() noexcept {
  if (finished_) return;
  finished_ = true;
  g_api->finalize();
}

void Processes::abort(int code) noexcept {
  g_api->abort(code);
  std::_Exit(code);
}

void Unpacker::raw(void* p, size_t n) {
  if (bytes_.size() - at_ < n) throw std::runtime_error("a message between processes ends early");
  std::memcpy(p, bytes_.data() + at_, n);
  at_ += n;
}

std::int64_t Unpacker::integer() {
  std::int64_t v = 0;
  raw(&v, sizeof v);
  return v;
}

double Unpacker::number() {
  double v = 0;
  raw(&v, sizeof v);
  return v;
}

std::string Unpacker::text() {
  const auto n = static_cast<size_t>(integer());
  if (bytes_.size() - at_ < n) throw std::runtime_error("a message between processes ends early");
  std::string s = bytes_.substr(at_, n);
  at_ += n;
  return s;
}

std::vector<double> Unpacker::numbers() {
  const auto n = static_cast<size_t>(integer());
  if ((bytes_.size() - at_) / sizeof(double) < n)
    throw std::runtime_error("a message between processes ends early");
  std::vector<double> v(n);
  raw(v.data(), n * sizeof(double));
  return v;
}

}  // namespace stickslip

// The interface of the MPI plugin libstickslip_mpi.so (src/cli/mpi/): the few MPI operations a
// study spread over processes needs (cli/processes.h), behind plain C types so that the program
// neither links nor includes MPI. Loaded with dlopen only when the program runs under mpirun
// with more than one process; docs/dependencies.md says why it is a plugin.
//
// Messages are byte buffers of any length with a tag >= 0, ordered per (source, destination).
// Every function returns 0 on success; on failure a non-zero code, and last_error() says why.
#pragma once

#include <cstddef>
#include <cstdint>

namespace stickslip {

inline constexpr int kMpiPluginAbi = 1;

struct MpiPluginApi {
  int abi = kMpiPluginAbi;
  // MPI_Init_thread (MPI calls from the main thread only), then the rank and number of
  // processes of MPI_COMM_WORLD.
  int (*initialize)(int* rank, int* size) = nullptr;
  // Sends a copy of data[0, size) to `dest` without waiting for the receiver: the transfer
  // completes in the background, at progress() or at finalize().
  int (*send)(int dest, int tag, const void* data, std::uint64_t size) = nullptr;
  // Lets the sends under way advance (for a process that computes long between MPI calls).
  int (*progress)() = nullptr;
  // *waiting = 1 when a message from `source` (-1: any) can be received now, else 0.
  int (*pending)(int source, int* waiting) = nullptr;
  // Waits for the next message from `source` (-1: any). *data is malloc'ed (release() it; null
  // when *size is 0).
  int (*receive)(int source, int* from, int* tag, void** data, std::uint64_t* size) = nullptr;
  void (*release)(void* data) = nullptr;
  // The minimum of `value` over every process (a collective: every process must call it).
  int (*all_min)(int value, int* minimum) = nullptr;
  // Completes the sends under way, then MPI_Finalize.
  int (*finalize)() = nullptr;
  // MPI_Abort of every process (the last resort: nothing else can stop a peer).
  void (*abort)(int code) = nullptr;
  const char* (*last_error)() = nullptr;
};

}  // namespace stickslip

// The plugin's entry point.
extern "C" const stickslip::MpiPluginApi* stickslip_mpi_plugin_api();

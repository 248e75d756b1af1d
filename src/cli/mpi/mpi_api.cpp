// The MPI plugin (cli/mpi_plugin_api.h): the only code of stickslip that calls MPI, built as
// libstickslip_mpi.so against Open MPI and loaded by cli/processes.cpp under mpirun.
//
// A message is a header (its length and tag) followed by its bytes in chunks of at most
// kChunkBytes (MPI counts are int); MPI keeps the order of messages between two processes with
// the same tag, so the chunks after a header are that message's.
// The C API only (Open MPI's and MPICH's headers add their deprecated C++ bindings otherwise).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <list>
#include <string>
#include <vector>

#include "cli/mpi_plugin_api.h"

namespace {

constexpr int kHeaderTag = 1;
constexpr int kChunkTag = 2;
constexpr std::uint64_t kChunkBytes = std::uint64_t{1} << 30;

std::string g_error;

int failed(const std::string& what, int code) {
  char text[MPI_MAX_ERROR_STRING] = {0};
  int length = 0;
  MPI_Error_string(code, text, &length);
  g_error = what + ": " + std::string(text, static_cast<size_t>(std::max(length, 0)));
  return code == 0 ? 1 : code;
}

// A send under way: its bytes stay alive until MPI is done with them.
struct Outgoing {
  std::int64_t header[2] = {0, 0};  // length, tag
  std::vector<char> bytes;
  std::vector<MPI_Request> requests;
};
std::list<Outgoing> g_outgoing;

// Frees the sends that are complete; 0 or an MPI error code.
int reap() {
  for (auto it = g_outgoing.begin(); it != g_outgoing.end();) {
    int done = 0;
    const int code = MPI_Testall(static_cast<int>(it->requests.size()), it->requests.data(), &done,
                                 MPI_STATUSES_IGNORE);
    if (code != MPI_SUCCESS) return failed("MPI_Testall", code);
    it = done ? g_outgoing.erase(it) : std::next(it);
  }
  return 0;
}

int initialize(int* rank, int* size) {
  int provided = 0;
  int code = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (code != MPI_SUCCESS) return failed("MPI_Init_thread", code);
  // Errors come back as codes (turned into messages), not as MPI's own abort.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  if ((code = MPI_Comm_rank(MPI_COMM_WORLD, rank)) != MPI_SUCCESS)
    return failed("MPI_Comm_rank", code);
  if ((code = MPI_Comm_size(MPI_COMM_WORLD, size)) != MPI_SUCCESS)
    return failed("MPI_Comm_size", code);
  return 0;
}

int send(int dest, int tag, const void* data, std::uint64_t size) {
  if (const int code = reap()) return code;
  Outgoing& out = g_outgoing.emplace_back();
  out.header[0] = static_cast<std::int64_t>(size);
  out.header[1] = tag;
  out.bytes.assign(static_cast<const char*>(data), static_cast<const char*>(data) + size);
  out.requests.emplace_back();
  int code =
      MPI_Isend(out.header, 2, MPI_INT64_T, dest, kHeaderTag, MPI_COMM_WORLD, &out.requests.back());
  if (code != MPI_SUCCESS) return failed("MPI_Isend", code);
  for (std::uint64_t at = 0; at < size; at += kChunkBytes) {
    const int count = static_cast<int>(std::min(kChunkBytes, size - at));
    out.requests.emplace_back();
    code = MPI_Isend(out.bytes.data() + at, count, MPI_BYTE, dest, kChunkTag, MPI_COMM_WORLD,
                     &out.requests.back());
    if (code != MPI_SUCCESS) return failed("MPI_Isend", code);
  }
  return 0;
}

int progress() { return reap(); }

int pending(int source, int* waiting) {
  if (const int code = reap()) return code;
  MPI_Status status;
  const int code = MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, kHeaderTag, MPI_COMM_WORLD,
                              waiting, &status);
  return code == MPI_SUCCESS ? 0 : failed("MPI_Iprobe", code);
}

int receive(int source, int* from, int* tag, void** data, std::uint64_t* size) {
  *data = nullptr;
  *size = 0;
  std::int64_t header[2] = {0, 0};
  MPI_Status status;
  int code = MPI_Recv(header, 2, MPI_INT64_T, source < 0 ? MPI_ANY_SOURCE : source, kHeaderTag,
                      MPI_COMM_WORLD, &status);
  if (code != MPI_SUCCESS) return failed("MPI_Recv", code);
  *from = status.MPI_SOURCE;
  *tag = static_cast<int>(header[1]);
  const auto length = static_cast<std::uint64_t>(header[0]);
  if (length == 0) return 0;
  char* bytes = static_cast<char*>(std::malloc(length));
  if (bytes == nullptr) {
    g_error = "out of memory for a message of " + std::to_string(length) + " bytes";
    return 1;
  }
  for (std::uint64_t at = 0; at < length; at += kChunkBytes) {
    const int count = static_cast<int>(std::min(kChunkBytes, length - at));
    code =
        MPI_Recv(bytes + at, count, MPI_BYTE, *from, kChunkTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (code != MPI_SUCCESS) {
      std::free(bytes);
      return failed("MPI_Recv", code);
    }
  }
  *data = bytes;
  *size = length;
  return 0;
}

void release(void* data) { std::free(data); }

int all_min(int value, int* minimum) {
  const int code = MPI_Allreduce(&value, minimum, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return code == MPI_SUCCESS ? 0 : failed("MPI_Allreduce", code);
}

int finalize() {
  for (Outgoing& out : g_outgoing) {
    const int code = MPI_Waitall(static_cast<int>(out.requests.size()), out.requests.data(),
                                 MPI_STATUSES_IGNORE);
    if (code != MPI_SUCCESS) return failed("MPI_Waitall", code);
  }
  g_outgoing.clear();
  const int code = MPI_Finalize();
  return code == MPI_SUCCESS ? 0 : failed("MPI_Finalize", code);
}

void abort_all(int code) { MPI_Abort(MPI_COMM_WORLD, code); }

const char* last_error() { return g_error.c_str(); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const stickslip::MpiPluginApi*
stickslip_mpi_plugin_api() {
  static const stickslip::MpiPluginApi api{
      .abi = stickslip::kMpiPluginAbi,
      .initialize = &initialize,
      .send = &send,
      .progress = &progress,
      .pending = &pending,
      .receive = &receive,
      .release = &release,
      .all_min = &all_min,
      .finalize = &finalize,
      .abort = &abort_all,
      .last_error = &last_error,
  };
  return &api;
}

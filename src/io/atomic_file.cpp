#include "io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <locale>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <streambuf>
#include <vector>

#include <fmt/core.h>

#include "core/errors.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPrefix = ".stickslip-tmp-";
constexpr const char* kLockSuffix = ".lock";

// Guards the registry of live folders and the creation of every temporary file, so that the
// interruption handler (remove_all_temporaries_and_stop) sees all of them and none appears after.
std::mutex g_mutex;
std::set<const TemporaryFolder*> g_live;
std::set<std::pair<dev_t, ino_t>> g_scanned;  // directories already cleaned by this process
std::mutex g_protected_mutex;
std::set<std::pair<dev_t, ino_t>> g_protected;  // input files (protect_input_file)

bool is_protected(const fs::path& p) {
  struct stat st {};
  if (::stat(p.c_str(), &st) != 0) return false;
  std::lock_guard<std::mutex> lock(g_protected_mutex);
  return g_protected.count({st.st_dev, st.st_ino}) > 0;
}

std::string reason(int error) { return std::strerror(error); }

// An output stream buffer on a POSIX descriptor that remembers the errno of a failed write
// (std::ofstream loses it).
class DescriptorBuffer : public std::streambuf {
 public:
  explicit DescriptorBuffer(int fd) : fd_(fd) { setp(buffer_, buffer_ + sizeof buffer_); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        error_ = n < 0 ? errno : EIO;
        return false;
      }
      p += n;
    }
    setp(buffer_, buffer_ + sizeof buffer_);
    return true;
  }
  int fd_;
  int error_ = 0;
  char buffer_[1 << 16];
};

std::string random_hex() {
  static std::mt19937_64 engine{std::random_device{}()};
  return fmt::format("{:016x}", engine());
}

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }
bool ends_with(const std::string& s, const std::string& p) {
  return s.size() >= p.size() && s.compare(s.size() - p.size(), p.size(), p) == 0;
}

// "<name>.tmp.<pid>.<n>" of an older stickslip: the pid, or 0 if the name is not of that form.
long legacy_temporary_pid(const std::string& name) {
  const size_t last = name.rfind('.');
  if (last == std::string::npos || last == 0) return 0;
  const size_t middle = name.rfind('.', last - 1);
  if (middle == std::string::npos || middle < 4 || name.compare(middle - 4, 4, ".tmp") != 0) {
    return 0;
  }
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 12 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  const std::string pid = name.substr(middle + 1, last - middle - 1);
  if (!digits(pid) || !digits(name.substr(last + 1))) return 0;
  return std::stol(pid);
}

int remove_stale_unlocked(const fs::path& dir) {
  int removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (starts_with(name, kPrefix) && ends_with(name, kLockSuffix)) {
      const fs::path lock = it->path();
      const int fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC | O_NOFOLLOW);
      if (fd < 0) continue;
      if (::flock(fd, LOCK_EX | LOCK_NB) == 0) {  // its holder is gone
        const fs::path folder =
            dir / name.substr(0, name.size() - std::string(kLockSuffix).size());
        std::error_code ignored;
        fs::remove_all(folder, ignored);
        if (!fs::exists(folder, ignored) && ::unlink(lock.c_str()) == 0) ++removed;
      }
      ::close(fd);
    } else if (const long pid = legacy_temporary_pid(name); pid > 0) {
      if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH &&
          it->is_regular_file(ec) && !is_protected(it->path()) &&
          ::unlink(it->path().c_str()) == 0) {
        ++removed;
      }
    }
  }
  return removed;
}

}  // namespace

TemporaryFolder::TemporaryFolder(const fs::path& dir_in) {
  const fs::path dir = dir_in.empty() ? fs::path(".") : dir_in;
  std::lock_guard<std::mutex> lock(g_mutex);
  struct stat st {};
  if (::stat(dir.c_str(), &st) != 0) {
    throw InvalidInput({dir.string(), 0, ""}, "cannot write in this folder: " + reason(errno));
  }
  if (g_scanned.insert({st.st_dev, st.st_ino}).second) remove_stale_unlocked(dir);
  for (int attempt = 0;; ++attempt) {
    const std::string base = kPrefix + std::to_string(::getpid()) + "-" + random_hex();
    lock_path_ = dir / (base + kLockSuffix);
    path_ = dir / base;
    const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
      if (errno == EEXIST && attempt < 10) continue;
      throw InvalidInput({dir.string(), 0, ""},
                         "cannot create a temporary file in this folder: " + reason(errno));
    }
    ::flock(fd, LOCK_EX);
    // Another process's remove_stale_temporaries may have locked and removed the new file between
    // open and flock: then it is no longer this path's file, and we start again.
    struct stat mine {}, named {};
    if (::fstat(fd, &mine) != 0 || ::stat(lock_path_.c_str(), &named) != 0 ||
        mine.st_ino != named.st_ino || mine.st_dev != named.st_dev) {
      ::close(fd);
      if (attempt < 10) continue;
      throw InvalidInput({dir.string(), 0, ""}, "cannot keep a lock file in this folder");
    }
    if (::mkdir(path_.c_str(), 0700) != 0) {
      const int error = errno;
      ::unlink(lock_path_.c_str());
      ::close(fd);
      throw InvalidInput({dir.string(), 0, ""},
                         "cannot create a temporary folder in this folder: " + reason(error));
    }
    lock_fd_ = fd;
    g_live.insert(this);
    return;
  }
}

TemporaryFolder::~TemporaryFolder() {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_live.erase(this);
  std::error_code ignored;
  fs::remove_all(path_, ignored);
  ::unlink(lock_path_.c_str());
  ::close(lock_fd_);
}

int TemporaryFolder::create_file(const std::string& name, const std::string& display_path) const {
  std::lock_guard<std::mutex> lock(g_mutex);
  const int fd = ::open((path_ / name).c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) {
    throw InvalidInput({display_path, 0, ""},
                       "cannot create a temporary file for it: " + reason(errno));
  }
  return fd;
}

int remove_stale_temporaries(const fs::path& dir) { return remove_stale_unlocked(dir); }

void remove_all_temporaries_and_stop() {
  g_mutex.lock();  // never unlocked: the process is about to exit
  for (const TemporaryFolder* t : g_live) {
    std::error_code ignored;
    fs::remove_all(t->path(), ignored);
    fs::path lock = t->path();
    lock += kLockSuffix;
    ::unlink(lock.c_str());
  }
}

void protect_input_file(const fs::path& path) {
  struct stat st {};
  if (path.empty() || ::stat(path.c_str(), &st) != 0) return;
  std::lock_guard<std::mutex> lock(g_protected_mutex);
  g_protected.insert({st.st_dev, st.st_ino});
}

namespace {
std::mutex g_published_mutex;
std::vector<fs::path> g_published;  // absolute, normalised, in order of publication
}  // namespace

std::vector<fs::path> published_files_under(const fs::path& dir) {
  const fs::path root = fs::absolute(dir).lexically_normal();
  std::vector<fs::path> out;
  std::lock_guard<std::mutex> lock(g_published_mutex);
  for (const fs::path& file : g_published) {
    const fs::path relative = file.lexically_relative(root);
    if (!relative.empty() && *relative.begin() != "..") out.push_back(relative);
  }
  return out;
}

void publish_file(const fs::path& from, const fs::path& to) {
  if (is_protected(to)) {
    throw InvalidInput({to.string(), 0, ""},
                       "this is an input file of the case: a result would replace it (results "
                       "never replace inputs; choose another output folder with -o)");
  }
  if (::rename(from.c_str(), to.c_str()) != 0) {
    throw InvalidInput({to.string(), 0, ""}, "cannot put the file in place: " + reason(errno));
  }
  const fs::path file = fs::absolute(to).lexically_normal();
  std::lock_guard<std::mutex> lock(g_published_mutex);
  if (std::find(g_published.begin(), g_published.end(), file) == g_published.end())
    g_published.push_back(file);
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write) {
  const SourceLocation where{path, 0, ""};
  const fs::path target(path);
  const std::string name = target.filename().string();
  std::unique_ptr<TemporaryFolder> folder;
  try {
    folder = std::make_unique<TemporaryFolder>(target.parent_path());
  } catch (const InvalidInput& e) {
    throw InvalidInput(where, e.message());
  }
  const int fd = folder->create_file(name, path);
  int error = 0;
  {
    DescriptorBuffer buffer(fd);
    std::ostream out(&buffer);
    out.imbue(std::locale::classic());
    try {
      write(out);
      out.flush();
    } catch (...) {
      ::close(fd);
      throw;  // the folder and the temporary go with `folder`
    }
    if (!out) error = buffer.error() ? buffer.error() : EIO;
  }
  if (::close(fd) != 0 && error == 0) error = errno;  // NFS and quotas may report only here
  if (error != 0) throw InvalidInput(where, "cannot write this file: " + reason(error));
  publish_file(folder->path() / name, target);
}

void create_output_folder(const fs::path& dir) {
  const SourceLocation where{dir.string(), 0, ""};
  fs::path prefix;
  for (const fs::path& part : dir) {
    prefix /= part;
    std::error_code ec;
    const fs::file_status s = fs::status(prefix, ec);
    if (fs::exists(s) && !fs::is_directory(s)) {
      throw InvalidInput(where, "cannot create the output folder: " + prefix.string() +
                                    " is a file, not a folder (choose another folder with -o)");
    }
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    throw InvalidInput(where,
                       "cannot create the output folder: " + ec.message() +
                           " (choose another folder with -o or output.directory)");
  }
}

}  // namespace stickslip

#include "core/common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>

#include "core/common/error.h"

namespace bliskrun {

namespace fs = std::filesystem;

namespace {

// Temporary files of writes in progress, for remove_unfinished_writes().
std::mutex unfinished_mutex;
std::set<std::string> unfinished;

// Creates the temporary and lists it under one lock, so that a hard stop
// (remove_unfinished_writes from another thread, then _Exit) cannot come
// between the two and leave it behind.
struct Unfinished {
  explicit Unfinished(std::string& tmp) {
    std::lock_guard<std::mutex> lock(unfinished_mutex);
    fd = mkstemp(tmp.data());
    if (fd < 0) return;
    tmp_ = tmp;
    unfinished.insert(tmp_);
  }
  ~Unfinished() {
    std::lock_guard<std::mutex> lock(unfinished_mutex);
    if (fd >= 0) unfinished.erase(tmp_);
  }
  int fd = -1;
  std::string tmp_;
};

}  // namespace

void remove_unfinished_writes() {
  std::lock_guard<std::mutex> lock(unfinished_mutex);
  for (const auto& tmp : unfinished) ::unlink(tmp.c_str());
}

void write_file_atomic(const std::string& path, const std::string& contents) {
  const fs::path target(path);
  std::error_code ec;
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw Error("cannot create folder '" + target.parent_path().string() +
                        "': " + ec.message());
  }
  // The temporary lives beside the target so rename() stays on one file
  // system and is atomic.
  std::string tmp = path + ".tmp.XXXXXX";
  const Unfinished in_progress(tmp);
  const int fd = in_progress.fd;
  if (fd < 0) throw Error("cannot write '" + path + "': " + std::strerror(errno));
  const char* data = contents.data();
  size_t left = contents.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      const std::string reason = std::strerror(errno);
      ::close(fd);
      ::unlink(tmp.c_str());
      throw Error("cannot write '" + path + "': " + reason);
    }
    data += n;
    left -= static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::fchmod(fd, 0644) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    ::unlink(tmp.c_str());
    throw Error("cannot write '" + path + "': " + reason);
  }
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw Error("cannot write '" + path + "': " + reason);
  }
}

}  // namespace bliskrun

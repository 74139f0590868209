#include "core/io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/error.hpp"

namespace gmslab {

namespace {

namespace fs = std::filesystem;

// ".NAME.tmp-" : every temporary file of a save of NAME starts with this; the writer's process id
// follows, then mkstemp's six random characters.
std::string temp_prefix(const fs::path& target) {
  return "." + target.filename().string() + ".tmp-";
}

// True when `rest` ("<pid>-XXXXXX") names a process that no longer exists.
bool writer_is_gone(const std::string& rest) {
  const auto dash = rest.find('-');
  if (dash == std::string::npos || dash == 0 || dash > 10) return false;
  long pid = 0;
  for (std::size_t i = 0; i < dash; ++i) {
    if (rest[i] < '0' || rest[i] > '9') return false;
    pid = pid * 10 + (rest[i] - '0');
  }
  if (pid <= 0 || pid == static_cast<long>(::getpid())) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

// Closes fd on a detached thread (the old file's last reference: its blocks are released there);
// closes it here when no thread can be started.
void release_in_background(int fd) noexcept {
  try {
    std::thread([fd] { ::close(fd); }).detach();
  } catch (...) {
    ::close(fd);
  }
}

}  // namespace

std::size_t remove_stale_temporaries(const std::string& path) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string prefix = temp_prefix(target);
  std::size_t removed = 0;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0 || !writer_is_gone(name.substr(prefix.size()))) continue;
    std::error_code rm;
    if (fs::remove(it->path(), rm)) ++removed;
  }
  return removed;
}

AtomicFileWriter::AtomicFileWriter(const std::string& path) : path_(path) {
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  remove_stale_temporaries(path);
  tmp_ = (dir / (temp_prefix(target) + std::to_string(::getpid()) + "-XXXXXX")).string();
  fd_ = ::mkstemp(tmp_.data());
  if (fd_ < 0)
    throw IoError("cannot create a temporary file beside '" + path +
                             "': " + std::strerror(errno));
  buf_.reserve(kBuffer);
}

AtomicFileWriter::~AtomicFileWriter() { abandon(); }

void AtomicFileWriter::abandon() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(tmp_.c_str());
    fd_ = -1;
  }
}

void AtomicFileWriter::fail(const char* what) {
  const std::string err = std::strerror(errno);
  abandon();
  throw IoError(std::string("cannot save '") + path_ + "' (" + what + "): " + err);
}

void AtomicFileWriter::write_all(const char* p, std::size_t left) {
  while (left > 0) {
    const ssize_t w = ::write(fd_, p, left);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail("write");
    }
    p += w;
    left -= static_cast<std::size_t>(w);
    written_ += static_cast<std::size_t>(w);
  }
  start_writeback();
}

void AtomicFileWriter::start_writeback() {
#if defined(__linux__)
  // The disk writes of every 8 MiB written are started now (asynchronously), so that commit's
  // fsync waits for the last few MiB only and not for the whole file. Only a hint: fsync is what
  // makes the file durable and reports the errors.
  constexpr std::size_t kWriteback = std::size_t{8} << 20;
  if (written_ - started_ < kWriteback) return;
  (void)::sync_file_range(fd_, static_cast<off_t>(started_),
                          static_cast<off_t>(written_ - started_), SYNC_FILE_RANGE_WRITE);
  started_ = written_;
#endif
}

void AtomicFileWriter::write(std::string_view text) {
  if (fd_ < 0) throw InternalError("AtomicFileWriter: write after commit or failure");
  if (buf_.size() + text.size() > kBuffer) flush();
  if (text.size() >= kBuffer)
    write_all(text.data(), text.size());
  else
    buf_.append(text);
}

void AtomicFileWriter::flush() {
  write_all(buf_.data(), buf_.size());
  buf_.clear();
}

void AtomicFileWriter::commit() {
  if (fd_ < 0) throw InternalError("AtomicFileWriter: commit after commit or failure");
  flush();
  if (::fchmod(fd_, 0644) != 0) fail("chmod");
  if (::fsync(fd_) != 0) fail("fsync");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const std::string err = std::strerror(errno);
    ::unlink(tmp_.c_str());
    throw IoError("cannot save '" + path_ + "' (close): " + err);
  }
  // The file being replaced stays open across the rename, so that the rename only relinks and the
  // release of the old file's blocks (tens of milliseconds for a file of 100 MB on ext4, mostly
  // waiting for the journal) happens when that descriptor is closed, on a thread of its own: the
  // new file is in place and durable without waiting for it.
  const int old = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const std::string err = std::strerror(errno);
    if (old >= 0) ::close(old);
    ::unlink(tmp_.c_str());
    throw IoError("cannot save '" + path_ + "' (rename): " + err);
  }
  if (old >= 0) release_in_background(old);
  // Make the rename itself durable.
  const fs::path target(path_);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void write_file_atomic(const std::string& path, std::string_view contents) {
  AtomicFileWriter w(path);
  w.write(contents);
  w.commit();
}

std::string set_aside(const std::string& path) {
  std::string to = path + ".unreadable";
  for (int i = 2; fs::exists(to); ++i) to = path + ".unreadable-" + std::to_string(i);
  if (::rename(path.c_str(), to.c_str()) != 0)
    throw IoError("cannot move '" + path + "' aside to '" + to +
                             "': " + std::strerror(errno));
  return to;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file (" + std::strerror(errno) + ")");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return ss.str();
}

}  // namespace gmslab

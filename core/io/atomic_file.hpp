// gmslab core: atomic file writes. The text goes to a temporary file in the same folder, is
// flushed to disk (fsync), then renamed over the target: a reader sees the old file or the new
// one, never half of one, even when the writer is killed. The temporary file is named
// ".NAME.tmp-<pid>-XXXXXX"; one left behind by a writer that was killed mid-save is removed by the
// next save of NAME once that process no longer exists.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace gmslab {

// A file written atomically in pieces (streamed): the pieces go to the temporary file as they
// come (through a 1 MiB buffer, so memory stays constant whatever the size; on Linux the disk
// writes of every 8 MiB are started as it goes), and commit() flushes, fsyncs and renames it over
// the target. Destroyed without commit() (an error, an exception), it
// removes the temporary file and the target is untouched. Errors throw IoError (core/error.hpp)
// naming the path and the system error.
class AtomicFileWriter {
 public:
  explicit AtomicFileWriter(const std::string& path);
  ~AtomicFileWriter();
  AtomicFileWriter(const AtomicFileWriter&) = delete;
  AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;
  void write(std::string_view text);
  void commit();
  const std::string& temporary_path() const { return tmp_; }

 private:
  static constexpr std::size_t kBuffer = 1u << 20;
  void flush();
  void write_all(const char* p, std::size_t n);
  void start_writeback();
  [[noreturn]] void fail(const char* what);
  void abandon() noexcept;
  std::string path_, tmp_, buf_;
  int fd_ = -1;
  std::size_t written_ = 0, started_ = 0;  // bytes written; those whose disk write was started
};

// Throws IoError naming the path and the system error on failure.
void write_file_atomic(const std::string& path, std::string_view contents);
// Removes the temporary files beside `path` whose writing process no longer exists (a save that
// was killed); files of live writers, including this process, are kept. Returns how many it removed.
std::size_t remove_stale_temporaries(const std::string& path);
// Moves a file that could not be read aside, to PATH.unreadable (or PATH.unreadable-2, -3, ... if
// taken), so that a later save to PATH does not overwrite what the user had. Returns the new path;
// throws IoError naming both paths when the rename fails.
std::string set_aside(const std::string& path);
// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace gmslab

// gmslab core: atomic file writes. The text goes to a temporary file in the same folder, is
// flushed to disk (fsync), then renamed over the target: a reader sees the old file or the new
// one, never half of one, even when the writer is killed.
#pragma once

#include <string>
#include <string_view>

namespace gmslab {

// Throws std::runtime_error naming the path and the system error on failure.
void write_file_atomic(const std::string& path, std::string_view contents);
// Reads a whole file; throws InputError naming the path when it cannot be read.
std::string read_file(const std::string& path);

}  // namespace gmslab

// Helpers of the hardening tests: a private temporary folder per test process (ctest runs the
// cases in parallel, so no two processes share a file name) and "load this text, return the error".
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::hardening {

// A folder that lives as long as the test process and is removed at exit.
inline const std::filesystem::path& temp_dir() {
  static const std::filesystem::path dir = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "gmslab-hard-XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) std::abort();
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(temp_dir(), ec);
    });
    return std::filesystem::path(tmpl);
  }();
  return dir;
}

inline std::string temp_file(const std::string& name) { return (temp_dir() / name).string(); }

inline std::string preset_text(const std::string& name) {
  return read_file(std::string(GMSLAB_SOURCE_DIR) + "/presets/" + name);
}

// Writes `text` to `name` in the temp folder and loads it as a preset: the InputError message, or
// "" when it loaded.
inline std::string load_error(const std::string& name, const std::string& text) {
  const std::string path = temp_file(name);
  write_file_atomic(path, text);
  try {
    load_scenario(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace gmslab::hardening

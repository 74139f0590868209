// gmslab core: strict reading of JSON objects.
//
// JsonReader wraps one JSON object and its key path ("friction.elements[2].k"). Every accessor
// checks presence, type, finiteness and range, and throws InputError with the file, the key path
// and what would be accepted. finish() rejects any key that was not read, so a typo is an error and
// never a silent default. Use it for every loader (presets, sessions, reports read back).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace gmslab {

class JsonReader {
 public:
  JsonReader(const nlohmann::json& j, std::string file, std::string path = "");

  const nlohmann::json& json() const { return j_; }
  const std::string& path() const { return path_; }
  std::string where(const std::string& key) const;  // "file: key 'a.b.key'"
  bool has(const std::string& key) const;

  // Required number in [lo, hi] (or (lo, hi] with lo_open). `unit` is shown in messages.
  double number(const std::string& key, double lo, double hi, const std::string& unit = "",
                bool lo_open = false);
  std::optional<double> opt_number(const std::string& key, double lo, double hi,
                                   const std::string& unit = "", bool lo_open = false);
  long long integer(const std::string& key, long long lo, long long hi);
  // Reads "schema_version" and returns it; throws unless it lies in [oldest, newest] (the message
  // names the version found and the ones this gmslab reads). oldest = 0 means newest only.
  int schema_version(int newest, int oldest = 0);
  std::string string(const std::string& key);
  std::string opt_string(const std::string& key, const std::string& fallback);
  std::string choice(const std::string& key, const std::vector<std::string>& allowed);
  bool boolean(const std::string& key);
  JsonReader object(const std::string& key);
  std::vector<JsonReader> array_of_objects(const std::string& key, std::size_t min_size = 0,
                                           std::size_t max_size = SIZE_MAX);
  std::vector<double> numbers(const std::string& key, std::size_t min_size = 0,
                              std::size_t max_size = SIZE_MAX);
  const nlohmann::json& raw(const std::string& key);  // marks it read, no checks

  // Throws for keys present but never read.
  void finish() const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // Throws for this object as a whole ("file: key 'friction': what"), for cross-field problems.
  [[noreturn]] void fail_object(const std::string& what) const;

 private:
  const nlohmann::json& get(const std::string& key, const char* expected);
  const nlohmann::json& j_;
  std::string file_;
  std::string path_;
  mutable std::set<std::string> used_;  // keys read or asked about (the allowed set)
};

// Parses text as JSON; syntax errors become InputError with file, line and column.
nlohmann::json parse_json(const std::string& text, const std::string& file);

}  // namespace gmslab

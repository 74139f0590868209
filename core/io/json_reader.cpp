#include "core/io/json_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "core/error.hpp"

namespace gmslab {

namespace {
std::string num(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}
std::string type_name(const nlohmann::json& j) {
  return j.is_null() ? "null" : std::string(j.type_name());
}
}  // namespace

JsonReader::JsonReader(const nlohmann::json& j, std::string file, std::string path)
    : j_(j), file_(std::move(file)), path_(std::move(path)) {
  if (!j_.is_object())
    throw InputError(file_ + ": " + (path_.empty() ? "the document" : "key '" + path_ + "'") +
                     " must be a JSON object, got " + type_name(j_));
}

std::string JsonReader::where(const std::string& key) const {
  return file_ + ": key '" + (path_.empty() ? key : path_ + "." + key) + "'";
}

bool JsonReader::has(const std::string& key) const {
  used_.insert(key);
  return j_.contains(key);
}

void JsonReader::fail(const std::string& key, const std::string& what) const {
  throw InputError(where(key) + ": " + what);
}

void JsonReader::fail_object(const std::string& what) const {
  throw InputError(file_ + ": " + (path_.empty() ? "the document" : "key '" + path_ + "'") + ": " +
                   what);
}

const nlohmann::json& JsonReader::get(const std::string& key, const char* expected) {
  used_.insert(key);
  const auto it = j_.find(key);
  if (it == j_.end()) fail(key, std::string("missing (expected ") + expected + ")");
  return *it;
}

const nlohmann::json& JsonReader::raw(const std::string& key) { return get(key, "a value"); }

double JsonReader::number(const std::string& key, double lo, double hi, const std::string& unit,
                          bool lo_open) {
  const std::string range =
      (lo_open ? "(" : "[") + num(lo) + ", " + num(hi) + "]" + (unit.empty() ? "" : " " + unit);
  const auto& v = get(key, ("a number in " + range).c_str());
  if (v.is_string())
    fail(key, "expected a number in " + range + ", got the text \"" + v.get<std::string>().substr(0, 40) +
                  "\" (write the number without quotes or units)");
  if (!v.is_number()) fail(key, "expected a number in " + range + ", got " + type_name(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(key, "must be finite, expected a number in " + range);
  if ((lo_open ? !(x > lo) : !(x >= lo)) || x > hi)
    fail(key, num(x) + " is outside the allowed range " + range);
  return x;
}

std::optional<double> JsonReader::opt_number(const std::string& key, double lo, double hi,
                                             const std::string& unit, bool lo_open) {
  if (!has(key)) return std::nullopt;
  return number(key, lo, hi, unit, lo_open);
}

long long JsonReader::integer(const std::string& key, long long lo, long long hi) {
  const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const auto& v = get(key, ("an integer in " + range).c_str());
  if (!v.is_number_integer()) fail(key, "expected an integer in " + range + ", got " +
                                            (v.is_number() ? "a fractional number" : type_name(v)));
  const long long x = v.is_number_unsigned() && v.get<unsigned long long>() > (1ull << 62)
                          ? (1ll << 62)
                          : v.get<long long>();
  if (x < lo || x > hi) fail(key, std::to_string(x) + " is outside the allowed range " + range);
  return x;
}

int JsonReader::schema_version(int newest, int oldest) {
  if (oldest <= 0) oldest = newest;
  const auto version = integer("schema_version", 1, 1000);
  if (version < oldest || version > newest)
    fail("schema_version",
         "version " + std::to_string(version) + " is not supported; this gmslab reads version " +
             (oldest == newest ? std::to_string(newest)
                               : std::to_string(oldest) + " to " + std::to_string(newest)));
  return static_cast<int>(version);
}

std::string JsonReader::string(const std::string& key) {
  const auto& v = get(key, "a string");
  if (!v.is_string()) fail(key, "expected a string, got " + type_name(v));
  return v.get<std::string>();
}

std::string JsonReader::opt_string(const std::string& key, const std::string& fallback) {
  return has(key) ? string(key) : fallback;
}

std::string JsonReader::choice(const std::string& key, const std::vector<std::string>& allowed) {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  const auto& v = get(key, ("one of: " + list).c_str());
  if (!v.is_string()) fail(key, "expected one of: " + list + "; got " + type_name(v));
  const auto s = v.get<std::string>();
  for (const auto& a : allowed)
    if (a == s) return s;
  fail(key, "'" + s + "' is not allowed; expected one of: " + list);
}

bool JsonReader::boolean(const std::string& key) {
  const auto& v = get(key, "true or false");
  if (!v.is_boolean()) fail(key, "expected true or false, got " + type_name(v));
  return v.get<bool>();
}

JsonReader JsonReader::object(const std::string& key) {
  const auto& v = get(key, "an object");
  if (!v.is_object()) fail(key, "expected an object, got " + type_name(v));
  return JsonReader(v, file_, path_.empty() ? key : path_ + "." + key);
}

std::vector<JsonReader> JsonReader::array_of_objects(const std::string& key, std::size_t min_size,
                                                     std::size_t max_size) {
  const auto& v = get(key, "an array of objects");
  if (!v.is_array()) fail(key, "expected an array of objects, got " + type_name(v));
  if (v.size() < min_size || v.size() > max_size)
    fail(key, "has " + std::to_string(v.size()) + " entries; allowed " + std::to_string(min_size) +
                  " to " + std::to_string(max_size));
  std::vector<JsonReader> out;
  const std::string base = path_.empty() ? key : path_ + "." + key;
  for (std::size_t i = 0; i < v.size(); ++i)
    out.emplace_back(v[i], file_, base + "[" + std::to_string(i) + "]");
  return out;
}

std::vector<double> JsonReader::numbers(const std::string& key, std::size_t min_size,
                                        std::size_t max_size) {
  const auto& v = get(key, "an array of numbers");
  if (!v.is_array()) fail(key, "expected an array of numbers, got " + type_name(v));
  if (v.size() < min_size || v.size() > max_size)
    fail(key, "has " + std::to_string(v.size()) + " entries; allowed " + std::to_string(min_size) +
                  " to " + std::to_string(max_size));
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number())
      fail(key + "[" + std::to_string(i) + "]", "expected a number, got " + type_name(v[i]));
    const double x = v[i].get<double>();
    if (!std::isfinite(x)) fail(key + "[" + std::to_string(i) + "]", "must be finite");
    out.push_back(x);
  }
  return out;
}

void JsonReader::finish() const {
  for (const auto& [k, _] : j_.items()) {
    if (!used_.count(k)) {
      std::string known;
      for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
      fail(k, "unknown key (allowed here: " + known + ")");
    }
  }
}

namespace {
// "file:line:col" of byte offset pos in text (1-based line and column).
std::string location(const std::string& text, std::size_t pos, const std::string& file) {
  pos = std::min(pos, text.size());
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return file + ":" + std::to_string(line) + ":" + std::to_string(col);
}

// A hint on what would be accepted, for the syntax errors people actually make. `pos` is the byte
// offset where the parser stopped.
std::string syntax_hint(const std::string& text, std::size_t pos, const std::string& what) {
  std::size_t a = std::min(pos, text.size());
  while (a > 0 && (std::isalpha(static_cast<unsigned char>(text[a - 1])) || text[a - 1] == '-' ||
                   text[a - 1] == '+'))
    --a;
  std::string word;
  for (std::size_t i = a; i < text.size() && word.size() < 4; ++i)
    if (text[i] != '-' && text[i] != '+') word += static_cast<char>(std::tolower(text[i]));
  if (word.rfind("nan", 0) == 0 || word.rfind("inf", 0) == 0)
    return " (JSON has no NaN or Infinity; every value must be a finite number)";
  if (pos + 1 >= text.size())
    return " (the file ends in the middle of a value: is it truncated?)";
  if (what.find("UTF-8") != std::string::npos) return " (the file must be UTF-8 text, as JSON requires)";
  return "";
}
}  // namespace

nlohmann::json parse_json(const std::string& text, const std::string& file) {
  if (text.empty()) throw InputError(file + ": the file is empty (expected a JSON object)");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    if (const auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
    const std::size_t pos = e.byte == 0 ? 0 : e.byte - 1;
    throw InputError(location(text, pos, file) + ": malformed JSON: " + what +
                     syntax_hint(text, pos, what));
  } catch (const nlohmann::json::exception& e) {
    // out_of_range 406: a number such as 1e999 that no double can hold. The message quotes the
    // token; locate its first occurrence for the line and column.
    std::string what = e.what();
    std::size_t pos = 0;
    if (const auto a = what.find('\''), b = what.rfind('\''); a != std::string::npos && b > a)
      pos = std::min(text.find(what.substr(a + 1, b - a - 1)), text.size());
    if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    throw InputError(location(text, pos, file) + ": " + what +
                     " (numbers must be finite doubles, |x| < 1.8e308)");
  }
}

}  // namespace gmslab

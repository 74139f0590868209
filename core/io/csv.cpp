#include "core/io/csv.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"

namespace gmslab {

namespace {

struct Unit {
  std::string_view suffix;
  double scale;  // SI value = file value * scale
};

// A name a role is found by: `text` exactly (single letters: t, x, F, v, Fn) or in any case (words:
// time, position, force, ...). `force` tells which force an F name is (ForceKind).
enum class ForceKind { measured, friction, applied };
struct Alias {
  std::string_view text;
  bool any_case;
  ForceKind force = ForceKind::measured;
};

struct Role {
  std::string_view name;  // t, x, F, v, Fn
  bool required;
  std::vector<Unit> units;
  std::vector<Alias> aliases;
  std::string_view quantity;  // "time", "length", "force", "velocity" (F and Fn share "force")
};

const std::array<Role, 5>& roles() {
  static const std::array<Role, 5> r = {{
      {"t", true, {{"s", 1.0}, {"ms", 1e-3}, {"us", 1e-6}, {"\xC2\xB5" "s", 1e-6}},
       {{"t", false}, {"time", true}}, "time"},
      {"x", true, {{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"um", 1e-6}, {"\xC2\xB5" "m", 1e-6}, {"nm", 1e-9}},
       {{"x", false}, {"pos", true}, {"position", true}}, "length"},
      {"F", true, {{"N", 1.0}, {"kN", 1e3}, {"mN", 1e-3}},
       {{"F", false}, {"force", true}, {"F_friction", false, ForceKind::friction},
        {"F_applied", false, ForceKind::applied}}, "force"},
      {"v", false, {{"mps", 1.0}, {"mmps", 1e-3}, {"umps", 1e-6}, {"m/s", 1.0}, {"mm/s", 1e-3}, {"um/s", 1e-6},
                    {"\xC2\xB5" "m/s", 1e-6}},
       {{"v", false}, {"vel", true}, {"velocity", true}}, "velocity"},
      {"Fn", false, {{"N", 1.0}, {"kN", 1e3}, {"mN", 1e-3}},
       {{"Fn", false}, {"normal_force", true}}, "force"},
  }};
  return r;
}

std::string units_text(const Role& r) {
  std::string s;
  for (const auto& u : r.units) s += (s.empty() ? "" : ", ") + std::string(u.suffix);
  return s;
}

bool equal_any_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

// What a column name says about itself: its role (by an alias), which force it is, and its unit
// as written: NAME, NAME_UNIT, NAME [UNIT], NAME (UNIT), NAME[UNIT], NAME(UNIT).
struct NameInfo {
  int role = -1;  // index into roles(), -1: not a role's name
  ForceKind force = ForceKind::measured;
  std::string_view base, unit;  // unit "" = none written
  bool bracketed = false;       // the unit was written in brackets (so it is meant as a unit)
};

// Splits a name into base and unit: a trailing [UNIT] or (UNIT), else the part after the last '_'.
NameInfo split_unit(std::string_view h) {
  NameInfo n;
  n.base = h;
  if (!h.empty() && (h.back() == ']' || h.back() == ')')) {
    const char open = h.back() == ']' ? '[' : '(';
    const auto o = h.rfind(open);
    if (o != std::string_view::npos && o > 0) {
      n.base = h.substr(0, o);
      while (!n.base.empty() && (n.base.back() == ' ' || n.base.back() == '_')) n.base.remove_suffix(1);
      n.unit = h.substr(o + 1, h.size() - o - 2);
      while (!n.unit.empty() && n.unit.front() == ' ') n.unit.remove_prefix(1);
      while (!n.unit.empty() && n.unit.back() == ' ') n.unit.remove_suffix(1);
      n.bracketed = true;
      return n;
    }
  }
  const auto u = h.rfind('_');
  if (u != std::string_view::npos && u > 0) {
    n.base = h.substr(0, u);
    n.unit = h.substr(u + 1);
  }
  return n;
}

double unit_scale(std::size_t r, std::string_view unit);
std::string_view quantity_of(std::string_view unit);

// The role a column name names: the longest alias that is the whole name or the name's base
// (so "F_friction_N" is the friction force in N, "Fn_N" the normal force, "F1_N" no role).
NameInfo name_info(std::string_view h) {
  NameInfo best;
  std::size_t best_len = 0;
  for (std::size_t r = 0; r < roles().size(); ++r) {
    for (const auto& a : roles()[r].aliases) {
      if (h.size() < a.text.size() || a.text.size() <= best_len) continue;
      const auto head = h.substr(0, a.text.size());
      if (a.any_case ? !equal_any_case(head, a.text) : head != a.text) continue;
      NameInfo n;
      n.base = head;
      const auto rest = h.substr(a.text.size());
      if (!rest.empty()) {
        // The unit follows as _UNIT, [UNIT], (UNIT), with optional spaces before a bracket.
        auto tail = rest;
        while (!tail.empty() && tail.front() == ' ') tail.remove_prefix(1);
        if (!tail.empty() && tail.front() == '_' && tail.size() > 1 && tail == rest) {
          n.unit = tail.substr(1);
          // A word followed by _WORD that is no unit names something else ("force_sensor",
          // "time_stamp", "position_cmd_m"): not this role. A letter's suffix is meant as a unit
          // ("x_in": an unknown unit, an error).
          if (a.any_case && unit_scale(r, n.unit) == 0.0 && quantity_of(n.unit).empty()) continue;
        } else if (tail.size() >= 2 && ((tail.front() == '[' && tail.back() == ']') ||
                                         (tail.front() == '(' && tail.back() == ')'))) {
          n.unit = tail.substr(1, tail.size() - 2);
          while (!n.unit.empty() && n.unit.front() == ' ') n.unit.remove_prefix(1);
          while (!n.unit.empty() && n.unit.back() == ' ') n.unit.remove_suffix(1);
          n.bracketed = true;
        } else {
          continue;  // "F1_N", "timestamp", "position2": not this alias
        }
      }
      n.role = static_cast<int>(r);
      n.force = a.force;
      best = n;
      best_len = a.text.size();
    }
  }
  return best;
}

// The SI scale of `unit` for role r, or 0 when r does not take it.
double unit_scale(std::size_t r, std::string_view unit) {
  if (unit.empty()) return 1.0;
  for (const auto& u : roles()[r].units)
    if (u.suffix == unit) return u.scale;
  return 0.0;
}

// The quantity `unit` measures ("force" for N), or "" when it is no role's unit.
std::string_view quantity_of(std::string_view unit) {
  for (const auto& role : roles())
    for (const auto& u : role.units)
      if (u.suffix == unit) return role.quantity;
  return {};
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

// Line number (1-based) and byte of the first invalid UTF-8 sequence, if any.
std::optional<std::size_t> first_bad_utf8(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  const std::size_t n = s.size();
  std::size_t i = 0;
  while (i < n) {
    const unsigned c = p[i];
    if (c < 0x80) { ++i; continue; }
    std::size_t len = 0;
    unsigned min = 0;
    if ((c & 0xE0) == 0xC0) { len = 2; min = 0x80; }
    else if ((c & 0xF0) == 0xE0) { len = 3; min = 0x800; }
    else if ((c & 0xF8) == 0xF0 && c <= 0xF4) { len = 4; min = 0x10000; }
    else return i;
    if (i + len > n) return i;
    unsigned cp = c & (0xFF >> (len + 1));
    for (std::size_t k = 1; k < len; ++k) {
      if ((p[i + k] & 0xC0) != 0x80) return i;
      cp = (cp << 6) | (p[i + k] & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return i;
    i += len;
  }
  return std::nullopt;
}

std::size_t line_of(std::string_view s, std::size_t pos) {
  std::size_t line = 1;
  for (std::size_t i = 0; i < pos && i < s.size(); ++i) line += (s[i] == '\n');
  return line;
}

std::string where(const std::string& file, std::size_t line) {
  return file + ":" + std::to_string(line);
}

// Splits one line into fields at `sep` (no quoting inside number rows); sep == ' ' splits at
// runs of spaces and tabs.
void split_fields(std::string_view line, std::vector<std::string_view>& out, char sep = ',') {
  out.clear();
  if (sep == ' ') {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i >= line.size()) break;
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      out.push_back(trim(line.substr(i, j - i)));
      i = j;
    }
    return;
  }
  std::size_t start = 0;
  for (;;) {
    const auto c = line.find(sep, start);
    if (c == std::string_view::npos) {
      out.push_back(trim(line.substr(start)));
      return;
    }
    out.push_back(trim(line.substr(start, c - start)));
    start = c + 1;
  }
}

// A number in the file's dialect: decimal point, or decimal comma when `decimal` is ','.
bool parse_number(std::string_view f, double& out, char decimal = '.') {
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);
  if (f.empty()) return false;
  if (decimal == ',') {
    if (f.size() > 64 || f.find('.') != std::string_view::npos) return false;
    char buf[64];
    for (std::size_t i = 0; i < f.size(); ++i) buf[i] = f[i] == ',' ? '.' : f[i];
    const auto r = std::from_chars(buf, buf + f.size(), out);
    return r.ec == std::errc() && r.ptr == buf + f.size();
  }
  const auto r = std::from_chars(f.data(), f.data() + f.size(), out);
  return r.ec == std::errc() && r.ptr == f.data() + f.size();
}

bool is_comment(std::string_view tl) {
  return tl.empty() || tl.front() == '#' || tl.front() == '%' || tl.substr(0, 2) == "//";
}

bool all_numbers(const std::vector<std::string_view>& fields, char decimal) {
  double d = 0.0;
  for (const auto f : fields)
    if (!parse_number(f, d, decimal)) return false;
  return !fields.empty();
}

// Finds the separator and decimal mark from the first non-comment lines: the candidate under
// which the lines split into the same number of fields (>= 2) and the most fields are numbers;
// ties go to the earlier candidate (semicolon, tab, comma, whitespace; decimal point first).
// When no candidate splits the lines consistently, comma (then the row checks name the line).
CsvDialect detect(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  while (pos < text.size() && lines.size() < 30) {
    auto nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!is_comment(trim(line))) lines.push_back(line);
  }
  static constexpr std::array<CsvDialect, 7> candidates = {{
      {';', '.'}, {';', ','}, {'\t', '.'}, {'\t', ','}, {',', '.'}, {' ', '.'}, {' ', ','}}};
  CsvDialect best{',', '.'};
  long best_score = 0;
  std::vector<std::string_view> f;
  for (const auto& c : candidates) {
    if (lines.empty()) break;
    split_fields(lines[lines.size() > 1 ? 1 : 0], f, c.separator);
    const std::size_t n = f.size();
    if (n < 2) continue;
    split_fields(lines[0], f, c.separator);
    if (f.size() != n) continue;
    long score = 1;  // a consistent split beats none
    double d = 0.0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
      split_fields(lines[i], f, c.separator);
      if (f.size() != n) continue;
      for (const auto x : f) score += parse_number(x, d, c.decimal) ? 1 : 0;
    }
    if (score > best_score) {
      best_score = score;
      best = c;
    }
  }
  return best;
}

struct Chosen {
  std::ptrdiff_t index = -1;  // column in the file
  double scale = 1.0;
};

// Where the names came from, for messages: a CSV header (or its absence) or a MATLAB file.
struct NameSource {
  std::string loc;          // "file:line" of the header, or the file
  bool mat = false;         // names are MATLAB variables ("var" or "var:COLUMN")
  bool headerless = false;  // a CSV without a header row: names are positions "1", "2", ...
};

bool all_digits(std::string_view s) {
  if (s.empty() || s.size() > 6) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// The SI scale of the column `h` mapped to role r (by name or position): its unit as written
// (NAME_UNIT, NAME [UNIT], NAME (UNIT)). A unit of another quantity, or an unknown unit in brackets
// or on a role's name, is an error; NAME_WORD where WORD is no unit (pos_raw, data:2, 3) is SI.
double mapped_scale(std::string_view h, std::size_t r, const std::string& noun, const NameSource& src) {
  const Role& role = roles()[r];
  const NameInfo named = name_info(h);
  if (named.role >= 0 && roles()[static_cast<std::size_t>(named.role)].quantity != role.quantity)
    throw InputError(src.loc + ": " + noun + " '" + std::string(h) + "' is mapped to " + std::string(role.name) +
                     " (" + std::string(role.quantity) + "), but its name says " +
                     std::string(roles()[static_cast<std::size_t>(named.role)].name) + " (" +
                     std::string(roles()[static_cast<std::size_t>(named.role)].quantity) + ")");
  const NameInfo n = named.role >= 0 ? named : split_unit(h);
  const double scale = unit_scale(r, n.unit);
  if (scale > 0.0) return scale;
  const auto q = quantity_of(n.unit);
  if (!q.empty())
    throw InputError(src.loc + ": " + noun + " '" + std::string(h) + "' is mapped to " + std::string(role.name) +
                     " (" + std::string(role.quantity) + "), but its unit '" + std::string(n.unit) + "' is a " +
                     std::string(q) + " unit; accepted for " + std::string(role.name) + ": " + units_text(role));
  if (n.bracketed)
    throw InputError(src.loc + ": " + noun + " '" + std::string(h) + "' (mapped to " + std::string(role.name) +
                     "): unknown unit '" + std::string(n.unit) + "'; accepted: " + units_text(role));
  return 1.0;
}

const char* force_name(ForceKind k) {
  return k == ForceKind::friction ? "friction" : k == ForceKind::applied ? "applied" : "measured";
}

// Finds the column of each role, by explicit name (or 1-based position in a CSV) or by name and
// unit (NAME, NAME_UNIT, NAME [UNIT], NAME (UNIT); Role::aliases). Every chosen column keeps the
// unit its name gives, however it was chosen. One column for two roles is an error.
std::array<Chosen, 5> choose_columns(const std::vector<std::string_view>& header,
                                     const CsvColumns& cols, const NameSource& src) {
  const std::array<const std::string*, 5> explicit_names = {&cols.t, &cols.x, &cols.F, &cols.v,
                                                            &cols.Fn};
  const std::string noun = src.mat ? "variable" : "column";
  std::string names;
  for (const auto& h : header) names += (names.empty() ? "" : ", ") + std::string(h);
  if (src.headerless && (cols.t.empty() || cols.x.empty() || cols.F.empty()))
    throw InputError(src.loc + ": the first row holds numbers, so the file has no header row; give the " +
                     std::to_string(header.size()) +
                     " columns by position (1-based), e.g. --columns t=1,x=2,F=3 (optional v=, Fn=)");
  // Which force F is: unset = the measured force (F, force) or a trace's friction force.
  std::optional<ForceKind> want_force;
  if (!cols.force.empty()) {
    if (cols.force == "friction") want_force = ForceKind::friction;
    else if (cols.force == "applied") want_force = ForceKind::applied;
    else throw InputError("--force '" + cols.force + "': expected friction or applied");
    if (!cols.F.empty())
      throw InputError("--force " + cols.force + " and --columns F=" + cols.F +
                       " both choose the force column; give one of them");
  }
  std::array<Chosen, 5> out;
  for (std::size_t r = 0; r < 5; ++r) {
    const Role& role = roles()[r];
    if (!explicit_names[r]->empty()) {
      const std::string& want = *explicit_names[r];
      for (std::size_t c = 0; c < header.size(); ++c)
        if (header[c] == want) out[r].index = static_cast<std::ptrdiff_t>(c);
      if (out[r].index < 0 && !src.mat && all_digits(want)) {
        const auto k = std::stoul(want);
        if (k >= 1 && k <= header.size()) out[r].index = static_cast<std::ptrdiff_t>(k - 1);
      }
      if (out[r].index < 0) {
        if (src.mat)
          throw InputError(src.loc + ": no numeric vector or matrix column '" + want + "' (mapped to " +
                           std::string(role.name) + "); accepted: a variable name (a vector) or NAME:COLUMN " +
                           "(a column of a matrix, 1-based); the file has: " + (names.empty() ? "nothing usable" : names));
        throw InputError(src.loc + ": column '" + want + "' (mapped to " + std::string(role.name) +
                         ") is not in the header" +
                         (src.headerless ? "" : " and is not a position 1.." + std::to_string(header.size())) +
                         "; columns: " + names);
      }
      out[r].scale = src.headerless ? 1.0
                                    : mapped_scale(header[static_cast<std::size_t>(out[r].index)], r, noun, src);
      continue;
    }
    std::string skipped_forces;  // F columns of another force than the one wanted (for the message)
    for (std::size_t c = 0; c < header.size(); ++c) {
      const NameInfo n = name_info(header[c]);
      if (n.role != static_cast<int>(r)) continue;
      if (r == 2 && (want_force ? n.force != *want_force : n.force == ForceKind::applied)) {
        skipped_forces += (skipped_forces.empty() ? "'" : ", '") + std::string(header[c]) + "' (" +
                          force_name(n.force) + ")";
        continue;
      }
      const double scale = unit_scale(r, n.unit);
      if (scale == 0.0)
        throw InputError(src.loc + ": " + noun + " '" + std::string(header[c]) + "': unknown unit '" +
                         std::string(n.unit) + "'; accepted: " + std::string(n.base) + " (SI) or " +
                         std::string(n.base) + " with a unit of " + units_text(role) +
                         " (as " + std::string(n.base) + "_UNIT, " + std::string(n.base) + " [UNIT] or " +
                         std::string(n.base) + " (UNIT)), or map it with --columns");
      if (out[r].index >= 0)
        throw InputError(src.loc + ": two " + noun + "s for " + std::string(role.name) + " ('" +
                         std::string(header[static_cast<std::size_t>(out[r].index)]) + "' and '" +
                         std::string(header[c]) + "'); choose one with --columns " +
                         std::string(role.name) + "=NAME");
      out[r] = {static_cast<std::ptrdiff_t>(c), scale};
    }
    if (out[r].index >= 0 || !(role.required || (r == 2 && want_force))) continue;
    if (r == 2 && want_force)
      throw InputError(src.loc + ": --force " + cols.force + ": no " + noun + " for the " + cols.force +
                       " force (expected F_" + cols.force + " or F_" + cols.force + "_N, as gmslab simulate writes); " +
                       noun + "s: " + (names.empty() ? "none" : names));
    throw InputError(src.loc + ": no " + noun + " for " + std::string(role.name) + " (expected " +
                     (src.mat ? "a variable" : "a header") + " named " + std::string(role.name) + " or " +
                     std::string(role.name) + "_UNIT, " + std::string(role.name) + " [UNIT] with a unit of " +
                     units_text(role) + (role.aliases.size() > 1 ? ", or " + std::string(role.aliases[1].text) : std::string()) +
                     ", or --columns " + std::string(role.name) + "=" +
                     (src.mat ? "VARIABLE or VARIABLE:COLUMN" : "NAME or POSITION") + "); " + noun +
                     "s: " + (names.empty() ? "none" : names) +
                     (skipped_forces.empty() ? "" : "; " + skipped_forces + ": choose it with --force"));
  }
  for (std::size_t a = 0; a < 5; ++a)
    for (std::size_t b = a + 1; b < 5; ++b)
      if (out[a].index >= 0 && out[a].index == out[b].index)
        throw InputError(src.loc + ": " + noun + " '" + std::string(header[static_cast<std::size_t>(out[a].index)]) +
                         "' is mapped to both " + std::string(roles()[a].name) + " and " +
                         std::string(roles()[b].name) + "; one " + noun + " can have one role (--columns)");
  return out;
}

}  // namespace

CsvDialect detect_dialect(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  return detect(text);
}

std::string describe(const CsvDialect& d) {
  const std::string sep = d.separator == ';'    ? "semicolon"
                          : d.separator == '\t' ? "tab"
                          : d.separator == ' '  ? "whitespace"
                                                : "comma";
  return sep + "-separated, decimal " + (d.decimal == ',' ? "comma" : "point");
}

const std::vector<double>* MeasuredRecord::extra_column(std::string_view name) const {
  for (const auto& [n, col] : extra)
    if (n == name) return &col;
  return nullptr;
}

CsvColumns parse_column_map(std::string_view spec) {
  CsvColumns c;
  std::vector<std::string_view> items;
  split_fields(spec, items);
  for (auto item : items) {
    const auto eq = item.find('=');
    const auto role = eq == std::string_view::npos ? item : trim(item.substr(0, eq));
    const auto name = eq == std::string_view::npos ? std::string_view{} : trim(item.substr(eq + 1));
    std::string* slot = role == "t"    ? &c.t
                        : role == "x"  ? &c.x
                        : role == "F"  ? &c.F
                        : role == "v"  ? &c.v
                        : role == "Fn" ? &c.Fn
                                       : nullptr;
    if (!slot || name.empty())
      throw InputError("--columns: '" + std::string(item) +
                       "': expected ROLE=NAME with ROLE one of t, x, F, v, Fn, e.g. t=t_s,x=x_m,F=F_N");
    if (!slot->empty())
      throw InputError("--columns: " + std::string(role) + " is given twice ('" + std::string(role) + "=" + *slot +
                       "' and '" + std::string(item) + "'); give each role once");
    *slot = std::string(name);
  }
  return c;
}

MeasuredRecord parse_measured_csv(std::string_view text, const std::string& file,
                                  const CsvColumns& columns) {
  if (const auto bad = first_bad_utf8(text))
    throw InputError(where(file, line_of(text, *bad)) +
                     ": the file is not UTF-8 text (invalid byte sequence); save it as UTF-8 CSV");
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);

  const CsvDialect dialect = detect(text);
  const char sep = dialect.separator, dec = dialect.decimal;
  MeasuredRecord rec;
  rec.source = file;
  rec.dialect = dialect;
  std::vector<std::string> position_names;  // "1", "2", ... of a file without a header row
  std::vector<std::string_view> header, fields;
  std::array<Chosen, 5> chosen{};
  std::vector<std::vector<double>> extra_vals;
  std::vector<std::size_t> extra_idx;
  std::vector<bool> extra_ok;
  std::size_t header_line = 0;
  std::size_t line_no = 0;
  std::size_t pos = 0;
  std::vector<double> vals(5, 0.0);
  while (pos < text.size()) {
    auto nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto tl = trim(line);
    if (is_comment(tl)) continue;
    if (header_line == 0) {
      header_line = line_no;
      split_fields(line, header, sep);
      NameSource src{where(file, line_no), false, all_numbers(header, dec)};
      if (src.headerless) {
        for (std::size_t c = 0; c < header.size(); ++c) position_names.push_back(std::to_string(c + 1));
        header.assign(position_names.begin(), position_names.end());
      }
      chosen = choose_columns(header, columns, src);
      for (std::size_t c = 0; c < header.size(); ++c) {
        bool used = false;
        for (const auto& ch : chosen) used |= ch.index == static_cast<std::ptrdiff_t>(c);
        if (!used && !header[c].empty()) extra_idx.push_back(c);
      }
      extra_vals.resize(extra_idx.size());
      extra_ok.assign(extra_idx.size(), true);
      rec.has_header = !src.headerless;
      if (rec.has_header) continue;  // else this first line is the first data row
    }
    split_fields(line, fields, sep);
    if (fields.size() != header.size())
      throw InputError(where(file, line_no) + ": " + std::to_string(fields.size()) +
                       " fields, but " + (rec.has_header ? "the header has " : "the first row has ") +
                       std::to_string(header.size()) +
                       " (truncated or malformed row)");
    for (std::size_t r = 0; r < 5; ++r) {
      if (chosen[r].index < 0) continue;
      const auto f = fields[static_cast<std::size_t>(chosen[r].index)];
      const std::string col(header[static_cast<std::size_t>(chosen[r].index)]);
      double d = 0.0;
      if (!parse_number(f, d, dec))
        throw InputError(where(file, line_no) + ": column '" + col + "': '" +
                         std::string(f.substr(0, 40)) + "' is not a number (the file reads as " + describe(dialect) + ")");
      if (!std::isfinite(d))
        throw InputError(where(file, line_no) + ": column '" + col + "': '" + std::string(f) +
                         "' is not a finite number");
      vals[r] = d * chosen[r].scale;
      if (!std::isfinite(vals[r]))  // finite in the file's unit, not in SI (e.g. 1e306 kN)
        throw InputError(where(file, line_no) + ": column '" + col + "': '" + std::string(f) +
                         "' overflows when converted to SI units (scale " +
                         std::to_string(chosen[r].scale) + ")");
    }
    if (!rec.t.empty() && !(vals[0] > rec.t.back()))
      throw InputError(where(file, line_no) + ": column '" +
                       std::string(header[static_cast<std::size_t>(chosen[0].index)]) +
                       "': time " + std::string(fields[static_cast<std::size_t>(chosen[0].index)]) +
                       " is not greater than the previous row's; time must strictly increase");
    rec.t.push_back(vals[0]);
    rec.x.push_back(vals[1]);
    rec.F.push_back(vals[2]);
    if (chosen[3].index >= 0) rec.v.push_back(vals[3]);
    if (chosen[4].index >= 0) rec.Fn.push_back(vals[4]);
    for (std::size_t e = 0; e < extra_idx.size(); ++e) {
      if (!extra_ok[e]) continue;
      double d = 0.0;
      if (parse_number(fields[extra_idx[e]], d, dec) && std::isfinite(d)) extra_vals[e].push_back(d);
      else extra_ok[e] = false;
    }
  }
  if (header_line == 0)
    throw InputError(file + ": empty; expected a header row (e.g. t_s,x_m,F_N) or none (then --columns t=1,x=2,F=3) and at least " +
                     std::to_string(kMinSamples) +
                     " rows of numbers separated by commas, semicolons, tabs or spaces");
  if (rec.t.size() < kMinSamples)
    throw InputError(file + ": only " + std::to_string(rec.t.size()) + " data rows; at least " +
                     std::to_string(kMinSamples) + " are needed");
  rec.force_column = std::string(header[static_cast<std::size_t>(chosen[2].index)]);
  for (std::size_t e = 0; e < extra_idx.size(); ++e)
    if (extra_ok[e]) rec.extra.emplace_back(std::string(header[extra_idx[e]]), std::move(extra_vals[e]));
  return rec;
}

MeasuredRecord record_from_columns(const std::vector<NamedColumn>& columns, const CsvColumns& map,
                                   const std::string& file, const std::string& unusable) {
  std::vector<std::string_view> names;
  for (const auto& c : columns) names.push_back(c.name);
  NameSource src{file, true, false};
  std::array<Chosen, 5> chosen{};
  try {
    chosen = choose_columns(names, map, src);
  } catch (const InputError& e) {
    if (unusable.empty()) throw;
    throw InputError(std::string(e.what()) + " (not numeric vectors or matrices, so not usable: " + unusable + ")");
  }
  MeasuredRecord rec;
  rec.source = file;
  const auto& tcol = columns[static_cast<std::size_t>(chosen[0].index)];
  const std::size_t n = tcol.values.size();
  std::array<std::vector<double>*, 5> dest = {&rec.t, &rec.x, &rec.F, &rec.v, &rec.Fn};
  for (std::size_t r = 0; r < 5; ++r) {
    if (chosen[r].index < 0) continue;
    const auto& col = columns[static_cast<std::size_t>(chosen[r].index)];
    if (col.values.size() != n)
      throw InputError(file + ": variable '" + col.name + "' (" + std::string(roles()[r].name) + ") has " +
                       std::to_string(col.values.size()) + " values but '" + tcol.name + "' (t) has " +
                       std::to_string(n) + "; the chosen variables must have the same length");
    dest[r]->reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double d = col.values[k] * chosen[r].scale;
      if (!std::isfinite(d))
        throw InputError(file + ": variable '" + col.name + "' element " + std::to_string(k + 1) +
                         ": not a finite number in SI units (NaN, Inf or overflow)");
      if (r == 0 && k > 0 && !(d > rec.t.back()))
        throw InputError(file + ": variable '" + col.name + "' element " + std::to_string(k + 1) +
                         ": time is not greater than the previous element's; time must strictly increase");
      dest[r]->push_back(d);
    }
  }
  if (n < kMinSamples)
    throw InputError(file + ": only " + std::to_string(n) + " samples in '" + tcol.name + "'; at least " +
                     std::to_string(kMinSamples) + " are needed");
  rec.force_column = columns[static_cast<std::size_t>(chosen[2].index)].name;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    bool used = false;
    for (const auto& ch : chosen) used |= ch.index == static_cast<std::ptrdiff_t>(c);
    if (used || columns[c].values.size() != n) continue;
    bool ok = true;
    for (double d : columns[c].values) ok &= std::isfinite(d);
    if (ok) rec.extra.emplace_back(columns[c].name, columns[c].values);
  }
  return rec;
}

std::vector<NamedColumn> parse_csv_columns(std::string_view text, const std::string& file) {
  if (const auto bad = first_bad_utf8(text))
    throw InputError(where(file, line_of(text, *bad)) + ": the file is not UTF-8 text (invalid byte sequence)");
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const CsvDialect dialect = detect(text);
  std::vector<NamedColumn> cols;
  std::vector<std::string_view> fields;
  std::size_t line_no = 0, pos = 0;
  while (pos < text.size()) {
    auto nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (is_comment(trim(line))) continue;
    split_fields(line, fields, dialect.separator);
    if (cols.empty()) {
      if (all_numbers(fields, dialect.decimal))
        throw InputError(where(file, line_no) + ": the first row holds numbers; a trace file needs a header row of column names");
      for (const auto f : fields) cols.push_back({std::string(f), {}});
      continue;
    }
    if (fields.size() != cols.size())
      throw InputError(where(file, line_no) + ": " + std::to_string(fields.size()) + " fields, but the header has " +
                       std::to_string(cols.size()) + " (truncated or malformed row)");
    for (std::size_t c = 0; c < cols.size(); ++c) {
      double d = 0.0;
      if (!parse_number(fields[c], d, dialect.decimal))
        throw InputError(where(file, line_no) + ": column '" + cols[c].name + "': '" +
                         std::string(fields[c].substr(0, 40)) + "' is not a number");
      cols[c].values.push_back(d);
    }
  }
  if (cols.empty()) throw InputError(file + ": empty; expected a header row and rows of numbers");
  return cols;
}

MeasuredRecord load_measured_csv(const std::string& path, const CsvColumns& columns) {
  return parse_measured_csv(read_file(path), path, columns);
}

}  // namespace gmslab

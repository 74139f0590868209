// gmslab core: measured friction data from CSV (the input of identification).
//
// Format: UTF-8 text (a UTF-8 byte order mark is skipped), one sample per row; CRLF or LF; blank
// lines and comment lines (starting with '#', '%' or '//') are skipped. The dialect is detected
// from the first rows (detect_dialect): separator comma, semicolon, tab or whitespace (runs of
// spaces/tabs); decimal point, or decimal comma when the separator is not a comma. The first row
// is a header when any of its fields is not a number; a file without one names its columns by
// 1-based position (--columns t=1,x=2,F=4). With a header the columns are found by name:
//   t   time                [s]     (required, strictly increasing; sampling may be non-uniform)
//   x   position            [m]     (required)
//   F   measured force      [N]     (required; friction alone or actuator force, see ident/)
//   v   velocity            [m/s]   (optional; derived from x when absent)
//   Fn  normal force        [N]     (optional; enables the normal_load effect)
// Names: t or time; x, pos or position; F or force; v, vel or velocity; Fn or normal_force (the
// words in any case, the letters as written). A trace of `gmslab simulate` has two forces:
// F_friction_N is read as F, F_applied_N only with CsvColumns::force = "applied" (--force applied).
// The unit follows the name as NAME_UNIT, NAME [UNIT] or NAME (UNIT): t_s, t [ms], x (mm), pos_um,
// F [kN], v [mm/s], ...; values are converted to SI:
//   t: s, ms, us, µs   x: m, cm, mm, um, µm, nm   F, Fn: N, kN, mN
//   v: m/s, mm/s, um/s, µm/s, mps, mmps, umps
// An unknown unit on one of these names is an error naming the accepted units; a word name followed
// by _WORD that is no unit ("force_sensor_V", "time_stamp") names something else and is an extra
// column. Columns may also be
// mapped explicitly ("t=time,x=Weg_mm,F=F_N"; a mapped name that is a number and not a header
// name is a 1-based position). A mapped column keeps the unit its header gives, however it was
// chosen: x=2 on a header "Weg_mm" reads millimetres. Its unit must be one of the role's (x=F_N is
// an error); a mapped name without a unit (or NAME_WORD where WORD is no unit, e.g. pos_raw) is
// read as SI. One column mapped to two roles is an error naming both. Every other column that holds
// only numbers is kept in `extra` under its header name (e.g. pulse_code, a_mps2); other columns
// are ignored.
//
// Errors: InputError naming the file, the line and the column: missing or ambiguous column, text
// in a number field, NaN/inf, a row with too few or too many fields, time not increasing, fewer
// than kMinSamples rows, empty file, bytes that are not UTF-8. Never a crash, never a default.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gmslab {

inline constexpr std::size_t kMinSamples = 10;

// How a CSV file writes its numbers: separator ',', ';', '\t' or ' ' (any run of spaces and
// tabs) and decimal mark '.' or ','.
struct CsvDialect {
  char separator = ',';
  char decimal = '.';
  bool operator==(const CsvDialect&) const = default;
};
// "semicolon-separated, decimal comma" (for messages and reports).
std::string describe(const CsvDialect& d);

struct MeasuredRecord {
  std::string source;      // file name, for messages and reports
  std::vector<double> t;   // time [s]
  std::vector<double> x;   // position [m]
  std::vector<double> F;   // measured force [N]
  std::vector<double> v;   // velocity [m/s]; empty when the file has none
  std::vector<double> Fn;  // normal force [N]; empty when the file has none
  std::vector<std::pair<std::string, std::vector<double>>> extra;  // other numeric columns
  std::string force_column;  // header name the force came from (for reports), e.g. "F_N"
  CsvDialect dialect;        // how the CSV was read (default for other formats)
  bool has_header = true;    // false: a CSV whose columns were given by position

  std::size_t size() const { return t.size(); }
  // The extra column with this header name, or nullptr.
  const std::vector<double>* extra_column(std::string_view name) const;
};

// Explicit column names per role; empty = find by name. A CSV name may be a 1-based position
// ("2"); a MATLAB name is a variable ("q") or a column of a matrix ("data:2").
struct CsvColumns {
  std::string t, x, F, v, Fn;
  // Which force F is when it is found by name: "" = the measured force (F, force) or a trace's
  // friction force (F_friction_N); "friction" or "applied" = that force of a trace (F_applied_N).
  std::string force;
};

// Parses "t=t_s,x=x_m,F=F_N" (roles t, x, F, v, Fn); throws InputError naming the bad entry or a
// role given twice.
CsvColumns parse_column_map(std::string_view spec);

// Parses a whole CSV text (the fuzzable entry point). `file` is used in messages only.
MeasuredRecord parse_measured_csv(std::string_view text, const std::string& file,
                                  const CsvColumns& columns = {});
// Reads and parses a file; throws InputError when it cannot be read or is bad.
MeasuredRecord load_measured_csv(const std::string& path, const CsvColumns& columns = {});
// A numeric column from a non-CSV source (a MATLAB variable, or one column of a matrix variable:
// "data:2"), and the record made from such columns: the roles are chosen like CSV header names
// (names, unit suffixes, the explicit map); the chosen columns must have the same length, finite
// values and a strictly increasing time. Other columns of that length with finite values go to
// `extra`. `unusable` lists what the source holds that is not a numeric column ("s (struct)"),
// for messages. Throws InputError naming the file, the variable and the element.
struct NamedColumn {
  std::string name;
  std::vector<double> values;
};
MeasuredRecord record_from_columns(const std::vector<NamedColumn>& columns, const CsvColumns& map,
                                   const std::string& file, const std::string& unusable = {});

// Every column of a CSV text with a header row, by its header name, in file order (a trace as
// gmslab simulate writes it, in any dialect). Every field must be a number; throws InputError
// naming the file, line and column otherwise.
std::vector<NamedColumn> parse_csv_columns(std::string_view text, const std::string& file);

// The dialect of a CSV text (separator and decimal mark) as parse_measured_csv reads it.
CsvDialect detect_dialect(std::string_view text);

}  // namespace gmslab

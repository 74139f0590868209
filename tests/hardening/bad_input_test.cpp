// The bad-input table of README section `hardening`: one test per row. Every message must name
// the file, the line or key path, and what would be accepted.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <limits>

#include "core/io/csv.hpp"
#include "core/sim/assembly.hpp"
#include "hardening_util.hpp"

namespace gmslab::hardening {
namespace {

using nlohmann::json;

// Fig. 4 preset with one substitution (the substring must exist).
std::string fig4_with(const std::string& from, const std::string& to) {
  std::string s = preset_text("fig4_stick_slip.json");
  const auto p = s.find(from);
  EXPECT_NE(p, std::string::npos) << from;
  return p == std::string::npos ? s : s.replace(p, from.size(), to);
}

// 1-based line of the first occurrence of `what` in `text`.
int line_of(const std::string& text, const std::string& what) {
  const auto p = text.find(what);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(p), '\n'));
}

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << "message: " << (msg)

TEST(BadInput, MissingKeyNamesThePathAndTheRange) {
  const auto msg = load_error("missing.json", fig4_with("\"Fc\": 1.0, ", ""));
  EXPECT_HAS(msg, temp_file("missing.json"));
  EXPECT_HAS(msg, "key 'friction.Fc': missing (expected a number in (0, 1e+07] N)");
}

TEST(BadInput, UnknownKeyListsTheAllowedKeys) {
  const auto msg = load_error("unknown.json", fig4_with("\"mass\": 1.0", "\"mass\": 1.0, \"mas\": 2"));
  EXPECT_HAS(msg, temp_file("unknown.json"));
  EXPECT_HAS(msg, "key 'plant.mas': unknown key (allowed here: damper, mass, spring)");
}

TEST(BadInput, WrongTypeNamesExpectedAndActualType) {
  auto msg = load_error("type.json", fig4_with("\"mass\": 1.0", "\"mass\": [1.0]"));
  EXPECT_HAS(msg, "key 'plant.mass': expected a number in (0, 1e+09] kg, got array");
  msg = load_error("type2.json", fig4_with("\"signal\": {", "\"signal\": 3, \"x\": {"));
  EXPECT_HAS(msg, "key 'drive.signal': expected an object, got number");
  msg = load_error("type3.json", fig4_with("\"model\": \"gms\"", "\"model\": 1"));
  EXPECT_HAS(msg, "key 'friction.model': expected a string, got number");
}

TEST(BadInput, NaNAndInfinityLiteralsAreSyntaxErrorsWithLineAndColumn) {
  for (const std::string lit : {"NaN", "nan", "Infinity", "-Infinity", "inf"}) {
    const std::string text = fig4_with("\"Vs\": 0.001", "\"Vs\": " + lit);
    const auto msg = load_error("nan.json", text);
    EXPECT_EQ(msg.rfind(temp_file("nan.json") + ":" + std::to_string(line_of(text, lit)) + ":", 0),
              0u)
        << msg;
    EXPECT_HAS(msg, "malformed JSON");
    EXPECT_HAS(msg, "JSON has no NaN or Infinity; every value must be a finite number");
  }
}

TEST(BadInput, HugeExponentOverflowIsAnInputErrorWithLineAndColumn) {
  for (const std::string lit : {"1e999", "-2.5E+400"}) {
    const std::string text = fig4_with("\"Vs\": 0.001", "\"Vs\": " + lit);
    const auto msg = load_error("overflow.json", text);
    const int col = static_cast<int>(text.find(lit) - text.rfind('\n', text.find(lit)));
    EXPECT_HAS(msg, temp_file("overflow.json") + ":" + std::to_string(line_of(text, lit)) + ":" +
                        std::to_string(col) + ":");
    EXPECT_HAS(msg, "number overflow parsing '" + lit + "'");
    EXPECT_HAS(msg, "numbers must be finite doubles");
  }
  // 1e-999 underflows to 0 (a finite double); the range check then names the key.
  const auto msg = load_error("underflow.json", fig4_with("\"Vs\": 0.001", "\"Vs\": 1e-999"));
  EXPECT_HAS(msg, "key 'friction.Vs': 0 is outside the allowed range (0, 1000] m/s");
}

TEST(BadInput, NonFiniteValuesThroughTheApiAreRejectedByTheSimulation) {
  Scenario s = load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  s.plant.mass = std::numeric_limits<double>::quiet_NaN();
  try {
    AssemblySimulation sim = one_body_simulation(s);
    FAIL() << "NaN mass accepted";
  } catch (const InputError& e) {
    EXPECT_HAS(std::string(e.what()), "plant.mass: must be > 0 kg");
  }
  s.plant.mass = 1.0;
  s.friction.set_scalar("Fs", std::numeric_limits<double>::infinity());
  try {
    AssemblySimulation sim = one_body_simulation(s);
    FAIL() << "infinite Fs accepted";
  } catch (const InputError& e) {
    EXPECT_HAS(std::string(e.what()), "friction.Fs: inf is outside the allowed range (0, 1e+07] N");
  }
}

TEST(BadInput, ZeroOrNegativeMassStiffnessOrStepNamesTheRange) {
  struct Row {
    const char *from, *to, *expect;
  };
  const Row rows[] = {
      {"\"mass\": 1.0", "\"mass\": 0", "key 'plant.mass': 0 is outside the allowed range (0, 1e+09] kg"},
      {"\"mass\": 1.0", "\"mass\": -2", "key 'plant.mass': -2 is outside the allowed range (0, 1e+09] kg"},
      {"\"k\": 75000", "\"k\": 0",
       "key 'friction.elements[0].k': 0 is outside the allowed range (0, 1e+12] N/m"},
      {"\"k\": 60000", "\"k\": -60000",
       "key 'friction.elements[1].k': -60000 is outside the allowed range (0, 1e+12] N/m"},
      {"\"spring\": 2.0", "\"spring\": 0",
       "key 'drive.spring': 0 is outside the allowed range (0, 1e+12] N/m"},
      {"\"mass\": 1.0", "\"mass\": 1.0, \"spring\": -1",
       "key 'plant.spring': -1 is outside the allowed range [0, 1e+12] N/m"},
      {"\"dt\": 1e-5", "\"dt\": 0", "key 'run.dt': 0 is outside the allowed range (0, 1] s"},
      {"\"dt\": 1e-5", "\"dt\": -1e-5", "key 'run.dt': -1e-05 is outside the allowed range (0, 1] s"},
      {"\"duration\": 25", "\"duration\": 0",
       "key 'run.duration': 0 is outside the allowed range (0, 1e+06] s"},
  };
  for (const auto& r : rows) {
    const auto msg = load_error("range.json", fig4_with(r.from, r.to));
    EXPECT_HAS(msg, temp_file("range.json"));
    EXPECT_HAS(msg, r.expect);
  }
}

TEST(BadInput, StepTooLargeForTheStiffestElementNamesTheLimit) {
  // Loads (dt is in range) but cannot be simulated stably: sum k = 210000 + 2 (pull spring) N/m
  // on 1 kg gives 2 / sqrt(210002) = 4.36434e-3 s.
  const std::string path = temp_file("dt.json");
  write_file_atomic(path, fig4_with("\"dt\": 1e-5", "\"dt\": 0.01"));
  const Scenario s = load_scenario(path);
  try {
    AssemblySimulation sim = one_body_simulation(s);
    FAIL() << "unstable step accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_HAS(msg, "run.dt: 0.01 s is too large for the stiffest mode");
    EXPECT_HAS(msg, "it must be < 0.00436434 s = 2/sqrt(sum k / m)");
  }
}

TEST(BadInput, WeightsThatDoNotSumToOneNameTheSum) {
  const auto msg = load_error("alpha.json", fig4_with("\"alpha\": 0.1", "\"alpha\": 0.2"));
  EXPECT_HAS(msg, temp_file("alpha.json") + ": key 'friction': parameters of model 'gms'");
  EXPECT_HAS(msg, "element weights alpha must sum to 1 (they sum to 1.1)");
}

TEST(BadInput, CoulombLevelAboveStaticLevelNamesBothValues) {
  const auto msg = load_error("fcfs.json", fig4_with("\"Fc\": 1.0", "\"Fc\": 2.0"));
  EXPECT_HAS(msg, temp_file("fcfs.json") + ": key 'friction'");
  EXPECT_HAS(msg, "Fc must not exceed Fs (Fc = 2 N, Fs = 1.5 N)");
}

TEST(BadInput, MoreElementsThanTheModelAllowsNamesTheLimit) {
  const Scenario base =
      load_scenario(std::string(GMSLAB_SOURCE_DIR) + "/presets/fig4_stick_slip.json");
  for (const auto& info : model_registry()) {
    if (info.columns.empty()) continue;
    json j = to_json(base);
    ModelParams p = info.defaults();
    p.elements.assign(info.max_elements + 1, p.elements.front());
    j["friction"] = to_json(p);
    const auto msg = load_error("many.json", j.dump());
    EXPECT_HAS(msg, temp_file("many.json") + ": key 'friction.elements': has " +
                        std::to_string(info.max_elements + 1) + " entries; allowed " +
                        std::to_string(info.min_elements) + " to " +
                        std::to_string(info.max_elements));
    p.elements.clear();
    j["friction"] = to_json(p);
    EXPECT_HAS(load_error("none.json", j.dump()), "key 'friction.elements': has 0 entries");
  }
}

TEST(BadInput, TimeThatDoesNotIncreaseNamesThePoint) {
  const std::string sig =
      "\"signal\": {\"type\": \"piecewise_linear\", \"points\": [[0, 0], [1, 1], [0.5, 2]]}";
  auto msg = load_error("time.json", fig4_with("\"signal\": {\"type\": \"ramp\", \"value\": 0, "
                                               "\"slope\": 0.1}",
                                               sig));
  EXPECT_HAS(msg, temp_file("time.json") + ": key 'drive.signal.points[2]': time must increase");
  const std::string seq =
      "\"signal\": {\"type\": \"sequence\", \"segments\": [{\"from\": 1, \"signal\": {\"type\": "
      "\"constant\", \"value\": 0}}, {\"from\": 1, \"signal\": {\"type\": \"constant\", \"value\": "
      "1}}]}";
  msg = load_error("seq.json",
                   fig4_with("\"signal\": {\"type\": \"ramp\", \"value\": 0, \"slope\": 0.1}", seq));
  EXPECT_HAS(msg, "key 'drive.signal.segments[1].from': segment start times must increase");
}

TEST(BadInput, TextInANumberFieldQuotesTheText) {
  const auto msg = load_error("text.json", fig4_with("\"mass\": 1.0", "\"mass\": \"1.0 kg\""));
  EXPECT_HAS(msg, temp_file("text.json") + ": key 'plant.mass': expected a number in (0, 1e+09] kg, "
                                           "got the text \"1.0 kg\" (write the number without "
                                           "quotes or units)");
}

TEST(BadInput, EmptyOrBlankFileSaysSo) {
  EXPECT_EQ(load_error("empty.json", ""),
            temp_file("empty.json") + ": the file is empty (expected a JSON object)");
  const auto msg = load_error("blank.json", "  \n\n");
  EXPECT_HAS(msg, temp_file("blank.json") + ":3:1: malformed JSON");
  EXPECT_HAS(msg, "is it truncated?");
}

TEST(BadInput, HugeFileIsRefusedBeforeReading) {
  // A sparse 65 MiB file: no time or disk is spent on it.
  const std::string path = temp_file("huge.json");
  const int fd = ::open(path.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::ftruncate(fd, 65ll << 20), 0);
  ::close(fd);
  try {
    load_scenario(path);
    FAIL() << "huge file accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": the file is 68157440 bytes; a scenario preset may be "
                                         "at most 67108864 bytes (64 MiB)");
  }
}

TEST(BadInput, TruncatedFileNamesWhereItEnds) {
  const std::string text = preset_text("fig4_stick_slip.json");
  for (const std::size_t cut : {text.size() / 3, text.size() / 2, text.size() - 3}) {
    const std::string part = text.substr(0, cut);
    const auto msg = load_error("cut.json", part);
    const int lines = 1 + static_cast<int>(std::count(part.begin(), part.end(), '\n'));
    EXPECT_HAS(msg, temp_file("cut.json") + ":" + std::to_string(lines) + ":");
    EXPECT_HAS(msg, "is it truncated?");
  }
}

TEST(BadInput, FileThatIsNotUtf8NamesLineAndEncoding) {
  // "Fig. 4" with a Latin-1 e-acute (0xE9) in the name string, on line 3.
  const std::string text = fig4_with("\"Fig. 4", "\"Fig\xe9 4");
  const auto msg = load_error("latin1.json", text);
  EXPECT_HAS(msg, temp_file("latin1.json") + ":3:");
  EXPECT_HAS(msg, "the file must be UTF-8 text");
  // A UTF-16 file (what some editors save) fails on its first byte.
  const auto msg16 = load_error("utf16.json", std::string("\xff\xfe{\0\"\0", 6));
  EXPECT_HAS(msg16, temp_file("utf16.json") + ":1:1: malformed JSON");
}

TEST(BadInput, DocumentThatIsNotAnObjectSaysWhatIsExpected) {
  EXPECT_EQ(load_error("array.json", "[1, 2]"),
            temp_file("array.json") + ": the document must be a JSON object, got array");
}

TEST(BadInput, UnknownModelListsTheKnownModels) {
  const auto msg = load_error("model.json", fig4_with("\"model\": \"gms\"", "\"model\": \"gsm\""));
  EXPECT_HAS(msg, "key 'friction.model': unknown friction model 'gsm' (known models: gms");
}

TEST(BadInput, MissingFileNamesThePath) {
  try {
    load_scenario(temp_file("does_not_exist.json"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              temp_file("does_not_exist.json") + ": cannot open file (No such file or directory)");
  }
}

TEST(BadInput, DeeplyNestedSequencesAreRefusedNotRecursedForever) {
  json sig = {{"type", "constant"}, {"value", 1.0}};
  for (int i = 0; i < 50; ++i)
    sig = {{"type", "sequence"}, {"segments", json::array({{{"from", 0.0}, {"signal", sig}}})}};
  json j = json::parse(preset_text("fig4_stick_slip.json"));
  j["drive"]["signal"] = sig;
  const auto msg = load_error("deep.json", j.dump());
  EXPECT_HAS(msg, "sequences nest more than 8 levels deep; flatten the signal");
}


// ---- measured-data CSV (core/io/csv.hpp) ----------------------------------------------------

namespace csv_rows {
// Header + 12 rows of t [s], x [m], F [N]; row i (1-based data row) is on line i + 1.
std::string good_csv() {
  std::string s = "t_s,x_m,F_N\n";
  for (int i = 0; i < 12; ++i)
    s += std::to_string(0.001 * i) + "," + std::to_string(1e-6 * i) + "," + std::to_string(0.1 * i) +
         "\n";
  return s;
}

std::string csv_error(const std::string& name, const std::string& text) {
  const std::string path = temp_file(name);
  write_file_atomic(path, text);
  try {
    load_measured_csv(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The CSV with line `line` (1-based) replaced.
std::string with_line(int line, const std::string& repl) {
  std::string s = good_csv();
  std::size_t a = 0;
  for (int i = 1; i < line; ++i) a = s.find('\n', a) + 1;
  return s.replace(a, s.find('\n', a) - a, repl);
}
}  // namespace csv_rows

TEST(BadInputCsv, TimeThatDoesNotIncreaseNamesLineAndColumn) {
  using namespace csv_rows;
  const auto msg = csv_error("time.csv", with_line(6, "0.002,4e-6,0.4"));
  EXPECT_HAS(msg, temp_file("time.csv") + ":6: column 't_s': time 0.002 is not greater than the "
                                          "previous row's; time must strictly increase");
}

TEST(BadInputCsv, TextAndNonFiniteNumbersNameLineAndColumn) {
  using namespace csv_rows;
  auto msg = csv_error("text.csv", with_line(4, "0.002,abc,0.2"));
  EXPECT_HAS(msg, temp_file("text.csv") + ":4: column 'x_m': 'abc' is not a number");
  msg = csv_error("nan.csv", with_line(5, "0.003,3e-6,nan"));
  EXPECT_HAS(msg, temp_file("nan.csv") + ":5: column 'F_N': 'nan' is not a finite number");
  msg = csv_error("inf.csv", with_line(5, "0.003,1e999,0.3"));
  EXPECT_HAS(msg, temp_file("inf.csv") + ":5: column 'x_m'");
}

TEST(BadInputCsv, EmptyTruncatedAndShortFilesSaySo) {
  using namespace csv_rows;
  EXPECT_HAS(csv_error("empty.csv", ""),
             temp_file("empty.csv") + ": empty; expected a header row (e.g. t_s,x_m,F_N)");
  const std::string g = good_csv();
  // Last row "0.011000,0.000011,1.100000" cut inside its second field. (A cut inside the last
  // field cannot be told from a shorter number: it loads.)
  const auto msg = csv_error("cut.csv", g.substr(0, g.size() - 12));
  EXPECT_HAS(msg, temp_file("cut.csv") + ":13: 2 fields, but the header has 3 (truncated or "
                                         "malformed row)");
  EXPECT_HAS(csv_error("short.csv", g.substr(0, g.find("0.005"))),
             temp_file("short.csv") + ": only 5 data rows; at least 10 are needed");
}

TEST(BadInputCsv, FileThatIsNotUtf8NamesTheLine) {
  using namespace csv_rows;
  const auto msg = csv_error("latin1.csv", "# caf\xe9\n" + good_csv());
  EXPECT_HAS(msg, temp_file("latin1.csv") + ":1: the file is not UTF-8 text");
}

TEST(BadInputCsv, MissingColumnNamesWhatIsAccepted) {
  using namespace csv_rows;
  const auto msg = csv_error("cols.csv", "t_s,x_m\n0,0\n");
  EXPECT_HAS(msg, temp_file("cols.csv") + ":1: no column for");
}

}  // namespace
}  // namespace gmslab::hardening

namespace gmslab {
namespace {

TEST(BadInputCsv, ValueThatOverflowsInSiUnitsIsRejected) {
  // Regression (fuzzer rule, tests/fuzz/regressions/csv_unit_overflow.csv): 1e306 kN is finite in
  // the file but +inf in N.
  std::string text = "t_s,x_m,F_kN\n";
  for (int i = 0; i < 12; ++i)
    text += std::to_string(0.001 * i) + ",0.0," + (i == 5 ? "1e306" : "0.001") + "\n";
  try {
    parse_measured_csv(text, "overflow.csv");
    FAIL() << "accepted a force of 1e306 kN";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("overflow.csv:7: column 'F_kN'"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("SI"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace gmslab

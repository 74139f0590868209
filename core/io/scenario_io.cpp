#include "core/io/scenario_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/preset_io.hpp"

namespace gmslab {

using nlohmann::json;

namespace {
constexpr double kBig = 1e12;
constexpr std::size_t kMaxPoints = 1'000'000;
}  // namespace

json to_json(const ModelParams& p) {
  const ModelInfo& info = model_info(p.model);
  json j;
  j["model"] = p.model;
  for (std::size_t i = 0; i < info.scalars.size(); ++i)
    j[std::string(info.scalars[i].key)] = p.scalars.at(i);
  if (!info.columns.empty()) {
    json rows = json::array();
    for (const auto& row : p.elements) {
      json e;
      for (std::size_t c = 0; c < info.columns.size(); ++c)
        e[std::string(info.columns[c].key)] = row.at(c);
      rows.push_back(e);
    }
    j["elements"] = rows;
  }
  return j;
}

ModelParams model_params_from_json(JsonReader& r) {
  ModelParams p;
  p.model = r.string("model");
  const ModelInfo* info = nullptr;
  try {
    info = &model_info(p.model);
  } catch (const InputError& e) {
    r.fail("model", e.what());
  }
  for (const auto& s : info->scalars)
    p.scalars.push_back(r.number(std::string(s.key), s.lo, s.hi, std::string(s.unit), s.lo_open));
  if (!info->columns.empty()) {
    auto rows = r.array_of_objects("elements", info->min_elements, info->max_elements);
    for (auto& row : rows) {
      std::vector<double> v;
      for (const auto& c : info->columns)
        v.push_back(row.number(std::string(c.key), c.lo, c.hi, std::string(c.unit), c.lo_open));
      row.finish();
      p.elements.push_back(std::move(v));
    }
  }
  r.finish();
  std::vector<std::string> problems;
  if (info->check) info->check(p, problems);
  if (!problems.empty()) {
    std::string all;
    for (const auto& m : problems) all += (all.empty() ? "" : "; ") + m;
    r.fail_object("parameters of model '" + p.model + "': " + all);
  }
  return p;
}

json to_json(const Signal& s) {
  json j;
  j["type"] = to_string(s.kind);
  switch (s.kind) {
    case Signal::Kind::Constant:
      j["value"] = s.value;
      break;
    case Signal::Kind::Ramp:
      j["value"] = s.value;
      j["slope"] = s.slope;
      break;
    case Signal::Kind::Sine:
      j["offset"] = s.offset;
      j["amplitude"] = s.amplitude;
      j["frequency"] = s.frequency;
      j["phase"] = s.phase;
      break;
    case Signal::Kind::PiecewiseLinear: {
      json pts = json::array();
      for (std::size_t i = 0; i < s.pt.size(); ++i) pts.push_back({s.pt[i], s.py[i]});
      j["points"] = pts;
      break;
    }
    case Signal::Kind::TurningPoints:
      j["start"] = s.start;
      j["rate"] = s.rate;
      j["points"] = s.points;
      break;
    case Signal::Kind::Triangle:
      j["low"] = s.low;
      j["high"] = s.high;
      j["rate"] = s.rate;
      j["cycles"] = s.cycles;
      break;
    case Signal::Kind::Sequence: {
      json segs = json::array();
      for (const auto& seg : s.segments) segs.push_back({{"from", seg.from}, {"signal", to_json(seg.signal)}});
      j["segments"] = segs;
      break;
    }
  }
  return j;
}

namespace {
constexpr int kMaxSignalNesting = 8;  // sequences inside sequences (bounds the recursion)
Signal signal_from_json_at(JsonReader& r, int depth);
}  // namespace

RunSettings run_settings_from_json(JsonReader& run) {
  RunSettings rs;
  rs.dt = run.number("dt", 0, 1, "s", true);
  rs.duration = run.number("duration", 0, 1e6, "s", true);
  rs.record_every = run.has("record_every") ? static_cast<int>(run.integer("record_every", 1, 1000000)) : 1;
  if (rs.duration / rs.dt > 1e10)
    run.fail("dt", "duration / dt = " + specs::num(rs.duration / rs.dt) +
                       " steps exceeds 1e10; raise dt or shorten the run");
  run.finish();
  return rs;
}

Signal signal_from_json(JsonReader& r) { return signal_from_json_at(r, 0); }

namespace {
Signal signal_from_json_at(JsonReader& r, int depth) {
  const std::string type = r.choice("type", {"constant", "ramp", "sine", "piecewise_linear",
                                             "turning_points", "triangle", "sequence"});
  Signal s;
  if (type == "constant") {
    s = Signal::constant(r.number("value", -kBig, kBig));
  } else if (type == "ramp") {
    const double v = r.number("value", -kBig, kBig);
    s = Signal::ramp(v, r.number("slope", -kBig, kBig, "per s"));
  } else if (type == "sine") {
    const double off = r.number("offset", -kBig, kBig);
    const double amp = r.number("amplitude", -kBig, kBig);
    const double f = r.number("frequency", 0, 1e6, "Hz");
    const double ph = r.has("phase") ? r.number("phase", -1e3, 1e3, "rad") : 0.0;
    s = Signal::sine(off, amp, f, ph);
  } else if (type == "piecewise_linear") {
    const auto& pts = r.raw("points");
    if (!pts.is_array() || pts.size() < 1 || pts.size() > kMaxPoints)
      r.fail("points", "expected an array of 1 to 1e6 [t, y] pairs");
    std::vector<double> t, y;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto& p = pts[i];
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        r.fail("points[" + std::to_string(i) + "]", "expected a pair [t in s, value]");
      const double ti = p[0].get<double>(), yi = p[1].get<double>();
      if (!std::isfinite(ti) || !std::isfinite(yi))
        r.fail("points[" + std::to_string(i) + "]", "must be finite");
      if (!t.empty() && !(ti > t.back()))
        r.fail("points[" + std::to_string(i) + "]", "time must increase (" + specs::num(ti) +
                                                        " s after " + specs::num(t.back()) + " s)");
      t.push_back(ti);
      y.push_back(yi);
    }
    s = Signal::piecewise_linear(std::move(t), std::move(y));
  } else if (type == "turning_points") {
    const double start = r.number("start", -kBig, kBig);
    const double rate = r.number("rate", 0, kBig, "per s", true);
    s = Signal::turning_points(start, rate, r.numbers("points", 1, kMaxPoints));
  } else if (type == "triangle") {
    const double lo = r.number("low", -kBig, kBig);
    const double hi = r.number("high", lo, kBig);
    const double rate = r.number("rate", 0, kBig, "per s", true);
    s = Signal::triangle(lo, hi, rate, static_cast<int>(r.integer("cycles", 1, 100000)));
  } else {
    if (depth >= kMaxSignalNesting)
      r.fail("type", "sequences nest more than " + std::to_string(kMaxSignalNesting) +
                         " levels deep; flatten the signal");
    auto segs = r.array_of_objects("segments", 1, 10000);
    std::vector<Signal::Segment> out;
    for (auto& seg : segs) {
      const double from = seg.number("from", -kBig, kBig, "s");
      if (!out.empty() && !(from > out.back().from))
        seg.fail("from", "segment start times must increase");
      auto sub = seg.object("signal");
      out.push_back({from, signal_from_json_at(sub, depth + 1)});
      seg.finish();
    }
    s = Signal::sequence(std::move(out));
  }
  r.finish();
  return s;
}
}  // namespace

json to_json(const Scenario& s) {
  json j;
  j["schema_version"] = kScenarioSchemaVersion;
  j["name"] = s.name;
  j["description"] = s.description;
  j["friction"] = to_json(s.friction);
  j["plant"] = {{"mass", s.plant.mass}, {"spring", s.plant.spring}, {"damper", s.plant.damper}};
  json d;
  d["type"] = to_string(s.drive.kind);
  d["signal"] = to_json(s.drive.signal);
  if (s.drive.kind == Drive::Kind::Pull) {
    d["spring"] = s.drive.pull_spring;
    d["damper"] = s.drive.pull_damper;
  }
  j["drive"] = d;
  j["run"] = {{"dt", s.run.dt}, {"duration", s.run.duration}, {"record_every", s.run.record_every}};
  return j;
}

Scenario scenario_from_json(const json& j, const std::string& file) {
  if (j.is_object() && j.contains("schema_version") && j["schema_version"] == 2)
    throw InputError(file + ": key 'schema_version': version 2 is an assembled plant (core/io/assembly_io.hpp); "
                     "it opens in the Plant view (gmslab render FILE --view plant), not as a one-body scenario");
  JsonReader r(j, file);
  r.schema_version(kScenarioSchemaVersion);
  Scenario s;
  s.name = r.string("name");
  s.description = r.opt_string("description", "");
  {
    auto f = r.object("friction");
    s.friction = model_params_from_json(f);
  }
  {
    auto p = r.object("plant");
    s.plant.mass = p.number("mass", 0, 1e9, "kg", true);
    s.plant.spring = p.has("spring") ? p.number("spring", 0, 1e12, "N/m") : 0.0;
    s.plant.damper = p.has("damper") ? p.number("damper", 0, 1e12, "N s/m") : 0.0;
    p.finish();
  }
  {
    auto d = r.object("drive");
    const auto type = d.choice("type", {"displacement", "velocity", "force", "pull"});
    s.drive.kind = type == "displacement" ? Drive::Kind::Displacement
                   : type == "velocity"   ? Drive::Kind::Velocity
                   : type == "force"      ? Drive::Kind::Force
                                          : Drive::Kind::Pull;
    auto sig = d.object("signal");
    s.drive.signal = signal_from_json(sig);
    if (s.drive.kind == Drive::Kind::Pull) {
      s.drive.pull_spring = d.number("spring", 0, 1e12, "N/m", true);
      s.drive.pull_damper = d.has("damper") ? d.number("damper", 0, 1e12, "N s/m") : 0.0;
    }
    d.finish();
  }
  {
    auto run = r.object("run");
    s.run = run_settings_from_json(run);
  }
  r.finish();
  return s;
}

Scenario load_scenario(const std::string& path) {
  std::error_code ec;
  if (const auto bytes = std::filesystem::file_size(path, ec); !ec && bytes > kMaxPresetBytes)
    throw InputError(path + ": the file is " + std::to_string(bytes) +
                     " bytes; a scenario preset may be at most " +
                     std::to_string(kMaxPresetBytes) + " bytes (64 MiB)");
  return scenario_from_json(parse_json(read_file(path), path), path);
}

void save_scenario(const Scenario& s, const std::string& path) {
  write_file_atomic(path, to_json(s).dump(2) + "\n");
}

std::string shipped_preset(const std::string& name, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p(name);
  if (name.empty() || p.has_parent_path()) return {};
  if (p.extension() != ".json") p += ".json";
  const fs::path in_dir = fs::path(dir) / p;
  return fs::is_regular_file(in_dir, ec) ? in_dir.string() : std::string();
}

std::string preset_names(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

}  // namespace gmslab

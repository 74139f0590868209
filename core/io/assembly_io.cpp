#include "core/io/assembly_io.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab {

using nlohmann::json;

namespace {
std::string end_name(const Assembly& a, int i) { return i == kGround ? "ground" : a.bodies.at(i).name; }
}  // namespace

int preset_schema_version(const json& j) {
  if (!j.is_object() || !j.contains("schema_version") || !j["schema_version"].is_number_integer()) return 0;
  return j["schema_version"].get<int>();
}

json to_json(const AssemblyScenario& s) {
  const Assembly& a = s.plant;
  json j;
  j["schema_version"] = kAssemblySchemaVersion;
  j["name"] = s.name;
  j["description"] = s.description;
  json p;
  p["bodies"] = json::array();
  for (const auto& b : a.bodies) p["bodies"].push_back({{"name", b.name}, {"mass", b.mass}});
  p["springs"] = json::array();
  for (const auto& x : a.springs)
    p["springs"].push_back({{"name", x.name}, {"a", end_name(a, x.a)}, {"b", end_name(a, x.b)}, {"stiffness", x.stiffness}});
  p["dampers"] = json::array();
  for (const auto& x : a.dampers)
    p["dampers"].push_back({{"name", x.name}, {"a", end_name(a, x.a)}, {"b", end_name(a, x.b)}, {"damping", x.damping}});
  p["contacts"] = json::array();
  for (const auto& x : a.contacts)
    p["contacts"].push_back({{"name", x.name}, {"a", end_name(a, x.a)}, {"b", end_name(a, x.b)}, {"friction", to_json(x.friction)}});
  p["drives"] = json::array();
  for (const auto& d : a.drives) {
    json jd = {{"name", d.name}, {"type", to_string(d.kind)}, {"body", end_name(a, d.body)}, {"signal", to_json(d.signal)}};
    if (d.kind == DrivePart::Kind::Pull) {
      jd["spring"] = d.pull_spring;
      jd["damper"] = d.pull_damper;
      jd["point_velocity"] = d.point_velocity;
    }
    p["drives"].push_back(jd);
  }
  j["plant"] = p;
  j["run"] = {{"dt", s.run.dt}, {"duration", s.run.duration}, {"record_every", s.run.record_every}};
  return j;
}

namespace {
// A body named by `key` ("ground" allowed when `ground_ok`): its index, or an error naming the key.
int body_ref(JsonReader& r, const std::string& key, const Assembly& a, bool ground_ok) {
  const std::string name = r.string(key);
  if (name == "ground") {
    if (!ground_ok) r.fail(key, "a drive acts on a body, not on ground");
    return kGround;
  }
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (a.bodies[i].name == name) return static_cast<int>(i);
  std::string known;
  for (const auto& b : a.bodies) known += (known.empty() ? "" : ", ") + b.name;
  r.fail(key, "unknown body '" + name + "' (bodies: " + known + (ground_ok ? ", or ground)" : ")"));
}

AssemblyScenario read_v2(JsonReader& r, const std::string& file) {
  AssemblyScenario s;
  s.name = r.string("name");
  s.description = r.opt_string("description", "");
  Assembly& a = s.plant;
  {
    auto p = r.object("plant");
    for (auto& b : p.array_of_objects("bodies", 1, kMaxBodies)) {
      Body body;
      body.name = b.string("name");
      body.mass = b.number("mass", 0, 1e9, "kg", true);
      b.finish();
      a.bodies.push_back(body);
    }
    auto list = [&](const char* key) {
      return p.has(key) ? p.array_of_objects(key, 0, 256) : std::vector<JsonReader>{};
    };
    for (auto& x : list("springs")) {
      SpringPart sp{x.string("name"), body_ref(x, "a", a, true), body_ref(x, "b", a, true), 0.0};
      sp.stiffness = x.number("stiffness", 0, 1e12, "N/m");
      if (sp.a == kGround) std::swap(sp.a, sp.b);
      if (sp.a == sp.b) x.fail_object("connects " + end_name(a, sp.a) + " to itself; a spring joins two different bodies or a body and ground");
      x.finish();
      a.springs.push_back(sp);
    }
    for (auto& x : list("dampers")) {
      DamperPart dp{x.string("name"), body_ref(x, "a", a, true), body_ref(x, "b", a, true), 0.0};
      dp.damping = x.number("damping", 0, 1e12, "N s/m");
      if (dp.a == kGround) std::swap(dp.a, dp.b);
      if (dp.a == dp.b) x.fail_object("connects " + end_name(a, dp.a) + " to itself; a damper joins two different bodies or a body and ground");
      x.finish();
      a.dampers.push_back(dp);
    }
    for (auto& x : list("contacts")) {
      ContactPart cp;
      cp.name = x.string("name");
      cp.a = body_ref(x, "a", a, true);
      cp.b = body_ref(x, "b", a, true);
      if (cp.a == cp.b) x.fail_object("connects " + end_name(a, cp.a) + " to itself; a contact joins two different bodies or a body and ground");
      if (cp.a == kGround) x.fail("a", "the first body of a contact must be a body (friction acts on v_a - v_b); put ground as b");
      auto f = x.object("friction");
      cp.friction = model_params_from_json(f);
      x.finish();
      a.contacts.push_back(cp);
    }
    for (auto& x : list("drives")) {
      DrivePart d;
      d.name = x.string("name");
      const auto type = x.choice("type", {"force", "displacement", "velocity", "pull"});
      d.kind = type == "force"          ? DrivePart::Kind::Force
               : type == "displacement" ? DrivePart::Kind::Displacement
               : type == "velocity"     ? DrivePart::Kind::Velocity
                                        : DrivePart::Kind::Pull;
      d.body = body_ref(x, "body", a, false);
      auto sig = x.object("signal");
      d.signal = signal_from_json(sig);
      if (d.kind == DrivePart::Kind::Pull) {
        d.pull_spring = x.number("spring", 0, 1e12, "N/m", true);
        d.pull_damper = x.has("damper") ? x.number("damper", 0, 1e12, "N s/m") : 0.0;
        d.point_velocity = x.has("point_velocity") ? x.boolean("point_velocity") : false;
      }
      x.finish();
      a.drives.push_back(d);
    }
    p.finish();
  }
  {
    auto run = r.object("run");
    s.run = run_settings_from_json(run);
  }
  r.finish();
  // Structure (names, connectivity, prescribed motion twice): every problem, with its key path.
  const auto bad = validate(a, "plant");
  if (!bad.empty()) {
    std::string msg = file + ": invalid plant:";
    for (const auto& b : bad) msg += "\n  key '" + b.substr(0, b.find(':')) + "'" + b.substr(b.find(':'));
    throw InputError(msg);
  }
  return s;
}
}  // namespace

AssemblyScenario assembly_scenario_from_json(const json& j, const std::string& file) {
  if (preset_schema_version(j) == 1) return assembly_from_scenario(scenario_from_json(j, file));
  JsonReader r(j, file);
  r.schema_version(kAssemblySchemaVersion, 1);
  return read_v2(r, file);
}

AssemblyScenario load_assembly_scenario(const std::string& path) {
  std::error_code ec;
  if (const auto bytes = std::filesystem::file_size(path, ec); !ec && bytes > kMaxPresetBytes)
    throw InputError(path + ": the file is " + std::to_string(bytes) + " bytes; a preset may be at most 64 MiB");
  return assembly_scenario_from_json(parse_json(read_file(path), path), path);
}

namespace {
void write_assembly_csv_header(const AssemblyTrace& tr, std::ostream& out) {
  out << "t_s";
  for (const auto& c : tr.channels) out << ',' << c.name << '_' << (c.unit == "m/s" ? "mps" : c.unit);
  for (const auto& c : tr.channels)
    if (c.kind == Channel::Kind::ContactForce) out << ",slip." << c.name.substr(2);
  out << '\n';
}
void write_assembly_csv_rows(const AssemblyTrace& tr, std::ostream& out) {
  char buf[32];
  const std::size_t nc = tr.channels.size();
  for (std::size_t k = 0; k < tr.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.17g", tr.t[k]);
    out << buf;
    for (std::size_t c = 0; c < nc; ++c) {
      std::snprintf(buf, sizeof buf, ",%.17g", tr.values[k * nc + c]);
      out << buf;
    }
    for (std::size_t j = 0; j < tr.contact_slip.size(); ++j) out << ',' << static_cast<int>(tr.contact_slip[j][k]);
    out << '\n';
  }
}
}  // namespace

void write_assembly_trace_csv(const AssemblyTrace& tr, std::ostream& out) {
  write_assembly_csv_header(tr, out);
  write_assembly_csv_rows(tr, out);
}

std::size_t stream_assembly_trace_csv(const AssemblyScenario& s, const std::function<void(std::string_view)>& sink) {
  constexpr std::size_t kChunkSamples = 1u << 14;
  AssemblySimulation sim(s, TraceOptions{.max_bytes = 0, .reserve_samples = kChunkSamples + 2});
  std::ostringstream o;
  write_assembly_csv_header(sim.trace(), o);
  std::size_t written = 0;
  const auto chunk_steps = kChunkSamples * static_cast<std::size_t>(s.run.record_every);
  auto drain = [&] {
    write_assembly_csv_rows(sim.trace(), o);
    written += sim.trace().size();
    sim.clear_trace();
    const std::string text = o.str();
    sink(text);
    o.str("");
  };
  while (!sim.finished()) {
    sim.advance(chunk_steps);
    drain();
  }
  if (sim.trace().size() > 0 || written == 0) drain();  // a run of zero steps: its first sample
  return written;
}

std::size_t save_assembly_trace_csv(const AssemblyScenario& s, const std::string& path) {
  AtomicFileWriter file(path);
  const std::size_t n = stream_assembly_trace_csv(s, [&](std::string_view t) { file.write(t); });
  file.commit();
  return n;
}

void save_assembly_scenario(const AssemblyScenario& s, const std::string& path) {
  write_file_atomic(path, to_json(s).dump(2) + "\n");
}

}  // namespace gmslab

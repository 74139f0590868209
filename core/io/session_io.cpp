#include "core/io/session_io.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab {

using nlohmann::json;

json to_json(const Session& s) {
  json j;
  j["schema_version"] = kSessionSchemaVersion;
  j["scenario_path"] = s.scenario_path;
  j["scenario"] = to_json(s.scenario);
  j["compare"] = s.compare ? to_json(*s.compare) : json(nullptr);
  j["view"] = {{"speed", s.view.speed},
               {"color_phases", s.view.color_phases},
               {"slip_velocity", s.view.slip_velocity},
               {"tab", s.view.tab},
               {"friction_against", s.view.friction_against}};
  const DesignSettings& d = s.design;
  j["design"] = {{"plant",
                  {{"source", control::to_string(d.plant.source)},
                   {"num", d.plant.num},
                   {"den", d.plant.den},
                   {"drive", d.plant.drive},
                   {"output", d.plant.output}}},
                 {"regime", d.regime},
                 {"velocity", d.velocity},
                 {"zeta", d.zeta},
                 {"wn", d.wn},
                 {"use_K", d.use_K},
                 {"K", d.K},
                 {"max_ratio", d.max_ratio},
                 {"compensator", control::to_string(d.compensator)},
                 {"reference", to_string(d.reference)},
                 {"amplitude", d.amplitude},
                 {"slope", d.slope},
                 {"frequency", d.frequency},
                 {"compensation", d.compensation},
                 {"feedforward_source", control::to_string(d.feedforward_source)},
                 {"mismatch_force", d.mismatch_force},
                 {"mismatch_stiffness", d.mismatch_stiffness},
                 {"sample_time", d.sample_time},
                 {"max_overshoot", d.max_overshoot},
                 {"settling_time", d.settling_time},
                 {"other_regime", d.other_regime},
                 {"zero_degree", d.zero_degree}};
  const IdentifySettings& i = s.identify;
  j["identify"] = {{"data", i.data},
                   {"validate", i.validate},
                   {"columns", i.columns},
                   {"mask", i.mask},
                   {"validate_mask", i.validate_mask},
                   {"mask_edges", i.mask_edges},
                   {"model", i.model},
                   {"elements", i.elements},
                   {"compare", i.compare}};
  j["plant"] = s.plant ? json{{"path", s.plant->path},
                              {"speed", s.plant->speed},
                              {"magnification", s.plant->magnification},
                              {"plotted", s.plant->plotted},
                              {"linear_plant",
                               {{"drive", s.plant->tf_drive}, {"output", s.plant->tf_output}, {"sliding", s.plant->tf_sliding}}},
                              {"scenario", to_json(s.plant->scenario)}}
                       : json(nullptr);
  return j;
}

namespace {
ViewSettings view_from_json(JsonReader& r) {
  ViewSettings v;
  v.speed = r.number("speed", 1e-3, 1e3, "s/s");
  v.color_phases = r.boolean("color_phases");
  v.slip_velocity = r.number("slip_velocity", 0, 1e3, "m/s", true);
  v.tab = r.string("tab");
  if (v.tab.size() > 64) r.fail("tab", "at most 64 characters");
  v.friction_against = r.choice("friction_against", {"auto", "displacement", "velocity"});
  r.finish();
  return v;
}

// design.plant: the plant source; num / den checked as the Design tab checks them (the value in
// force is always a valid pair).
control::PlantChoice plant_choice_from_json(JsonReader& r) {
  control::PlantChoice p;
  p.source = *control::plant_source_from_string(r.choice("source", {"scenario", "assembly", "typed"}));
  const auto text = [&r](const char* key, std::size_t max) {
    std::string v = r.string(key);
    if (v.size() > max) r.fail(key, "at most " + std::to_string(max) + " characters");
    return v;
  };
  p.num = text("num", 4096);
  p.den = text("den", 4096);
  if (const std::string why = control::coefficients_problem(p.num, false); !why.empty()) r.fail("num", why);
  if (const std::string why = control::coefficients_problem(p.den, true); !why.empty()) r.fail("den", why);
  try {
    control::typed_plant(p.num, p.den);
  } catch (const InputError& e) {  // improper: deg num > deg den
    r.fail("num", e.what());
  }
  p.drive = text("drive", 256);
  p.output = text("output", 256);
  r.finish();
  return p;
}

DesignSettings design_from_json(JsonReader& r) {
  DesignSettings d;
  if (r.has("plant")) {  // sessions before the plant source have none: the scenario's plant
    auto plant = r.object("plant");
    d.plant = plant_choice_from_json(plant);
  }
  d.regime = r.choice("regime", {"presliding", "sliding"});
  d.velocity = r.number("velocity", 0, 1e3, "m/s");
  d.zeta = r.number("zeta", 0.02, 0.98);
  d.wn = r.number("wn", 0, 1e5, "rad/s", true);
  d.use_K = r.boolean("use_K");
  d.K = r.number("K", 0, 1e7, "", true);
  d.max_ratio = r.number("max_ratio", 1.5, 100);
  if (r.has("compensator"))  // sessions before the compensator types: the lead
    d.compensator = *control::compensator_type_from_string(
        r.choice("compensator", {"lead", "lag", "lead_lag", "pi", "pid"}));
  d.reference = *design_reference_from_string(r.choice("reference", {"step", "ramp", "sine"}));
  d.amplitude = r.number("amplitude", 0, 1, "m", true);
  d.slope = r.number("slope", 0, 1, "m/s", true);
  d.frequency = r.number("frequency", 0, 100, "Hz", true);
  d.compensation = r.choice("compensation", {"coulomb", "gms"});
  if (r.has("feedforward_source"))  // sessions before the measured-velocity feedforward: the reference
    d.feedforward_source =
        *control::feedforward_source_from_string(r.choice("feedforward_source", {"reference", "measured"}));
  d.mismatch_force = r.number("mismatch_force", 0.2, 2);
  d.mismatch_stiffness = r.number("mismatch_stiffness", 0.1, 10);
  d.sample_time = r.number("sample_time", 0, 0.01, "s");
  d.max_overshoot = r.number("max_overshoot", 0.1, 90, "%");
  d.settling_time = r.number("settling_time", 0, 100, "s", true);
  d.other_regime = r.boolean("other_regime");
  d.zero_degree = r.boolean("zero_degree");
  r.finish();
  return d;
}
IdentifySettings identify_from_json(JsonReader& r) {
  IdentifySettings i;
  const auto text = [&r](const char* key) {
    std::string v = r.string(key);
    if (v.size() > 4096) r.fail(key, "at most 4096 characters");
    return v;
  };
  i.data = text("data");
  i.validate = text("validate");
  i.columns = text("columns");
  i.mask = text("mask");
  i.validate_mask = text("validate_mask");
  i.mask_edges = text("mask_edges");
  std::vector<std::string> tags;
  for (const auto& m : model_registry()) tags.emplace_back(m.tag);
  i.model = r.choice("model", tags);
  i.elements = static_cast<int>(r.integer("elements", 0, 64));  // 0 = auto
  i.compare = r.boolean("compare");
  r.finish();
  return i;
}
PlantTabSettings plant_tab_from_json(JsonReader& r, const std::string& file) {
  PlantTabSettings p;
  p.path = r.string("path");
  if (p.path.size() > 4096) r.fail("path", "at most 4096 characters");
  p.speed = r.number("speed", 1e-3, 1e3, "s/s");
  p.magnification = r.number("magnification", 0, 1e6, "px/mm");
  const json& sc = r.raw("scenario");
  if (preset_schema_version(sc) != kAssemblySchemaVersion)
    r.fail("scenario", "an assembled plant with schema_version " + std::to_string(kAssemblySchemaVersion) + " expected");
  p.scenario = assembly_scenario_from_json(sc, file + " (in 'plant.scenario')");
  const Assembly& a = p.scenario.plant;
  // Output names of the plant (as the trace names them), for "plotted".
  std::string outputs;
  std::vector<std::string> names;
  for (const auto& c : output_channels(a)) names.push_back(c.name), outputs += (outputs.empty() ? "" : ", ") + c.name;
  const json& plotted = r.raw("plotted");
  if (!plotted.is_array()) r.fail("plotted", "an array of output names expected");
  for (std::size_t i = 0; i < plotted.size(); ++i) {
    const std::string key = "plotted[" + std::to_string(i) + "]";
    if (!plotted[i].is_string()) r.fail(key, "an output name (string) expected");
    const std::string n = plotted[i].get<std::string>();
    if (std::find(names.begin(), names.end(), n) == names.end()) r.fail(key, "unknown output '" + n + "' (outputs: " + outputs + ")");
    if (std::find(p.plotted.begin(), p.plotted.end(), n) != p.plotted.end()) r.fail(key, "output '" + n + "' listed twice");
    p.plotted.push_back(n);
  }
  auto lp = r.object("linear_plant");
  p.tf_drive = lp.string("drive");
  std::string drives;
  bool drive_ok = a.drives.empty() && p.tf_drive.empty();
  for (const auto& d : a.drives) drive_ok = drive_ok || d.name == p.tf_drive, drives += (drives.empty() ? "" : ", ") + d.name;
  if (!drive_ok) lp.fail("drive", "unknown drive '" + p.tf_drive + "' (drives: " + (drives.empty() ? "none: use \"\"" : drives) + ")");
  p.tf_output = lp.string("output");
  std::string bodies;
  bool body_ok = false;
  for (const auto& b : a.bodies) body_ok = body_ok || b.name == p.tf_output, bodies += (bodies.empty() ? "" : ", ") + b.name;
  if (!body_ok) lp.fail("output", "unknown body '" + p.tf_output + "' (bodies: " + bodies + ")");
  p.tf_sliding = lp.boolean("sliding");
  lp.finish();
  r.finish();
  return p;
}
}  // namespace

Session session_from_json(const json& j, const std::string& file) {
  JsonReader r(j, file);
  const int version = r.schema_version(kSessionSchemaVersion, kOldestSessionSchemaVersion);
  Session s;
  s.scenario_path = r.string("scenario_path");
  s.scenario = scenario_from_json(r.raw("scenario"), file + " (in 'scenario')");
  const json& cmp = r.raw("compare");
  if (!cmp.is_null()) {
    JsonReader c(cmp, file, "compare");
    s.compare = model_params_from_json(c);
  }
  auto view = r.object("view");
  s.view = view_from_json(view);
  if (version >= 2) {
    auto design = r.object("design");
    s.design = design_from_json(design);
  }
  if (version >= 3) {
    auto identify = r.object("identify");
    s.identify = identify_from_json(identify);
  }
  if (version >= 4) {
    const json& plant = r.raw("plant");
    if (!plant.is_null()) {
      if (!plant.is_object()) r.fail("plant", "an object or null expected");
      JsonReader p(plant, file, "plant");
      s.plant = plant_tab_from_json(p, file);
    }
  }
  r.finish();
  return s;
}

Session load_session(const std::string& path) {
  return session_from_json(parse_json(read_file(path), path), path);
}

void save_session(const Session& s, const std::string& path) {
  write_file_atomic(path, to_json(s).dump(2) + "\n");
}

}  // namespace gmslab

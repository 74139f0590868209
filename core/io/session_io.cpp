#include "core/io/session_io.hpp"

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
}  // namespace

Session session_from_json(const json& j, const std::string& file) {
  JsonReader r(j, file);
  r.schema_version(kSessionSchemaVersion);
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

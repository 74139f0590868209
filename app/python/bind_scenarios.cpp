// gmslab Python module: scenarios - ModelParams, Plant, RunSettings, Scenario, load_scenario,
// save_scenario.
#include "app/python/bindings.hpp"
#include "core/error.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::py_bindings {

using namespace pybind11::literals;
namespace {
void bind_model_params(py::module_& m) {
  py::class_<ModelParams>(m, "ModelParams",
                          "Friction model parameters: registry tag, scalars by key, element rows")
      .def(py::init([](const std::string& tag) { return model_info(tag).defaults(); }),
           py::arg("model"),
           "The registry defaults of model `model` (e.g. 'gms'); InputError for an unknown tag")
      .def_readwrite("model", &ModelParams::model, "Registry tag, e.g. 'gms'")
      .def_readwrite("elements", &ModelParams::elements,
                     "Element rows (list of lists, one value per column key; see columns())")
      .def(
          "keys",
          [](const ModelParams& p) {
            std::vector<std::string> k;
            for (const auto& s : model_info(p.model).scalars) k.emplace_back(s.key);
            return k;
          },
          "Scalar parameter keys of this model, e.g. ['Fs', 'Fc', 'Vs', ...]")
      .def(
          "columns",
          [](const ModelParams& p) {
            std::vector<std::string> k;
            for (const auto& s : model_info(p.model).columns) k.emplace_back(s.key);
            return k;
          },
          "Element column keys, e.g. ['alpha', 'k', 'C']")
      .def("__getitem__",
           [](const ModelParams& p, const std::string& k) {
             try {
               return p.scalar(k);
             } catch (const InputError&) {
               throw py::key_error("friction: no parameter '" + k + "' in model " + p.model);
             }
           })
      .def("__setitem__",
           [](ModelParams& p, const std::string& k, double v) {
             if (model_info(p.model).scalar_index(k) < 0)
               throw py::key_error("friction: no parameter '" + k + "' in model " + p.model);
             p.set_scalar(k, v);
           })
      .def("column", &ModelParams::column, py::arg("key"),
           "One element column, e.g. column('k') [N/m]")
      .def("__eq__", [](const ModelParams& a, const ModelParams& b) { return a == b; })
      .def("__repr__",
           [](const ModelParams& p) { return "<ModelParams " + to_json(p).dump() + ">"; });
}

void bind_scenario(py::module_& m) {
  py::class_<Plant>(m, "Plant",
                    "The body: mass [kg], spring to ground [N/m], damper to ground [N s/m]")
      .def_readwrite("mass", &Plant::mass, "m [kg], > 0")
      .def_readwrite("spring", &Plant::spring, "k [N/m], >= 0")
      .def_readwrite("damper", &Plant::damper, "c [N s/m], >= 0");
  py::class_<RunSettings>(m, "RunSettings",
                          "Integration step dt [s], duration [s], record_every [-]")
      .def_readwrite("dt", &RunSettings::dt, "Integration step [s]")
      .def_readwrite("duration", &RunSettings::duration, "Simulated time [s]")
      .def_readwrite("record_every", &RunSettings::record_every,
                     "Keep every n-th step in the trace [-]");

  py::class_<Scenario>(
      m, "Scenario",
      "A scenario preset: friction, plant, drive and run settings. Edit the fields "
      "(sc.plant.mass = 2.0, sc.friction['Fs'] = 1.2, sc.run.dt = 1e-5), then "
      "validate() or simulate(); drive via the 'drive' dict")
      .def(py::init([](py::dict d) { return scenario_from_json(from_py(d), "<dict>"); }),
           py::arg("data"),
           "A scenario from a dict in the preset JSON schema (validated; InputError names the key)")
      .def_readwrite("name", &Scenario::name)
      .def_readwrite("description", &Scenario::description)
      .def_readwrite("friction", &Scenario::friction)
      .def_readwrite("plant", &Scenario::plant)
      .def_readwrite("run", &Scenario::run)
      .def_property(
          "drive", [](const Scenario& s) { return to_py(to_json(s)["drive"]); },
          [](Scenario& s, py::dict d) {
            auto j = to_json(s);
            j["drive"] = from_py(d);
            s = scenario_from_json(j, "<scenario>");
          },
          "The drive as a dict (type, signal, spring, damper), as in the preset JSON")
      .def(
          "to_dict", [](const Scenario& s) { return to_py(to_json(s)); },
          "The preset JSON as a dict")
      .def_static(
          "from_dict", [](py::dict d) { return scenario_from_json(from_py(d), "<dict>"); },
          py::arg("data"),
          "A scenario from a dict in the preset JSON schema (to_dict, an identify report's "
          "'scenario'); "
          "validated, InputError names the key")
      .def(
          "validate", [](const Scenario& s) { (void)validated(s, "<scenario>"); },
          "Checks every field as a preset file is checked; raises InputError naming the key and "
          "the range")
      .def(
          "stability_limit_dt", [](const Scenario& s) { return stability_limit_dt(s); },
          "Largest stable integration step [s] for this plant and friction")
      .def("__eq__", [](const Scenario& a, const Scenario& b) { return a == b; })
      .def("__repr__", [](const Scenario& s) { return "<Scenario '" + s.name + "'>"; });
}
}  // namespace

void bind_scenarios(py::module_& m) {
  bind_model_params(m);
  bind_scenario(m);
  m.def("load_scenario", &load_scenario_arg, py::arg("path"),
        "Loads a scenario preset (JSON): a path (str or os.PathLike), or a shipped preset's name "
        "(\"fig2a_presliding\") from any folder; InputError names the file and the key path");
  m.def(
      "save_scenario",
      [](const Scenario& s, const py::object& path_obj) {
        const std::string path = path_arg(path_obj, "path");
        save_scenario(validated(s, path), path);
      },
      py::arg("scenario"), py::arg("path"), "Validates and writes the preset atomically");
}

}  // namespace gmslab::py_bindings

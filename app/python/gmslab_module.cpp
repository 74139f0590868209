// gmslab Python module (_gmslab, wrapped by the package app/python/gmslab): the core's jobs as
// Python calls with NumPy arrays. Every call runs the same core function the CLI and the window
// run (load_scenario, Simulation, build_model, design_report, root_locus, run_identification,
// make_figure, load_measured). Core errors become Python exceptions carrying the same message:
// InputError -> gmslab.InputError (a ValueError), SimulationError -> gmslab.SimulationError (a
// RuntimeError), IoError -> gmslab.IoError (an OSError). Long calls release the GIL.
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/control/design_report.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/preset_io.hpp"
#include "core/control/design_plant_json.hpp"
#include "core/control/polynomial.hpp"
#include "core/control/root_locus.hpp"
#include "core/control/scenario_plant.hpp"
#include "core/error.hpp"
#include "core/figures/figure_set.hpp"
#include "core/friction/model.hpp"
#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "core/io/measured_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_file.hpp"
#include "core/sim/simulation.hpp"

namespace py = pybind11;
using namespace pybind11::literals;
using namespace gmslab;

namespace {

py::object to_py(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }
nlohmann::json from_py(const py::object& o) {
  return nlohmann::json::parse(py::module_::import("json").attr("dumps")(o).cast<std::string>());
}

py::array_t<double> arr(const std::vector<double>& v) { return py::array_t<double>(v.size(), v.data()); }
py::array_t<std::complex<double>> carr(const std::vector<control::cplx>& v) {
  return py::array_t<std::complex<double>>(v.size(), v.data());
}

// The presets (gmslab::presets_dir): env GMSLAB_PRESETS, the source tree's, the installed ones next
// to this package (PREFIX/lib/python3/dist-packages/gmslab -> PREFIX/share/gmslab/presets, as the
// .deb lays them out), or those under the configured install prefix. Called with the GIL held.
std::string preset_dir() {
  namespace fs = std::filesystem;
  const fs::path here = fs::path(py::module_::import("gmslab").attr("__file__").cast<std::string>()).parent_path();
  return presets_dir((here / "../../../../share/gmslab/presets").string());
}

// The design dict with its roots as complex numbers, as root_locus gives them: every
// "closed_loop_poles" ([[re, im], ...]) a complex NumPy array; "s_d", "slow_pole" and a gain
// point's "s" ([re, im]) a complex. gmslab.to_json turns them back into the CLI's JSON.
bool is_pair(const py::handle& v) {
  if (!py::isinstance<py::list>(v)) return false;
  const auto l = py::reinterpret_borrow<py::list>(v);
  return l.size() == 2 && (py::isinstance<py::float_>(l[0]) || py::isinstance<py::int_>(l[0])) &&
         (py::isinstance<py::float_>(l[1]) || py::isinstance<py::int_>(l[1]));
}
void complex_roots(py::handle o) {
  if (py::isinstance<py::list>(o)) {
    for (const auto& item : py::reinterpret_borrow<py::list>(o)) complex_roots(item);
    return;
  }
  if (!py::isinstance<py::dict>(o)) return;
  auto d = py::reinterpret_borrow<py::dict>(o);
  for (const auto& [k, v] : d) {
    const std::string key = py::str(k);
    if (key == "closed_loop_poles" && py::isinstance<py::list>(v)) {
      std::vector<std::complex<double>> roots;
      bool all = true;
      for (const auto& r : py::reinterpret_borrow<py::list>(v)) {
        if (!is_pair(r)) { all = false; break; }
        const auto l = py::reinterpret_borrow<py::list>(r);
        roots.emplace_back(l[0].cast<double>(), l[1].cast<double>());
      }
      if (all) d[k] = py::array_t<std::complex<double>>(roots.size(), roots.data());
    } else if ((key == "s_d" || key == "slow_pole" || key == "s") && is_pair(v)) {
      const auto l = py::reinterpret_borrow<py::list>(v);
      d[k] = py::cast(std::complex<double>(l[0].cast<double>(), l[1].cast<double>()));
    } else {
      complex_roots(v);
    }
  }
}

// A path argument: str or any os.PathLike (pathlib.Path), as open() takes it. `what` names the
// argument in the TypeError.
std::string path_arg(const py::object& o, const char* what) {
  if (py::isinstance<py::str>(o)) return o.cast<std::string>();
  if (py::hasattr(o, "__fspath__")) {
    const py::object p = py::module_::import("os").attr("fspath")(o);
    if (py::isinstance<py::str>(p)) return p.cast<std::string>();
  }
  throw py::type_error(std::string(what) + ": expected a path (str or os.PathLike), got " +
                       py::str(py::type::of(o).attr("__name__")).cast<std::string>());
}

// A preset path as given, or a shipped preset's bare name (gmslab::resolve_preset, as the CLI and
// the window's --open take it); the error names the closest preset and lists them.
std::string resolve_preset_arg(const std::string& path) {
  return resolve_preset(path, preset_dir());
}

Scenario load_scenario_arg(const py::object& o) {
  return load_scenario(resolve_preset_arg(path_arg(o, "path")));
}

// A scenario checked the way a preset file is (every key, type and range; messages name the key).
Scenario validated(const Scenario& s, const std::string& where) { return scenario_from_json(to_json(s), where); }

// The step h [s] and the velocities of Model.step / Model.run, checked as the CLI checks run.dt
// ((0, 1] s) and a drive: finite.
void check_step(double h, const char* what) {
  if (!(std::isfinite(h) && h > 0.0 && h <= 1.0))
    throw InputError(std::string(what) + ": h = " + std::to_string(h) + " s: must be in (0, 1] s (as run.dt)");
}

// A friction model with its state: build any registry model, step it, read state and elements.
struct PyModel {
  std::unique_ptr<FrictionModel> model;
  std::vector<double> state;
  explicit PyModel(const ModelParams& p) {
    const auto errs = validate(p, "friction");
    if (!errs.empty()) {
      std::string m;
      for (const auto& e : errs) m += (m.empty() ? "" : "; ") + e;
      throw InputError(m);
    }
    model = build_model(p);
    state.assign(model->state_size(), 0.0);
    model->reset(state);
  }
};

struct PyTrace {
  Trace tr;
};

struct PyPlantTrace {
  AssemblyTrace tr;
};

}  // namespace

PYBIND11_MODULE(_gmslab, m) {
  m.doc() = "gmslab: GMS friction simulation, compensation design and identification (C++ core)";

  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<SimulationError>(m, "SimulationError", PyExc_RuntimeError);
  py::register_exception<IoError>(m, "IoError", PyExc_OSError);
  py::register_exception<InternalError>(m, "InternalError", PyExc_RuntimeError);

  // ---- scenarios -------------------------------------------------------------------------
  py::class_<ModelParams>(m, "ModelParams", "Friction model parameters: registry tag, scalars by key, element rows")
      .def(py::init([](const std::string& tag) { return model_info(tag).defaults(); }), py::arg("model"),
           "The registry defaults of model `model` (e.g. 'gms'); InputError for an unknown tag")
      .def_readwrite("model", &ModelParams::model, "Registry tag, e.g. 'gms'")
      .def_readwrite("elements", &ModelParams::elements,
                     "Element rows (list of lists, one value per column key; see columns())")
      .def("keys", [](const ModelParams& p) {
        std::vector<std::string> k;
        for (const auto& s : model_info(p.model).scalars) k.emplace_back(s.key);
        return k;
      }, "Scalar parameter keys of this model, e.g. ['Fs', 'Fc', 'Vs', ...]")
      .def("columns", [](const ModelParams& p) {
        std::vector<std::string> k;
        for (const auto& s : model_info(p.model).columns) k.emplace_back(s.key);
        return k;
      }, "Element column keys, e.g. ['alpha', 'k', 'C']")
      .def("__getitem__", [](const ModelParams& p, const std::string& k) {
        try { return p.scalar(k); } catch (const InputError&) {
          throw py::key_error("friction: no parameter '" + k + "' in model " + p.model);
        }
      })
      .def("__setitem__", [](ModelParams& p, const std::string& k, double v) {
        if (model_info(p.model).scalar_index(k) < 0)
          throw py::key_error("friction: no parameter '" + k + "' in model " + p.model);
        p.set_scalar(k, v);
      })
      .def("column", &ModelParams::column, py::arg("key"), "One element column, e.g. column('k') [N/m]")
      .def("__eq__", [](const ModelParams& a, const ModelParams& b) { return a == b; })
      .def("__repr__", [](const ModelParams& p) { return "<ModelParams " + to_json(p).dump() + ">"; });

  py::class_<Plant>(m, "Plant", "The body: mass [kg], spring to ground [N/m], damper to ground [N s/m]")
      .def_readwrite("mass", &Plant::mass, "m [kg], > 0")
      .def_readwrite("spring", &Plant::spring, "k [N/m], >= 0")
      .def_readwrite("damper", &Plant::damper, "c [N s/m], >= 0");
  py::class_<RunSettings>(m, "RunSettings", "Integration step dt [s], duration [s], record_every [-]")
      .def_readwrite("dt", &RunSettings::dt, "Integration step [s]")
      .def_readwrite("duration", &RunSettings::duration, "Simulated time [s]")
      .def_readwrite("record_every", &RunSettings::record_every, "Keep every n-th step in the trace [-]");

  py::class_<Scenario>(m, "Scenario",
                       "A scenario preset: friction, plant, drive and run settings. Edit the fields "
                       "(sc.plant.mass = 2.0, sc.friction['Fs'] = 1.2, sc.run.dt = 1e-5), then "
                       "validate() or simulate(); drive via the 'drive' dict")
      .def(py::init([](py::dict d) { return scenario_from_json(from_py(d), "<dict>"); }), py::arg("data"),
           "A scenario from a dict in the preset JSON schema (validated; InputError names the key)")
      .def_readwrite("name", &Scenario::name)
      .def_readwrite("description", &Scenario::description)
      .def_readwrite("friction", &Scenario::friction)
      .def_readwrite("plant", &Scenario::plant)
      .def_readwrite("run", &Scenario::run)
      .def_property("drive", [](const Scenario& s) { return to_py(to_json(s)["drive"]); },
                    [](Scenario& s, py::dict d) {
                      auto j = to_json(s);
                      j["drive"] = from_py(d);
                      s = scenario_from_json(j, "<scenario>");
                    }, "The drive as a dict (type, signal, spring, damper), as in the preset JSON")
      .def("to_dict", [](const Scenario& s) { return to_py(to_json(s)); }, "The preset JSON as a dict")
      .def_static("from_dict", [](py::dict d) { return scenario_from_json(from_py(d), "<dict>"); }, py::arg("data"),
                  "A scenario from a dict in the preset JSON schema (to_dict, an identify report's 'scenario'); "
                  "validated, InputError names the key")
      .def("validate", [](const Scenario& s) { (void)validated(s, "<scenario>"); },
           "Checks every field as a preset file is checked; raises InputError naming the key and the range")
      .def("stability_limit_dt", [](const Scenario& s) { return stability_limit_dt(s); },
           "Largest stable integration step [s] for this plant and friction")
      .def("__eq__", [](const Scenario& a, const Scenario& b) { return a == b; })
      .def("__repr__", [](const Scenario& s) { return "<Scenario '" + s.name + "'>"; });

  m.def("load_scenario", &load_scenario_arg, py::arg("path"),
        "Loads a scenario preset (JSON): a path (str or os.PathLike), or a shipped preset's name "
        "(\"fig2a_presliding\") from any folder; InputError names the file and the key path");
  m.def("save_scenario", [](const Scenario& s, const py::object& path_obj) {
    const std::string path = path_arg(path_obj, "path");
    save_scenario(validated(s, path), path);
  },
        py::arg("scenario"), py::arg("path"), "Validates and writes the preset atomically");

  // ---- simulation ------------------------------------------------------------------------
  py::class_<PyTrace>(m, "Trace", "A simulated trace; arrays are NumPy copies")
      .def_property_readonly("t", [](const PyTrace& p) { return arr(p.tr.t); }, "time [s]")
      .def_property_readonly("x", [](const PyTrace& p) { return arr(p.tr.x); }, "position [m]")
      .def_property_readonly("v", [](const PyTrace& p) { return arr(p.tr.v); }, "velocity [m/s]")
      .def_property_readonly("friction", [](const PyTrace& p) { return arr(p.tr.friction); }, "friction force F_f [N]")
      .def_property_readonly("applied", [](const PyTrace& p) { return arr(p.tr.applied); },
                             "drive force on the body [N] (prescribed motion: F_f)")
      .def_property_readonly("element_force", [](const PyTrace& p) {
        py::array_t<double> a({p.tr.size(), p.tr.n_elements});
        std::copy(p.tr.element_force.begin(), p.tr.element_force.end(), a.mutable_data());
        return a;
      }, "element forces F_i [N], shape (samples, elements)")
      .def_property_readonly("element_slip", [](const PyTrace& p) {
        py::array_t<bool> a({p.tr.size(), p.tr.n_elements});
        for (std::size_t i = 0; i < p.tr.element_slip.size(); ++i) a.mutable_data()[i] = p.tr.element_slip[i] != 0;
        return a;
      }, "element slipping (True) or sticking, shape (samples, elements)")
      .def("__len__", [](const PyTrace& p) { return p.tr.size(); });

  py::class_<PyPlantTrace>(m, "PlantTrace", "A simulated assembled plant's trace; arrays are NumPy copies")
      .def_property_readonly("t", [](const PyPlantTrace& p) { return arr(p.tr.t); }, "time [s]")
      .def_property_readonly("outputs", [](const PyPlantTrace& p) {
        std::vector<std::string> names;
        for (const auto& c : p.tr.channels) names.push_back(c.name);
        return names;
      }, "the output names: x.BODY [m], v.BODY [m/s] per body, then F.PART [N] per contact, spring, damper, drive")
      .def("output", [](const PyPlantTrace& p, const std::string& name) { return arr(p.tr.series(name)); },
           py::arg("name"), "one output's samples; InputError names the outputs there are")
      .def_property_readonly("contact_slip", [](const PyPlantTrace& p) {
        py::dict d;
        for (const auto& c : p.tr.channels) {
          if (c.kind != Channel::Kind::ContactForce) continue;
          const auto& flags = p.tr.contact_slip[static_cast<std::size_t>(c.index)];
          py::array_t<bool> a(flags.size());
          for (std::size_t k = 0; k < flags.size(); ++k) a.mutable_data()[k] = flags[k] != 0;
          d[py::str(c.name.substr(2))] = a;
        }
        return d;
      }, "per contact name: in gross slip (True) at each sample")
      .def("__len__", [](const PyPlantTrace& p) { return p.tr.size(); });

  m.def("simulate", [](const py::object& sc_or_path) -> py::object {
    // A preset path loads once (load_preset): an assembled plant gives a PlantTrace.
    std::optional<Scenario> sc;
    std::optional<AssemblyScenario> plant;
    if (py::isinstance<Scenario>(sc_or_path)) {
      sc = sc_or_path.cast<Scenario>();
    } else {
      const Preset preset = load_preset(resolve_preset_arg(path_arg(sc_or_path, "path")));
      if (preset.assembled()) plant = preset.scenario;
      else sc = preset.one_body();
    }
    if (plant) {
      PyPlantTrace out;
      {
        py::gil_scoped_release nogil;
        out.tr = simulate(*plant);
      }
      return py::cast(std::move(out));
    }
    PyTrace out;
    {
      py::gil_scoped_release nogil;
      out.tr = simulate(*sc);
    }
    return py::cast(std::move(out));
  }, py::arg("scenario"),
        "Simulates a Scenario or a preset (path or shipped name) to its end on the one engine. A "
        "one-body scenario gives a Trace (t [s], x [m], v [m/s], friction [N], applied [N], "
        "element_force [N], element_slip); an assembled plant (schema 2) a PlantTrace (t, outputs, "
        "output(name), contact_slip). InputError for a bad scenario, SimulationError when the run "
        "diverges");

  // ---- friction models -------------------------------------------------------------------
  m.def("models", [] {
    py::list out;
    auto specs = [](const std::vector<ParamSpec>& v) {
      py::list l;
      for (const auto& s : v)
        l.append(py::dict("key"_a = std::string(s.key), "symbol"_a = std::string(s.symbol),
                          "unit"_a = std::string(s.unit), "help"_a = std::string(s.help), "lo"_a = s.lo,
                          "hi"_a = s.hi, "range"_a = s.range_text()));
      return l;
    };
    for (const auto& i : model_registry())
      out.append(py::dict("tag"_a = std::string(i.tag), "name"_a = std::string(i.name),
                          "citation"_a = std::string(i.citation), "equation"_a = std::string(i.equation),
                          "scalars"_a = specs(i.scalars), "columns"_a = specs(i.columns),
                          "min_elements"_a = i.min_elements, "max_elements"_a = i.max_elements));
    return out;
  }, "Every registry model: tag, name, citation, equation, parameter specs (key, unit, range)");

  py::class_<PyModel>(m, "Model", "A friction model with its state: step it with a velocity, read its force and elements")
      .def(py::init([](const py::object& o) {
        if (py::isinstance<py::str>(o)) return PyModel(model_info(o.cast<std::string>()).defaults());
        return PyModel(o.cast<ModelParams>());
      }), py::arg("model"), "A model from a registry tag (its defaults) or from ModelParams (validated)")
      .def("reset", [](PyModel& p) { p.model->reset(p.state); }, "Back to the virgin state")
      .def("step", [](PyModel& p, double v, double h, double f_other, double mass) {
        check_step(h, "step");
        if (!std::isfinite(v)) throw InputError("step: v = " + std::to_string(v) + ": the velocity must be finite");
        if (!std::isfinite(f_other) || !(std::isfinite(mass) && mass >= 0.0))
          throw InputError("step: f_other must be finite and mass finite and >= 0 kg");
        return p.model->step(p.state, {v, h, f_other, mass});
      }, py::arg("v"), py::arg("h"), py::arg("f_other") = 0.0, py::arg("mass") = 0.0,
           "One step at sliding velocity v [m/s] frozen over h [s]; returns the friction force [N]")
      .def("run", [](PyModel& p, py::array_t<double> v, double h) {
        check_step(h, "run");
        if (v.ndim() != 1) throw InputError("run: v must be a 1-D array of velocities [m/s], got " +
                                            std::to_string(v.ndim()) + "-D");
        auto vin = v.unchecked<1>();
        for (py::ssize_t i = 0; i < vin.shape(0); ++i)
          if (!std::isfinite(vin(i)))
            throw InputError("run: v[" + std::to_string(i) + "] = " + std::to_string(vin(i)) +
                             ": every velocity must be finite (nothing was stepped)");
        py::array_t<double> out(vin.shape(0));
        auto o = out.mutable_unchecked<1>();
        {
          py::gil_scoped_release nogil;
          for (py::ssize_t i = 0; i < vin.shape(0); ++i) o(i) = p.model->step(p.state, {vin(i), h, 0.0, 0.0});
        }
        return out;
      }, py::arg("v"), py::arg("h"), "Steps through a velocity array v [m/s] with step h [s]; friction [N] per step")
      .def_property_readonly("state", [](const PyModel& p) { return arr(p.state); }, "The model's state vector")
      .def("elements", [](const PyModel& p) {
        py::list l;
        for (std::size_t i = 0; i < p.model->element_count(); ++i) {
          const auto e = p.model->element(p.state, i);
          l.append(py::make_tuple(e.force, e.slipping));
        }
        return l;
      }, "Per element (force [N], slipping)")
      .def("steady_state", [](const PyModel& p, double v) { return p.model->steady_state(v); }, py::arg("v"),
           "Steady-state friction at constant velocity v [m/s] [N]")
      .def("break_away", [](const PyModel& p) { return p.model->break_away(); }, "Break-away force [N]")
      .def_property_readonly("params", [](const PyModel& p) { return p.model->params(); });

  // ---- design ------------------------------------------------------------------------------
  m.def("design", [](double zeta, double wn, std::optional<std::vector<double>> num,
                     std::optional<std::vector<double>> den, py::object scenario, const std::string& regime,
                     double velocity, std::optional<double> K, double max_ratio, double margin,
                     const std::string& drive, const std::string& output, std::optional<std::string> compensator,
                     double sample_time) {
    // The compensator type checked first, as the CLI's option check does.
    std::optional<control::CompensatorType> type;
    if (compensator) {
      type = control::compensator_type_from_string(*compensator);
      if (!type) throw InputError("compensator '" + *compensator + "': expected lead, lag, lead_lag, pi or pid");
    }
    // The request as `gmslab design` builds it (control::design_report: the design job and its JSON).
    control::DesignRequest req;
    control::PlantChoice& choice = req.plant;
    if (!scenario.is_none()) {
      if (num || den) throw InputError("give either scenario or num/den, not both");
      const bool path = !py::isinstance<Scenario>(scenario);  // str, os.PathLike or a preset name
      req.source = path ? resolve_preset_arg(path_arg(scenario, "scenario")) : std::string();
      std::optional<Preset> preset;
      if (path) preset = load_preset(req.source);
      if ((preset && preset->assembled()) || !drive.empty() || !output.empty()) {
        req.assembly = preset ? preset->scenario : assembly_from_scenario(scenario.cast<Scenario>());
        choice.source = control::PlantSource::Assembly;
        choice.drive = drive;
        choice.output = output;
      } else {
        req.scenario = preset ? preset->one_body() : scenario.cast<Scenario>();
        if (!path) req.source = req.scenario->name;
      }
    } else {
      if (!num || !den) throw InputError("give the plant as num and den (coefficients, highest power first), or scenario");
      auto text = [](const std::vector<double>& c) {
        std::string s;
        char b[40];
        for (double x : c) { std::snprintf(b, sizeof b, "%.17g ", x); s += b; }
        return s;
      };
      choice.source = control::PlantSource::Typed;
      choice.num = text(*num);
      choice.den = text(*den);
    }
    req.regime = control::regime_from_string(regime);
    req.velocity = velocity;
    req.root = {zeta, wn};
    req.K = K;
    req.options = {max_ratio, margin};
    req.sample_time = sample_time;
    req.compensator = type;
    nlohmann::json json;
    {
      py::gil_scoped_release release;
      json = control::design_report(req).json;
    }
    py::object out = to_py(json);
    complex_roots(out);
    return out;
  }, py::arg("zeta"), py::arg("wn"), py::arg("num") = py::none(), py::arg("den") = py::none(),
        py::arg("scenario") = py::none(), py::arg("regime") = "presliding", py::arg("velocity") = 0.0,
        py::arg("K") = py::none(), py::arg("max_ratio") = 20.0, py::arg("margin") = 0.1,
        py::arg("drive") = "", py::arg("output") = "", py::arg("compensator") = py::none(),
        py::arg("sample_time") = 0.0,
        "Phase-lead design (as `gmslab design --json`): desired roots zeta [-], wn [rad/s]; plant as "
        "num/den coefficients (highest power first, G(s) in m/N) or a scenario (path or Scenario) "
        "linearised in `regime` at `velocity` [m/s]; an assembled preset (schema 2) or drive / output "
        "names: from the force / pull `drive` to the `output` x.BODY; K: desired error constant (None: usable maximum). "
        "compensator: 'lead' | 'lag' | 'lead_lag' | 'pi' | 'pid' adds key typed_compensator (the Design view's "
        "compensator of that type, as `gmslab design --compensator`: type, kind, error, compensator {num, den, Kc, "
        "sections, matlab, python}, closed_loop_poles, gain_point, lag {factor, K, K_without_lag, slow_pole, "
        "slow_time_constant_s}, limit_cycles); sample_time [s]: controller sample time (0: continuous). "
        "Returns the report dict (phi_deg, K_max, z, p, Kc, closed_loop_poles, ...)");

  m.def("root_locus", [](const std::vector<double>& num, const std::vector<double>& den, bool negative,
                         const std::vector<double>& extra_gains) {
    auto text = [](const std::vector<double>& c) {
      std::string s;
      char b[40];
      for (double x : c) { std::snprintf(b, sizeof b, "%.17g ", x); s += b; }
      return s;
    };
    control::TransferFunction L{control::parse_polynomial(text(num), "num"), control::parse_polynomial(text(den), "den")};
    L.check_proper("num/den");
    control::LocusOptions opt;
    opt.negative = negative;
    opt.extra_gains = extra_gains;
    control::RootLocus r;
    {
      py::gil_scoped_release nogil;
      r = control::root_locus(L, opt);
    }
    py::array_t<std::complex<double>> br({r.branches.size(), r.gains.size()});
    for (std::size_t b = 0; b < r.branches.size(); ++b)
      for (std::size_t k = 0; k < r.gains.size() && k < r.branches[b].size(); ++k) br.mutable_at(b, k) = r.branches[b][k];
    py::list bk, cr;
    for (const auto& p : r.breakaways) bk.append(py::make_tuple(p.s, p.k));
    for (const auto& p : r.crossings) cr.append(py::make_tuple(p.s, p.k));
    py::dict d;
    d["poles"] = carr(r.poles);
    d["zeros"] = carr(r.zeros);
    d["gains"] = arr(r.gains);
    d["branches"] = br;
    d["centroid"] = r.centroid;
    d["asymptote_angles"] = arr(r.asymptote_angles);
    d["breakaways"] = bk;
    d["crossings"] = cr;
    d["infinite_gain"] = r.infinite_gain ? py::cast(*r.infinite_gain) : py::none();
    d["view"] = py::make_tuple(r.view.re_min, r.view.re_max, r.view.im_min, r.view.im_max);
    return d;
  }, py::arg("num"), py::arg("den"), py::arg("negative") = false, py::arg("extra_gains") = std::vector<double>{},
        "Root locus of L(s) = num/den (coefficients, highest power first): poles, zeros [rad/s], gains, "
        "branches (complex array [branch, gain]; NaN where a root is at infinity), centroid, "
        "asymptote_angles [rad], breakaways and crossings as (s, k)");

  // ---- identification ------------------------------------------------------------------------
  m.def("load_record", [](const py::object& path_obj, const std::string& columns, const std::string& force) {
    const std::string path = path_arg(path_obj, "path");
    CsvColumns cols = columns.empty() ? CsvColumns{} : parse_column_map(columns);
    cols.force = force;
    const auto r = load_measured(path, cols);
    py::dict d;
    d["t"] = arr(r.t), d["x"] = arr(r.x), d["F"] = arr(r.F);
    if (!r.v.empty()) d["v"] = arr(r.v);
    if (!r.Fn.empty()) d["Fn"] = arr(r.Fn);
    for (const auto& [n, c] : r.extra) d[py::str(n)] = arr(c);
    return d;
  }, py::arg("path"), py::arg("columns") = "", py::arg("force") = "",
        "A measured record (CSV in any common dialect, or MATLAB .mat) as a dict of arrays: t [s], x [m], "
        "F [N], optional v [m/s], Fn [N] and the other numeric columns; columns as --columns, force as "
        "--force (\"friction\" or \"applied\" for a gmslab simulate trace)");

  m.def("load_trace", [](const py::object& path_obj) {
    const auto cols = load_trace_columns(path_arg(path_obj, "path"));
    py::dict d;
    for (const auto& c : cols) d[py::str(c.name)] = arr(c.values);
    return d;
  }, py::arg("path"),
        "A trace file as `gmslab simulate` writes it (.csv, .h5/.hdf5 or .mat; any CSV with a header) as a "
        "dict of arrays by column name (t_s, x_m, v_mps, F_friction_N, F_applied_N, F1_N, slip1, ...), in file order "
        "(a .mat: by name)");

  m.def("identify", [](const py::object& data_obj, const py::object& validate_obj, const std::string& columns,
                       const std::string& model, const py::object& elements_obj, const std::string& mask,
                       const std::string& validate_mask, const std::string& mask_edges, double holdout,
                       const std::string& method, int starts, int max_evals, double min_gain,
                       const std::string& effects, const std::string& compare, double compare_seconds,
                       const std::string& force) {
    const std::string data = path_arg(data_obj, "data");
    const std::string validate = validate_obj.is_none() ? std::string() : path_arg(validate_obj, "validate");
    // elements: a whole number (2) or a string ("2", "auto"), checked as --elements is.
    std::string elements;
    if (py::isinstance<py::bool_>(elements_obj))
      throw InputError("elements: expected a whole number 1..64 or \"auto\", got a bool");
    else if (py::isinstance<py::int_>(elements_obj)) elements = py::str(elements_obj).cast<std::string>();
    else if (py::isinstance<py::float_>(elements_obj) && std::isfinite(elements_obj.cast<double>()) &&
             elements_obj.cast<double>() == std::round(elements_obj.cast<double>()) &&
             std::abs(elements_obj.cast<double>()) < 1e6)  // 2.0 (a sweep's range): the whole number
      elements = std::to_string(static_cast<long>(elements_obj.cast<double>()));
    else if (py::isinstance<py::str>(elements_obj)) elements = elements_obj.cast<std::string>();
    else
      throw InputError("elements: expected a whole number 1..64 or \"auto\", got " +
                       py::str(py::type::of(elements_obj).attr("__name__")).cast<std::string>());
    ident::IdentifyJob job;
    job.train.force = job.validation.force = force;
    job.train.path = data;
    job.validation.path = validate;
    job.train.columns = job.validation.columns = columns;
    job.train.mask = mask;
    job.validation.mask = validate_mask;
    job.train.mask_edges = job.validation.mask_edges = mask_edges;
    job.validation.mask_what = "validate_mask";
    job.train.mask_what = "mask";
    job.train.edges_what = job.validation.edges_what = "mask_edges";
    job.spec.model = model;
    job.spec.elements = ident::parse_element_count(elements, "elements");
    if (!(holdout >= 0.1 && holdout <= 0.5)) throw InputError("holdout: must be in [0.1, 0.5]");
    job.holdout = holdout;
    if (method != "bobyqa" && method != "sbplx" && method != "neldermead")
      throw InputError("method '" + method + "': expected bobyqa, sbplx or neldermead");
    job.method = method;
    if (starts < 1 || starts > 50) throw InputError("starts: must be in [1, 50]");
    job.starts = starts;
    if (max_evals < 20 || max_evals > 100000) throw InputError("max_evals: must be in [20, 100000]");
    job.max_evaluations = max_evals;
    if (!(min_gain >= 0.0 && min_gain <= 0.9)) throw InputError("min_gain: must be in [0, 0.9]");
    job.min_gain = min_gain;
    if (!compare.empty()) job.compare = ident::parse_model_list(compare);
    job.compare_seconds = compare_seconds;
    std::size_t a = 0;
    while (a < effects.size()) {
      auto b = effects.find(',', a);
      if (b == std::string::npos) b = effects.size();
      if (b > a) job.candidates.push_back(ident::effect_from_name(effects.substr(a, b - a)));
      a = b + 1;
    }
    std::optional<ident::IdentifyOutcome> out;
    {
      py::gil_scoped_release nogil;
      out = ident::run_identification(job);
    }
    nlohmann::json j = to_json(out->report);
    j["notes_job"] = out->notes;
    py::dict d = to_py(j);
    // A dict (the preset JSON), so the whole report is JSON-serialisable; Scenario.from_dict(d) makes it
    // a Scenario again.
    d["scenario"] = to_py(to_json(ident::identified_scenario(out->report, out->train)));
    return d;
  }, py::arg("data"), py::arg("validate") = py::none(), py::arg("columns") = "", py::arg("model") = "gms",
        py::arg("elements") = 4, py::arg("mask") = "", py::arg("validate_mask") = "", py::arg("mask_edges") = "",
        py::arg("holdout") = 0.25, py::arg("method") = "bobyqa", py::arg("starts") = 3, py::arg("max_evals") = 500,
        py::arg("min_gain") = 0.03, py::arg("effects") = "", py::arg("compare") = "",
        py::arg("compare_seconds") = ident::kCompareSeconds, py::arg("force") = "",
        "Identification as `gmslab identify` (same job and options): returns the report as a dict (the "
        "CLI's report JSON, JSON-serialisable) with 'scenario': the identified model as the preset JSON dict "
        "(gmslab.Scenario.from_dict(report['scenario']) for a Scenario)");

  // ---- figures -------------------------------------------------------------------------------
  m.def("figure_ids", &figure_ids, "Ids of the paper's figures, e.g. 'fig2a_presliding'");
  m.def("figure", [](const std::string& id) {
    Figure f;
    const std::string presets = preset_dir();
    {
      py::gil_scoped_release nogil;
      f = make_figure(id, presets);
    }
    py::list panels;
    for (const auto& p : f.panels) {
      py::list series;
      for (const auto& s : p.series) {
        py::dict sd;
        sd["label"] = s.label;
        sd["x"] = arr(s.x);
        sd["y"] = arr(s.y);
        sd["style"] = s.style == Series::Style::Solid ? "solid" : s.style == Series::Style::Dashed ? "dashed" : "dotted";
        series.append(sd);
      }
      py::dict pd;
      pd["letter"] = p.letter, pd["title"] = p.title, pd["x_label"] = p.x_label, pd["y_label"] = p.y_label;
      pd["series"] = series;
      panels.append(pd);
    }
    py::dict d;
    d["id"] = f.id, d["title"] = f.title, d["caption"] = f.caption, d["panels"] = panels;
    return d;
  }, py::arg("id"),
        "One of the paper's figures as data: id, title, caption, panels [{letter, title, x_label, y_label "
        "(with units), series [{label, x, y, style}]}]");
}

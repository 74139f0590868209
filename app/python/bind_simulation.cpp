// gmslab Python module: simulation - Trace, PlantTrace and simulate (one engine for one-body and
// assembled presets).
#include "app/python/bindings.hpp"
#include "core/error.hpp"
#include "core/io/preset_io.hpp"

namespace gmslab::py_bindings {

using namespace pybind11::literals;
namespace {
void bind_traces(py::module_& m) {
  py::class_<PyTrace>(m, "Trace", "A simulated trace; arrays are NumPy copies")
      .def_property_readonly(
          "t", [](const PyTrace& p) { return arr(p.tr.t); }, "time [s]")
      .def_property_readonly(
          "x", [](const PyTrace& p) { return arr(p.tr.x); }, "position [m]")
      .def_property_readonly(
          "v", [](const PyTrace& p) { return arr(p.tr.v); }, "velocity [m/s]")
      .def_property_readonly(
          "friction", [](const PyTrace& p) { return arr(p.tr.friction); }, "friction force F_f [N]")
      .def_property_readonly(
          "applied", [](const PyTrace& p) { return arr(p.tr.applied); },
          "drive force on the body [N] (prescribed motion: F_f)")
      .def_property_readonly(
          "element_force",
          [](const PyTrace& p) {
            py::array_t<double> a({p.tr.size(), p.tr.n_elements});
            std::copy(p.tr.element_force.begin(), p.tr.element_force.end(), a.mutable_data());
            return a;
          },
          "element forces F_i [N], shape (samples, elements)")
      .def_property_readonly(
          "element_slip",
          [](const PyTrace& p) {
            py::array_t<bool> a({p.tr.size(), p.tr.n_elements});
            for (std::size_t i = 0; i < p.tr.element_slip.size(); ++i)
              a.mutable_data()[i] = p.tr.element_slip[i] != 0;
            return a;
          },
          "element slipping (True) or sticking, shape (samples, elements)")
      .def("__len__", [](const PyTrace& p) { return p.tr.size(); });

  py::class_<PyPlantTrace>(m, "PlantTrace",
                           "A simulated assembled plant's trace; arrays are NumPy copies")
      .def_property_readonly(
          "t", [](const PyPlantTrace& p) { return arr(p.tr.t); }, "time [s]")
      .def_property_readonly(
          "outputs",
          [](const PyPlantTrace& p) {
            std::vector<std::string> names;
            for (const auto& c : p.tr.channels) names.push_back(c.name);
            return names;
          },
          "the output names: x.BODY [m], v.BODY [m/s] per body, then F.PART [N] per contact, "
          "spring, damper, drive")
      .def(
          "output",
          [](const PyPlantTrace& p, const std::string& name) { return arr(p.tr.series(name)); },
          py::arg("name"), "one output's samples; InputError names the outputs there are")
      .def_property_readonly(
          "contact_slip",
          [](const PyPlantTrace& p) {
            py::dict d;
            for (const auto& c : p.tr.channels) {
              if (c.kind != Channel::Kind::ContactForce) continue;
              const auto& flags = p.tr.contact_slip[static_cast<std::size_t>(c.index)];
              py::array_t<bool> a(flags.size());
              for (std::size_t k = 0; k < flags.size(); ++k) a.mutable_data()[k] = flags[k] != 0;
              d[py::str(c.name.substr(2))] = a;
            }
            return d;
          },
          "per contact name: in gross slip (True) at each sample")
      .def("__len__", [](const PyPlantTrace& p) { return p.tr.size(); });
}
}  // namespace

void bind_simulation(py::module_& m) {
  bind_traces(m);
  m.def(
      "simulate",
      [](const py::object& sc_or_path) -> py::object {
        // A preset path loads once (load_preset): an assembled plant gives a PlantTrace.
        std::optional<Scenario> sc;
        std::optional<AssemblyScenario> plant;
        if (py::isinstance<Scenario>(sc_or_path)) {
          sc = sc_or_path.cast<Scenario>();
        } else {
          const Preset preset = load_preset(resolve_preset_arg(path_arg(sc_or_path, "path")));
          if (preset.assembled())
            plant = preset.scenario;
          else
            sc = preset.one_body();
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
      },
      py::arg("scenario"),
      "Simulates a Scenario or a preset (path or shipped name) to its end on the one engine. A "
      "one-body scenario gives a Trace (t [s], x [m], v [m/s], friction [N], applied [N], "
      "element_force [N], element_slip); an assembled plant (schema 2) a PlantTrace (t, outputs, "
      "output(name), contact_slip). InputError for a bad scenario, SimulationError when the run "
      "diverges");
}

}  // namespace gmslab::py_bindings

// gmslab Python module: friction models - the registry (models()) and Model (a model with its
// state).
#include "app/python/bindings.hpp"
#include "core/error.hpp"
#include "core/friction/param_specs.hpp"

namespace gmslab::py_bindings {

using namespace pybind11::literals;
void bind_models(py::module_& m) {
  m.def(
      "models",
      [] {
        py::list out;
        auto specs = [](const std::vector<ParamSpec>& v) {
          py::list l;
          for (const auto& s : v)
            l.append(py::dict("key"_a = std::string(s.key), "symbol"_a = std::string(s.symbol),
                              "unit"_a = std::string(s.unit), "help"_a = std::string(s.help),
                              "lo"_a = s.lo, "hi"_a = s.hi, "range"_a = s.range_text()));
          return l;
        };
        for (const auto& i : model_registry())
          out.append(py::dict(
              "tag"_a = std::string(i.tag), "name"_a = std::string(i.name),
              "citation"_a = std::string(i.citation), "equation"_a = std::string(i.equation),
              "scalars"_a = specs(i.scalars), "columns"_a = specs(i.columns),
              "min_elements"_a = i.min_elements, "max_elements"_a = i.max_elements));
        return out;
      },
      "Every registry model: tag, name, citation, equation, parameter specs (key, unit, range)");

  py::class_<PyModel>(
      m, "Model",
      "A friction model with its state: step it with a velocity, read its force and elements")
      .def(py::init([](const py::object& o) {
             if (py::isinstance<py::str>(o))
               return PyModel(model_info(o.cast<std::string>()).defaults());
             return PyModel(o.cast<ModelParams>());
           }),
           py::arg("model"),
           "A model from a registry tag (its defaults) or from ModelParams (validated)")
      .def(
          "reset", [](PyModel& p) { p.model->reset(p.state); }, "Back to the virgin state")
      .def(
          "step",
          [](PyModel& p, double v, double h, double f_other, double mass) {
            check_step(h, "step");
            if (!std::isfinite(v))
              throw InputError("step: v = " + std::to_string(v) + ": the velocity must be finite");
            if (!std::isfinite(f_other) || !(std::isfinite(mass) && mass >= 0.0))
              throw InputError("step: f_other must be finite and mass finite and >= 0 kg");
            return p.model->step(p.state, {v, h, f_other, mass});
          },
          py::arg("v"), py::arg("h"), py::arg("f_other") = 0.0, py::arg("mass") = 0.0,
          "One step at sliding velocity v [m/s] frozen over h [s]; returns the friction force [N]")
      .def(
          "run",
          [](PyModel& p, py::array_t<double> v, double h) {
            check_step(h, "run");
            if (v.ndim() != 1)
              throw InputError("run: v must be a 1-D array of velocities [m/s], got " +
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
              for (py::ssize_t i = 0; i < vin.shape(0); ++i)
                o(i) = p.model->step(p.state, {vin(i), h, 0.0, 0.0});
            }
            return out;
          },
          py::arg("v"), py::arg("h"),
          "Steps through a velocity array v [m/s] with step h [s]; friction [N] per step")
      .def_property_readonly(
          "state", [](const PyModel& p) { return arr(p.state); }, "The model's state vector")
      .def(
          "elements",
          [](const PyModel& p) {
            py::list l;
            for (std::size_t i = 0; i < p.model->element_count(); ++i) {
              const auto e = p.model->element(p.state, i);
              l.append(py::make_tuple(e.force, e.slipping));
            }
            return l;
          },
          "Per element (force [N], slipping)")
      .def(
          "steady_state", [](const PyModel& p, double v) { return p.model->steady_state(v); },
          py::arg("v"), "Steady-state friction at constant velocity v [m/s] [N]")
      .def(
          "break_away", [](const PyModel& p) { return p.model->break_away(); },
          "Break-away force [N]")
      .def_property_readonly("params", [](const PyModel& p) { return p.model->params(); });
}

}  // namespace gmslab::py_bindings

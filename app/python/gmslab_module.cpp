// gmslab Python module (_gmslab, wrapped by the package app/python/gmslab): the core's jobs as
// Python calls with NumPy arrays. Every call runs the same core function the CLI and the window
// run (load_scenario, simulate on the one engine, build_model, design_report, root_locus,
// run_identification, make_figure, load_measured). Core errors become Python exceptions carrying
// the same message: InputError -> gmslab.InputError (a ValueError), SimulationError ->
// gmslab.SimulationError (a RuntimeError), IoError -> gmslab.IoError (an OSError). Long calls
// release the GIL. The bindings are split by area (bind_*.cpp, bindings.hpp).
#include "app/python/bindings.hpp"
#include "core/error.hpp"

PYBIND11_MODULE(_gmslab, m) {
  namespace py = pybind11;
  using namespace gmslab;
  m.doc() = "gmslab: GMS friction simulation, compensation design and identification (C++ core)";

  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);
  py::register_exception<SimulationError>(m, "SimulationError", PyExc_RuntimeError);
  py::register_exception<IoError>(m, "IoError", PyExc_OSError);
  py::register_exception<InternalError>(m, "InternalError", PyExc_RuntimeError);

  py_bindings::bind_scenarios(m);
  py_bindings::bind_simulation(m);
  py_bindings::bind_models(m);
  py_bindings::bind_design(m);
  py_bindings::bind_identification(m);
  py_bindings::bind_figures(m);
}

// gmslab Python module (_gmslab): what the binding files share - the conversions (JSON <-> Python,
// NumPy arrays), path and preset arguments, the argument checks, and the wrapped types - and the
// binding function of each area, called in turn by PYBIND11_MODULE (gmslab_module.cpp).
#pragma once

#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <complex>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/control/polynomial.hpp"
#include "core/friction/model.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab::py_bindings {

namespace py = pybind11;

py::object to_py(const nlohmann::json& j);
nlohmann::json from_py(const py::object& o);
py::array_t<double> arr(const std::vector<double>& v);
py::array_t<std::complex<double>> carr(const std::vector<control::cplx>& v);
// Coefficients as the text parse_polynomial reads (17 significant digits each).
std::string coefficient_text(const std::vector<double>& c);

// The presets (gmslab::presets_dir): env GMSLAB_PRESETS, the source tree's, the installed ones next
// to this package (PREFIX/share/gmslab/presets), or those under the configured install prefix.
// Called with the GIL held.
std::string preset_dir();
// The design dict with its roots as complex numbers, as root_locus gives them: every
// "closed_loop_poles" ([[re, im], ...]) a complex NumPy array; "s_d", "slow_pole" and a gain
// point's "s" ([re, im]) a complex. gmslab.to_json turns them back into the CLI's JSON.
void complex_roots(py::handle o);
// A path argument: str or any os.PathLike (pathlib.Path), as open() takes it. `what` names the
// argument in the TypeError.
std::string path_arg(const py::object& o, const char* what);
// A preset path as given, or a shipped preset's bare name (gmslab::resolve_preset, as the CLI and
// the window's --open take it); the error names the closest preset and lists them.
std::string resolve_preset_arg(const std::string& path);
Scenario load_scenario_arg(const py::object& o);
// A scenario checked the way a preset file is (every key, type and range; messages name the key).
Scenario validated(const Scenario& s, const std::string& where);
// The step h [s] and the velocities of Model.step / Model.run, checked as the CLI checks run.dt
// ((0, 1] s) and a drive: finite.
void check_step(double h, const char* what);

// A friction model with its state: build any registry model, step it, read state and elements.
struct PyModel {
  std::unique_ptr<FrictionModel> model;
  std::vector<double> state;
  explicit PyModel(const ModelParams& p);  // validates: InputError listing every problem
};

struct PyTrace {
  Trace tr;
};

struct PyPlantTrace {
  AssemblyTrace tr;
};

// The bindings by area, each adding its classes and functions to the module.
void bind_scenarios(py::module_& m);       // ModelParams, Plant, RunSettings, Scenario, load / save
void bind_simulation(py::module_& m);      // Trace, PlantTrace, simulate
void bind_models(py::module_& m);          // models(), Model
void bind_design(py::module_& m);          // design, root_locus
void bind_identification(py::module_& m);  // load_record, load_trace, identify
void bind_figures(py::module_& m);         // figure_ids, figure

}  // namespace gmslab::py_bindings

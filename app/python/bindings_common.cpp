// gmslab Python module: the helpers the binding files share (bindings.hpp).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/python/bindings.hpp"
#include "core/error.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::py_bindings {

py::object to_py(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}
nlohmann::json from_py(const py::object& o) {
  return nlohmann::json::parse(py::module_::import("json").attr("dumps")(o).cast<std::string>());
}

py::array_t<double> arr(const std::vector<double>& v) {
  return py::array_t<double>(v.size(), v.data());
}
py::array_t<std::complex<double>> carr(const std::vector<control::cplx>& v) {
  return py::array_t<std::complex<double>>(v.size(), v.data());
}

// The presets (gmslab::presets_dir): env GMSLAB_PRESETS, the source tree's, the installed ones next
// to this package (PREFIX/lib/python3/dist-packages/gmslab -> PREFIX/share/gmslab/presets, as the
// .deb lays them out), or those under the configured install prefix. Called with the GIL held.
std::string preset_dir() {
  namespace fs = std::filesystem;
  const fs::path here =
      fs::path(py::module_::import("gmslab").attr("__file__").cast<std::string>()).parent_path();
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
        if (!is_pair(r)) {
          all = false;
          break;
        }
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
Scenario validated(const Scenario& s, const std::string& where) {
  return scenario_from_json(to_json(s), where);
}

// The step h [s] and the velocities of Model.step / Model.run, checked as the CLI checks run.dt
// ((0, 1] s) and a drive: finite.
void check_step(double h, const char* what) {
  if (!(std::isfinite(h) && h > 0.0 && h <= 1.0))
    throw InputError(std::string(what) + ": h = " + std::to_string(h) +
                     " s: must be in (0, 1] s (as run.dt)");
}

PyModel::PyModel(const ModelParams& p) {
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

std::string coefficient_text(const std::vector<double>& c) {
  std::string s;
  char b[40];
  for (double x : c) {
    std::snprintf(b, sizeof b, "%.17g ", x);
    s += b;
  }
  return s;
}

}  // namespace gmslab::py_bindings

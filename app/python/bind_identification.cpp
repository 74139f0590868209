// gmslab Python module: identification - load_record, load_trace and identify (the job of
// `gmslab identify`, with its options checked as the CLI checks them).
#include <cmath>
#include <optional>

#include "app/python/bindings.hpp"
#include "core/error.hpp"
#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "core/io/measured_file.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_file.hpp"

namespace gmslab::py_bindings {

namespace {

// elements: a whole number (2) or a string ("2", "auto"), checked as --elements is.
std::string element_text(const py::object& elements_obj) {
  if (py::isinstance<py::bool_>(elements_obj))
    throw InputError("elements: expected a whole number 1..64 or \"auto\", got a bool");
  if (py::isinstance<py::int_>(elements_obj)) return py::str(elements_obj).cast<std::string>();
  if (py::isinstance<py::float_>(elements_obj) && std::isfinite(elements_obj.cast<double>()) &&
      elements_obj.cast<double>() == std::round(elements_obj.cast<double>()) &&
      std::abs(elements_obj.cast<double>()) < 1e6)  // 2.0 (a sweep's range): the whole number
    return std::to_string(static_cast<long>(elements_obj.cast<double>()));
  if (py::isinstance<py::str>(elements_obj)) return elements_obj.cast<std::string>();
  throw InputError("elements: expected a whole number 1..64 or \"auto\", got " +
                   py::str(py::type::of(elements_obj).attr("__name__")).cast<std::string>());
}

// The options of the fit, checked in the CLI's order and ranges.
void set_fit_options(ident::IdentifyJob& job, double holdout, const std::string& method, int starts,
                     int max_evals, double min_gain, const std::string& effects,
                     const std::string& compare, double compare_seconds) {
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
}

py::dict identify(const py::object& data_obj, const py::object& validate_obj,
                  const std::string& columns, const std::string& model,
                  const py::object& elements_obj, const std::string& mask,
                  const std::string& validate_mask, const std::string& mask_edges, double holdout,
                  const std::string& method, int starts, int max_evals, double min_gain,
                  const std::string& effects, const std::string& compare, double compare_seconds,
                  const std::string& force) {
  const std::string data = path_arg(data_obj, "data");
  const std::string validate =
      validate_obj.is_none() ? std::string() : path_arg(validate_obj, "validate");
  const std::string elements = element_text(elements_obj);
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
  set_fit_options(job, holdout, method, starts, max_evals, min_gain, effects, compare,
                  compare_seconds);
  std::optional<ident::IdentifyOutcome> out;
  {
    py::gil_scoped_release nogil;
    out = ident::run_identification(job);
  }
  nlohmann::json j = to_json(out->report);
  j["notes_job"] = out->notes;
  py::dict d = to_py(j);
  // A dict (the preset JSON), so the whole report is JSON-serialisable; Scenario.from_dict(d) makes
  // it a Scenario again.
  d["scenario"] = to_py(to_json(ident::identified_scenario(out->report, out->train)));
  return d;
}

}  // namespace

void bind_identification(py::module_& m) {
  m.def(
      "load_record",
      [](const py::object& path_obj, const std::string& columns, const std::string& force) {
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
      },
      py::arg("path"), py::arg("columns") = "", py::arg("force") = "",
      "A measured record (CSV in any common dialect, or MATLAB .mat) as a dict of arrays: t [s], x "
      "[m], "
      "F [N], optional v [m/s], Fn [N] and the other numeric columns; columns as --columns, force "
      "as "
      "--force (\"friction\" or \"applied\" for a gmslab simulate trace)");

  m.def(
      "load_trace",
      [](const py::object& path_obj) {
        const auto cols = load_trace_columns(path_arg(path_obj, "path"));
        py::dict d;
        for (const auto& c : cols) d[py::str(c.name)] = arr(c.values);
        return d;
      },
      py::arg("path"),
      "A trace file as `gmslab simulate` writes it (.csv, .h5/.hdf5 or .mat; any CSV with a "
      "header) as a "
      "dict of arrays by column name (t_s, x_m, v_mps, F_friction_N, F_applied_N, F1_N, slip1, "
      "...), in file order "
      "(a .mat: by name)");

  m.def("identify", &identify, py::arg("data"), py::arg("validate") = py::none(),
        py::arg("columns") = "", py::arg("model") = "gms", py::arg("elements") = 4,
        py::arg("mask") = "", py::arg("validate_mask") = "", py::arg("mask_edges") = "",
        py::arg("holdout") = 0.25, py::arg("method") = "bobyqa", py::arg("starts") = 3,
        py::arg("max_evals") = 500, py::arg("min_gain") = 0.03, py::arg("effects") = "",
        py::arg("compare") = "", py::arg("compare_seconds") = ident::kCompareSeconds,
        py::arg("force") = "",
        "Identification as `gmslab identify` (same job and options): returns the report as a dict "
        "(the "
        "CLI's report JSON, JSON-serialisable) with 'scenario': the identified model as the preset "
        "JSON dict "
        "(gmslab.Scenario.from_dict(report['scenario']) for a Scenario)");
}

}  // namespace gmslab::py_bindings

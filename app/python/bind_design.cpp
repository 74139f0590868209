// gmslab Python module: control design - design (the design job of `gmslab design --json`) and
// root_locus.
#include <cstdio>
#include <optional>

#include "app/python/bindings.hpp"
#include "core/control/design_report.hpp"
#include "core/control/root_locus.hpp"
#include "core/error.hpp"
#include "core/io/preset_io.hpp"

namespace gmslab::py_bindings {

namespace {

// The plant of a design request: a scenario (path, shipped name or Scenario; an assembled preset or
// drive / output names: the assembled plant) or num / den coefficients.
void choose_plant(control::DesignRequest& req, const std::optional<std::vector<double>>& num,
                  const std::optional<std::vector<double>>& den, const py::object& scenario,
                  const std::string& drive, const std::string& output) {
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
    return;
  }
  if (!num || !den)
    throw InputError(
        "give the plant as num and den (coefficients, highest power first), or scenario");
  choice.source = control::PlantSource::Typed;
  choice.num = coefficient_text(*num);
  choice.den = coefficient_text(*den);
}

py::object design(double zeta, double wn, std::optional<std::vector<double>> num,
                  std::optional<std::vector<double>> den, py::object scenario,
                  const std::string& regime, double velocity, std::optional<double> K,
                  double max_ratio, double margin, const std::string& drive,
                  const std::string& output, std::optional<std::string> compensator,
                  double sample_time) {
  // The compensator type checked first, as the CLI's option check does.
  std::optional<control::CompensatorType> type;
  if (compensator) {
    type = control::compensator_type_from_string(*compensator);
    if (!type)
      throw InputError("compensator '" + *compensator +
                       "': expected lead, lag, lead_lag, pi or pid");
  }
  // The request as `gmslab design` builds it (control::design_report: the design job and its JSON).
  control::DesignRequest req;
  choose_plant(req, num, den, scenario, drive, output);
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
}

py::dict root_locus(const std::vector<double>& num, const std::vector<double>& den, bool negative,
                    const std::vector<double>& extra_gains) {
  control::TransferFunction L{control::parse_polynomial(coefficient_text(num), "num"),
                              control::parse_polynomial(coefficient_text(den), "den")};
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
    for (std::size_t k = 0; k < r.gains.size() && k < r.branches[b].size(); ++k)
      br.mutable_at(b, k) = r.branches[b][k];
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
}

}  // namespace

void bind_design(py::module_& m) {
  m.def(
      "design", &design, py::arg("zeta"), py::arg("wn"), py::arg("num") = py::none(),
      py::arg("den") = py::none(), py::arg("scenario") = py::none(),
      py::arg("regime") = "presliding", py::arg("velocity") = 0.0, py::arg("K") = py::none(),
      py::arg("max_ratio") = 20.0, py::arg("margin") = 0.1, py::arg("drive") = "",
      py::arg("output") = "", py::arg("compensator") = py::none(), py::arg("sample_time") = 0.0,
      "Phase-lead design (as `gmslab design --json`): desired roots zeta [-], wn [rad/s]; plant as "
      "num/den coefficients (highest power first, G(s) in m/N) or a scenario (path or Scenario) "
      "linearised in `regime` at `velocity` [m/s]; an assembled preset (schema 2) or drive / "
      "output "
      "names: from the force / pull `drive` to the `output` x.BODY; K: desired error constant "
      "(None: usable maximum). "
      "compensator: 'lead' | 'lag' | 'lead_lag' | 'pi' | 'pid' adds key typed_compensator (the "
      "Design view's "
      "compensator of that type, as `gmslab design --compensator`: type, kind, error, compensator "
      "{num, den, Kc, "
      "sections, matlab, python}, closed_loop_poles, gain_point, lag {factor, K, K_without_lag, "
      "slow_pole, "
      "slow_time_constant_s}, limit_cycles); sample_time [s]: controller sample time (0: "
      "continuous). "
      "Returns the report dict (phi_deg, K_max, z, p, Kc, closed_loop_poles, ...)");
  m.def("root_locus", &root_locus, py::arg("num"), py::arg("den"), py::arg("negative") = false,
        py::arg("extra_gains") = std::vector<double>{},
        "Root locus of L(s) = num/den (coefficients, highest power first): poles, zeros [rad/s], "
        "gains, "
        "branches (complex array [branch, gain]; NaN where a root is at infinity), centroid, "
        "asymptote_angles [rad], breakaways and crossings as (s, k)");
}

}  // namespace gmslab::py_bindings

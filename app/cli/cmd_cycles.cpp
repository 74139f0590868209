// gmslab cycles: periodic orbits (limit cycles) of a preset's position loop with a given
// controller, their stability, a long simulation of the same loop and the hunting map over a gain
// scale.
//
//   gmslab cycles PRESET --controller-num "1000 5000" --controller-den "1 0" [--drive D --output O]
//                 [--gain-scale LO:HI:N] [--sample-time T] [--amplitude R] --json OUT
// The controller Kc prod (s + z_i) / prod (s + p_i) (one or two real sections, p_i = 0: an
// integrator) as numerator / denominator coefficients, highest power first. The loop, its step, the
// orbits and the simulation are the design job's (compute_design with this compensator as a manual
// one, periodic_orbits and hunting_map on: core/control/design_session.hpp); the JSON is
// cycles_json (core/control/design_report.hpp). OUT may be '-' (stdout).
#include <algorithm>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/cli/cli.hpp"
#include "core/control/design_report.hpp"
#include "core/control/polynomial.hpp"
#include "core/error.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/preset_io.hpp"

namespace gmslab::cli {

namespace {
using namespace gmslab::control;

struct Opts {
  std::string preset, num, den, drive, output, json;
  std::string gain_scale = "0.2:5:13";
  double amplitude = 0.01, T = 0.0;
};

// The real roots of p as positive numbers r (p has roots at -r); InputError naming `what` for a
// complex root or one in the right half plane (or at 0 when zero_ok is false).
std::vector<double> negated_real_roots(const Poly& p, const std::string& what, bool zero_ok) {
  std::vector<double> r;
  for (const cplx& x : p.roots()) {
    if (std::abs(x.imag()) > 1e-9 * std::max(1.0, std::abs(x)))
      throw InputError(what +
                       ": complex roots are not a compensator section (real zeros and poles only)");
    const double v = x.real() == 0.0 ? 0.0 : -x.real();
    if (v < 0.0 || (!zero_ok && v == 0.0))
      throw InputError(what + ": a root at s = " + std::to_string(x.real()) +
                       (zero_ok ? " (poles must be at s <= 0)" : " (zeros must be at s < 0)"));
    r.push_back(v);
  }
  std::sort(r.begin(), r.end());
  return r;
}

LeadCompensator compensator_from(const std::string& num, const std::string& den) {
  const Poly N = parse_polynomial(num, "--controller-num"),
             D = parse_polynomial(den, "--controller-den");
  if (N.degree() != D.degree() || N.degree() < 1 || N.degree() > 2)
    throw InputError(
        "--controller-num / --controller-den: the same degree, 1 or 2 (one or two sections "
        "(s + z)/(s + p)); got " +
        std::to_string(N.degree()) + " and " + std::to_string(D.degree()));
  const std::vector<double> z = negated_real_roots(N, "--controller-num", false),
                            p = negated_real_roots(D, "--controller-den", true);
  const double Kc = N.lead() / D.lead();
  if (!(Kc > 0.0))
    throw InputError(
        "--controller-num / --controller-den: the gain (ratio of the leading coefficients) must be "
        "> 0");
  LeadCompensator C{Kc, z[0], p[0]};
  if (z.size() == 2) C.second = Section{z[1], p[1]};
  check_compensator(C, "--controller-num / --controller-den");
  return C;
}

DesignInputs::GainGrid gain_grid(const std::string& text) {
  DesignInputs::GainGrid g;
  char c1 = 0, c2 = 0;
  std::istringstream in(text);
  if (!(in >> g.lo >> c1 >> g.hi >> c2 >> g.n) || c1 != ':' || c2 != ':' ||
      !(in >> std::ws).eof() || !(g.lo > 0.0) || !(g.hi > g.lo) || g.n < 2 || g.n > 200)
    throw InputError("--gain-scale '" + text +
                     "': expected LO:HI:N with 0 < LO < HI and N in [2, 200]");
  return g;
}

int run_cycles(const Opts& o) {
  DesignInputs in;
  const Preset preset = load_preset(resolve_preset(o.preset, presets_dir()));  // a bare name too
  if (preset.assembled() || !o.drive.empty() || !o.output.empty()) {
    in.assembly = preset.scenario;
    in.plant.source = PlantSource::Assembly;
    in.plant.drive = o.drive;
    in.plant.output = o.output;
  } else {
    in.scenario = preset.one_body();
  }
  in.manual = compensator_from(o.num, o.den);
  if (!(o.amplitude != 0.0) || !std::isfinite(o.amplitude))
    throw InputError("--amplitude must be finite and non-zero [m]");
  in.reference = Signal::constant(o.amplitude);
  in.sample_time = o.T;
  in.view = false;
  in.accuracy = Accuracy::Report;
  in.loop_compensations = {Compensation::None};
  in.periodic_orbits = true;
  in.hunting_map = gain_grid(o.gain_scale);
  const DesignOutputs out = compute_design(in);
  // The design stage's lead (not used: the compensator is given) may fail; the loop's may not.
  if (!out.orbits || out.loops.empty() || out.loops.front().trace.t.empty()) throw_failure(out);
  const nlohmann::json j = cycles_json(in, out);
  const std::string text = j.dump(2) + "\n";
  std::ostream& os = o.json == "-" ? std::cerr : std::cout;
  if (o.json == "-")
    std::cout << text;
  else
    write_file_atomic(o.json, text);
  for (const auto& orb : j["orbits"])
    os << (orb["stable"].get<bool>() ? "stable" : "unstable") << " orbit: amplitude "
       << orb["amplitude_m"].get<double>() << " m, period " << orb["period_s"].get<double>()
       << " s, stick " << orb["stick_fraction"].get<double>() << '\n';
  if (j["orbits"].empty()) os << j["not_found"].get<std::string>() << '\n';
  const auto& s = j["simulation"];
  os << "simulation: "
     << (s["hunting"].get<bool>()
             ? "hunting, amplitude " + std::to_string(s["amplitude_m"].get<double>()) +
                   " m, period " + std::to_string(s["period_s"].get<double>()) + " s"
             : std::string("no hunting"))
     << '\n';
  if (o.json != "-") os << "wrote " << o.json << '\n';
  return 0;
}
}  // namespace

void register_cycles(CLI::App& app, Action& action) {
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand(
      "cycles",
      "Limit cycles of a preset's loop with a given controller: periodic orbits, their stability, "
      "a long simulation and the hunting map over a gain scale");
  sub->add_option("preset", o->preset,
                  "Scenario or assembled preset (JSON file, or a shipped preset's name)")
      ->required();
  sub->add_option("--controller-num", o->num,
                  "Controller numerator, highest power first, e.g. \"1000 5000\"")
      ->required();
  sub->add_option("--controller-den", o->den,
                  "Controller denominator, highest power first, e.g. \"1 0\" (an integrator)")
      ->required();
  sub->add_option("--drive", o->drive,
                  "Assembled plant: the force or pull drive the controller acts through");
  sub->add_option("--output", o->output,
                  "Assembled plant: the measured output x.BODY (default: x of the drive's body)");
  sub->add_option("--gain-scale", o->gain_scale,
                  "Hunting map: controller gain scales LO:HI:N (geometric)")
      ->capture_default_str();
  sub->add_option("--sample-time", o->T, "Controller sample time [s] (0 = continuous; Tustin)")
      ->capture_default_str();
  sub->add_option("--amplitude", o->amplitude, "Constant set point [m]")->capture_default_str();
  sub->add_option("--json", o->json, "Write the result as JSON to this file ('-' = stdout)")
      ->required();
  sub->preparse_callback([o](std::size_t) { *o = Opts{}; });
  sub->callback([&action, o] { action = [o] { return run_cycles(*o); }; });
}

}  // namespace gmslab::cli

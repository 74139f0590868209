// gmslab design: phase-lead design with the largest reachable error constant
// for typed plant coefficients or a scenario's plant.
//
//   gmslab design --num "4" --den "1 2 0" --zeta 0.5 --wn 4 [--K 5] [--max-ratio 20] --json OUT
//   gmslab design --preset SCENARIO.json --zeta 0.7 --wn 60 [--regime sliding] [--K 1000]
//                 [--simulate --reference ramp --compensation all] --json OUT
//   gmslab design --preset presets/two_mass_drive.json --drive motor_force --output x.load ...
// The plant comes from core/control/design_plant.hpp (the Design tab's function): typed
// coefficients, a v1 scenario's one body, or an assembled plant (schema 2, or a v1 preset with
// --drive / --output) from a drive to an output. The design, its JSON and --simulate's loops are
// the design job's (core/control/design_report.hpp: the Design view's compute_design).
// OUT may be '-' (stdout). Without --K the design is the usable maximum (p/z = --max-ratio).
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "app/cli/cli.hpp"
#include "core/control/design_report.hpp"
#include "core/control/scenario_plant.hpp"
#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"

namespace gmslab::cli {

namespace {
using namespace gmslab::control;

struct Opts {
  std::string num, den, preset, json;
  std::string drive, output;  // assembled plant: drive name, output x.BODY / v.BODY
  std::string regime = "presliding";
  double velocity = 0.0;
  double zeta = 0.0, wn = 0.0;
  std::optional<double> K;
  double max_ratio = 20.0, margin = 0.1;
  bool simulate = false;
  std::string reference = "step", compensation = "all";
  std::string feedforward = "reference";  // what drives the compensation: reference | measured velocity
  double amplitude = 0.01, slope = 0.01, frequency = 1.0, duration = 2.0, dt = 0.0, T = 0.0;
  double mm_force = 1.0, mm_stiffness = 1.0, mm_velocity = 1.0;
  std::optional<double> lag_K;  // lead-lag: error constant the lag must reach
  double lag_zero_fraction = 0.1;
  std::string compensator;  // lag | lead_lag | pi | pid: also the Design view's compensator of that type
};

Signal reference_signal(const Opts& o) {
  if (o.reference == "step") return Signal::constant(o.amplitude);
  if (o.reference == "ramp") return Signal::ramp(0.0, o.slope);
  if (o.reference == "sine") {
    if (!(o.frequency > 0.0)) throw InputError("--frequency must be > 0 Hz");
    return Signal::sine(0.0, o.amplitude, o.frequency);
  }
  throw InputError("--reference '" + o.reference + "': expected step, ramp or sine");
}

// Short numbers for the summary (6 significant digits; "n/a" for null).
std::string f(const nlohmann::json& v) {
  if (!v.is_number()) return "n/a";
  std::ostringstream o;
  o.precision(6);
  o << v.get<double>();
  return o.str();
}

std::string poles_text(const nlohmann::json& poles) {
  std::string s;
  for (const auto& p : poles) {
    if (!p[1].is_number() || p[1].get<double>() < 0.0) continue;
    s += (s.empty() ? "" : ", ") + f(p[0]) + (p[1].get<double>() > 0.0 ? " +- j" + f(p[1]) : "");
  }
  return s;
}

void print_summary(std::ostream& os, const nlohmann::json& j) {
  const std::string k = j["constant"].get<std::string>();
  os << "single lead applicable: " << (j["applicable"].get<bool>() ? "yes" : "no");
  if (j.contains("reason")) os << " (" << j["reason"].get<std::string>() << ")";
  os << "\nphi = " << f(j["phi_deg"]) << " deg, K0 = " << f(j["K0"]) << ", " << k << "_max = "
     << f(j["K_max"]) << ", usable (p/z <= " << f(j["max_ratio"]) << ") = " << f(j["K_max_usable"]) << '\n';
  if (j.contains("z") && !j["z"].is_null())
    os << "design (" << (j.contains("design_kind") ? j["design_kind"].get<std::string>() : std::string("requested"))
       << "): Gc = " << f(j["Kc"]) << " (s + "
       << f(j["z"]) << ") / (s + " << f(j["p"]) << "), " << k << " = " << f(j["K"])
       << "\nclosed-loop poles: " << poles_text(j["closed_loop_poles"]) << '\n';
  if (j.contains("notes") && j["notes"].is_array())
    for (const auto& n : j["notes"]) os << "note: " << n.get<std::string>() << '\n';
  if (j.contains("relocations"))
    for (const auto& r : j["relocations"]) {
      os << "relocation " << r["path"].get<std::string>() << ": ";
      if (r["found"].get<bool>()) {
        os << "wn = " << f(r["wn"]) << " rad/s, zeta = " << f(r["zeta"]) << ", Gc = " << f(r["Kc"])
           << " (s + " << f(r["z"]) << ") / (s + " << f(r["p"]) << ")\n";
        for (const auto& n : r["notes"]) os << "  note: " << n.get<std::string>() << '\n';
      } else
        os << "none: " << r["reason"].get<std::string>() << '\n';
    }
  if (j.contains("frequency")) {
    const auto& m = j["frequency"]["margins"];
    const auto& c = j["frequency"]["closed_loop"];
    const auto& n = j["frequency"]["nyquist"];
    // null margins are infinite (no crossover)
    const auto gm = m["gain_margin_db"].is_null() ? std::string("inf (no phase crossover)")
                                                  : f(m["gain_margin_db"]) + " dB at " + f(m["phase_crossover_rad_s"]) + " rad/s";
    const auto pm = m["phase_margin_deg"].is_null() ? std::string("inf (no gain crossover)")
                                                    : f(m["phase_margin_deg"]) + " deg at " + f(m["gain_crossover_rad_s"]) + " rad/s";
    os << "margins (" << j["frequency"]["loop"].get<std::string>() << " loop): GM = " << gm << ", PM = " << pm
       << "; closed loop: bandwidth " << f(c["bandwidth_rad_s"])
       << " rad/s, peak " << f(c["peak_db"]) << " dB; Nyquist: N = " << n["encirclements"].get<int>()
       << ", P = " << n["open_rhp_poles"].get<int>() << ", Z = " << n["closed_rhp_poles"].get<int>()
       << (n["marginal"].get<bool>() ? " (marginal: a closed-loop pole on the axis, or not countable)"
           : n["stable"].get<bool>() ? " (stable)" : " (unstable)") << '\n';
  }
  if (j.contains("limit_cycles") && j["limit_cycles"].contains("periodic_orbits")) {
    const auto& po = j["limit_cycles"]["periodic_orbits"];
    if (po["orbits"].empty())
      os << "periodic orbits: none (" << po["not_found"].get<std::string>() << ")\n";
    for (const auto& o : po["orbits"])
      os << "periodic orbit: " << (o["stable"].get<bool>() ? "stable" : "unstable")
         << ", amplitude " << f(o["amplitude_m"]) << " m, period " << f(o["period_s"]) << " s\n";
  }
  if (j.contains("limit_cycles") && j["limit_cycles"].contains("cycles")) {
    const auto& lc = j["limit_cycles"];
    if (lc["cycles"].empty()) os << "describing function: no limit cycle predicted (" << lc["note"].get<std::string>() << ")\n";
    for (const auto& c : lc["cycles"])
      os << "describing function: " << (c["stable"].get<bool>() ? "stable" : "unstable (threshold)")
         << " limit cycle, amplitude " << f(c["amplitude_m"]) << " m, period " << f(c["period_s"]) << " s\n";
    if (lc.contains("hunting")) {
      if (lc["hunting"]["cycles"].empty()) os << "hunting: none predicted (" << lc["hunting"]["note"].get<std::string>() << ")\n";
      for (const auto& c : lc["hunting"]["cycles"])
        os << "hunting (stick-slip DF): amplitude " << f(c["amplitude_m"]) << " m, period " << f(c["period_s"])
           << " s" << (c["valid"].get<bool>() ? "" : " (outside the DF's validity)") << '\n';
    }
  }
  if (j.contains("simulation"))
    for (const auto& s : j["simulation"])
      os << "loop with friction, " << s["compensation"].get<std::string>()
         << ": e_ss = " << f(s["steady_state_error_m"]) << " m, RMS = " << f(s["rms_error_m"])
         << " m, overshoot = " << f(s["overshoot_percent"]) << " %, settling = "
         << f(s["settling_time_s"]) << " s" << (s["hunting"].get<bool>() ? ", hunting: amplitude " +
            f(s["cycle_amplitude_m"]) + " m, period " + f(s["cycle_period_s"]) + " s" : "") << '\n';
}

int run_design(const Opts& o) {
  DesignRequest req;
  std::string file;  // the preset's file (a shipped preset's bare name resolved)
  if (!o.preset.empty()) {
    if (!o.num.empty() || !o.den.empty())
      throw InputError("give either --preset or --num/--den, not both");
    file = resolve_preset(o.preset, presets_dir(), "--preset");
    const Preset preset = load_preset(file);
    if (preset.assembled() || !o.drive.empty() || !o.output.empty()) {
      // An assembled plant; a v1 preset with --drive / --output as its one-body assembly.
      req.assembly = preset.scenario;
      req.plant.source = PlantSource::Assembly;
      req.plant.drive = o.drive;
      req.plant.output = o.output;
    } else {
      req.scenario = preset.one_body();
    }
  } else {
    if (o.num.empty() || o.den.empty())
      throw InputError("give the plant as --num and --den (coefficients, highest power first), "
                       "or --preset SCENARIO.json");
    typed_plant(o.num, o.den, "--num", "--den");  // the errors name the options
    req.plant.source = PlantSource::Typed;
    req.plant.num = o.num;
    req.plant.den = o.den;
  }
  req.source = file;
  req.regime = regime_from_string(o.regime);
  req.velocity = o.velocity;
  if (o.simulate && !req.scenario && !req.assembly)
    throw InputError("--simulate needs --preset (the friction to simulate with)");
  req.root = {o.zeta, o.wn};
  req.K = o.K;
  req.options = {o.max_ratio, o.margin};
  req.sample_time = o.T;
  if (!o.compensator.empty()) req.compensator = compensator_type_from_string(o.compensator);
  req.lag_K = o.lag_K;
  req.lag_zero_fraction = o.lag_zero_fraction;
  if (o.simulate) {
    req.simulate = true;
    req.reference = reference_signal(o);
    if (o.compensation == "all") req.compensations = {Compensation::None, Compensation::Coulomb, Compensation::Gms};
    else req.compensations = {compensation_from_string(o.compensation)};
    req.feedforward_source = *feedforward_source_from_string(o.feedforward);
    req.mismatch = {o.mm_force, o.mm_stiffness, o.mm_velocity};
    req.timing = {o.duration, o.dt, LoopConfig{}.record_every};
  }
  const nlohmann::json j = design_report(req).json;
  const std::string text = j.dump(2) + "\n";
  if (o.json == "-") {
    std::cout << text;
    print_summary(std::cerr, j);
  } else {
    if (!o.json.empty()) write_file_atomic(o.json, text);
    print_summary(std::cout, j);
    if (!o.json.empty()) std::cout << "wrote " << o.json << '\n';
  }
  return 0;
}
}  // namespace

void register_design(CLI::App& app, Action& action) {
  // Owned by the app (its callbacks hold it): each Cli has its own options.
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand(
      "design", "Phase-lead design on the root locus with the largest reachable error constant");
  sub->add_option("--num", o->num, "Plant numerator coefficients, highest power first, e.g. \"4\"");
  sub->add_option("--den", o->den, "Plant denominator coefficients, highest power first, e.g. \"1 2 0\"");
  sub->add_option("--preset", o->preset,
                  "Design for this preset's plant (a JSON file or a shipped preset's name): a "
                  "scenario (force -> position of the mass) or an assembled "
                  "plant (schema 2: from --drive to --output)");
  sub->add_option("--drive", o->drive,
                  "Assembled plant: the force or pull drive the controller acts through (default: the first)");
  sub->add_option("--output", o->output,
                  "Assembled plant: the measured output x.BODY [m] or v.BODY [m/s] (default: x of the drive's body)");
  sub->add_option("--regime", o->regime, "Scenario plant regime: presliding or sliding")->capture_default_str();
  sub->add_option("--velocity", o->velocity, "Sliding operating velocity v0 [m/s] (default 10 Vs)");
  sub->add_option("--zeta", o->zeta, "Damping ratio of the desired dominant roots, in (0, 1)")->required();
  sub->add_option("--wn", o->wn, "Natural frequency of the desired dominant roots [rad/s], 1e-12 to 1e12")->required();
  sub->add_option("--K", o->K, "Desired error constant (Kp, Kv or Ka by plant type), > 0");
  sub->add_option("--max-ratio", o->max_ratio, "Bound on p/z for the usable maximum, > 1")->capture_default_str();
  sub->add_option("--margin", o->margin, "Relocation target K (1 + margin), > 0")->capture_default_str();
  sub->add_option("--json", o->json, "Write the design as JSON to this file ('-' = stdout)");
  sub->add_flag("--simulate", o->simulate, "Simulate the loop with the scenario's friction");
  sub->add_option("--reference", o->reference, "Reference: step, ramp or sine")->capture_default_str();
  sub->add_option("--amplitude", o->amplitude, "Step height / sine amplitude [m]")->capture_default_str();
  sub->add_option("--slope", o->slope, "Ramp velocity [m/s]")->capture_default_str();
  sub->add_option("--frequency", o->frequency, "Sine frequency [Hz]")->capture_default_str();
  sub->add_option("--duration", o->duration, "Simulated time [s]")->capture_default_str();
  sub->add_option("--dt", o->dt, "Integration step [s] (default: the scenario's run.dt)");
  sub->add_option("--sample-time", o->T, "Controller sample time [s] (0 = continuous; Tustin)")->capture_default_str();
  sub->add_option("--compensation", o->compensation, "none, coulomb, gms or all")->capture_default_str();
  sub->add_option("--feedforward", o->feedforward,
                  "What drives the compensation's feedforward: the reference velocity, or the measured one "
                  "(the loop then sees F(v) - F_hat(v))")
      ->check(CLI::IsMember({"reference", "measured"}))
      ->capture_default_str();
  sub->add_option("--compensator", o->compensator,
                  "Also the Design view's compensator of this type (key typed_compensator: sections, export, "
                  "lag cost; K from --K, else 10x); --simulate then simulates it (else the lead)")
      ->check(CLI::IsMember({"lead", "lag", "lead_lag", "pi", "pid"}));
  sub->add_option("--lag-K", o->lag_K, "Lead-lag: add a lag after the lead reaching this error constant (> the lead's)");
  sub->add_option("--lag-zero", o->lag_zero_fraction, "Lead-lag: lag zero at this fraction of |Re s_d|, (0, 1]")
      ->capture_default_str();
  sub->add_option("--mismatch-force", o->mm_force, "Compensator's Fs, Fc / plant's [-]")->capture_default_str();
  sub->add_option("--mismatch-stiffness", o->mm_stiffness, "Compensator's k_i, sigma_i / plant's [-]")->capture_default_str();
  sub->add_option("--mismatch-velocity", o->mm_velocity, "Compensator's Vs / plant's [-]")->capture_default_str();
  // Defaults again at every parse of this command (a Cli may be run many times).
  sub->preparse_callback([o](std::size_t) { *o = Opts{}; });
  sub->callback([&action, o] { action = [o] { return run_design(*o); }; });
}

}  // namespace gmslab::cli

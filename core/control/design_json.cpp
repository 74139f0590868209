#include "core/control/design_json.hpp"

#include "core/control/discrete.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace gmslab::control {

namespace {
nlohmann::json num(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }
constexpr double kDeg = 180.0 / std::numbers::pi;

void put_design(nlohmann::json& j, const LeadDesign& d) {
  j["z"] = num(d.z);
  j["p"] = num(d.p);
  j["Kc"] = num(d.Kc);
  j["K"] = num(d.K);
  j["ratio"] = num(d.p / d.z);
  j["closed_loop_poles"] = poles_json(d.closed_loop_poles);
  j["dominant"] = d.dominance.dominant;
  j["notes"] = d.dominance.notes;
}
}  // namespace

nlohmann::json poles_json(const std::vector<cplx>& poles) {
  nlohmann::json a = nlohmann::json::array();
  for (const cplx& p : poles) a.push_back({num(p.real()), num(p.imag())});
  return a;
}

nlohmann::json to_json(const LeadReport& r) {
  nlohmann::json j;
  const LeadLimits& L = r.limits;
  j["zeta"] = r.root.zeta;
  j["wn"] = r.root.wn;
  j["s_d"] = {L.s_d.real(), L.s_d.imag()};
  j["type"] = r.type.n;
  j["constant"] = error_constant_name(r.type.n);
  j["K0"] = num(r.type.K0);
  j["applicable"] = L.applicable;
  if (!L.applicable) j["reason"] = L.reason;
  j["phi_deg"] = num(L.phi * kDeg);
  j["beta_deg"] = num(L.beta * kDeg);
  j["G_abs"] = num(L.G_abs);
  j["M"] = num(L.M);
  j["K_max"] = num(L.K_max);
  j["K_max_usable"] = num(r.K_max_usable);
  if (L.applicable) j["pd_limit"] = {{"Kd", num(L.pd_Kd)}, {"z", num(L.pd_z)}};
  if (r.usable_design) {
    const LeadDesign& u = *r.usable_design;
    j["usable_design"] = {{"z", num(u.z)}, {"p", num(u.p)}, {"Kc", num(u.Kc)}, {"K", num(u.K)}};
  }
  if (r.K_des) j["K_requested"] = *r.K_des;
  if (r.design) {
    put_design(j, *r.design);
    j["within_max_ratio"] = r.within_max_ratio;
  } else {  // one shape: the design's keys are always there, null without a design (no --K)
    for (const char* k : {"z", "p", "Kc", "K", "ratio", "closed_loop_poles", "dominant", "notes", "within_max_ratio"})
      j[k] = nullptr;
  }
  {  // always present (empty without relocations): one shape
    nlohmann::json a = nlohmann::json::array();
    for (const Relocation& rel : r.relocations) {
      nlohmann::json o;
      o["path"] = rel.path;
      o["name"] = rel.path;  // the same, under the word
      o["found"] = rel.found;
      if (rel.found) {
        o["wn"] = rel.root.wn;
        o["zeta"] = rel.root.zeta;
        o["K_max"] = num(rel.K_max);
        put_design(o, rel.design);
      } else {
        o["reason"] = rel.reason;
        o["peak_K"] = num(rel.peak_K);
        o["peak_wn"] = num(rel.peak_root.wn);
        o["peak_zeta"] = num(rel.peak_root.zeta);
      }
      a.push_back(o);
    }
    j["relocations"] = a;
  }
  return j;
}

nlohmann::json to_json(const FrequencyReport& f) {
  const Margins& m = f.margins;
  const Nyquist& n = f.nyquist;
  return {{"margins",
           {{"gain_margin", num(m.gain_margin)},
            {"gain_margin_db", num(m.gain_margin_db)},
            {"phase_crossover_rad_s", num(m.phase_crossover)},
            {"phase_margin_deg", num(m.phase_margin)},
            {"gain_crossover_rad_s", num(m.gain_crossover)},
            {"gain_crossovers_rad_s", m.gain_crossovers},
            {"phase_crossovers_rad_s", m.phase_crossovers}}},
          {"closed_loop",
           {{"dc_gain", num(f.dc_gain)},
            {"bandwidth_rad_s", num(f.bandwidth)},
            {"peak_db", num(f.peak_db)},
            {"peak_rad_s", num(f.peak_w)}}},
          {"nyquist",
           {{"open_rhp_poles", n.open_rhp_poles},
            {"axis_poles", n.axis_poles},
            {"encirclements", n.encirclements},
            {"closed_rhp_poles", n.closed_rhp_poles},
            {"marginal", n.marginal},
            {"stable", n.stable}}}};
}

nlohmann::json to_json(const DiscreteFrequencyReport& f) {
  FrequencyReport c;
  c.margins = f.margins;
  c.nyquist = f.nyquist;
  const nlohmann::json j = to_json(c);
  return {{"sample_time_s", f.T},
          {"nyquist_frequency_rad_s", f.nyquist_frequency},
          {"margins", j["margins"]},
          {"nyquist", j["nyquist"]},
          {"closed_loop_poles_z", poles_json(f.closed_loop_poles)}};
}

nlohmann::json to_json(const ZLocus& z, double Kc) {
  nlohmann::json c = nlohmann::json::array(), st = nlohmann::json::array();
  for (const UnitCircleCrossing& x : z.crossings)
    c.push_back({{"z", {x.z.real(), x.z.imag()}}, {"omega_rad_s", x.omega}, {"gain", x.k}});
  bool stable = false;
  for (const auto& [lo, hi] : z.stable_gains) {
    st.push_back({lo, num(hi)});
    stable |= Kc > lo && Kc < hi;
  }
  return {{"sample_time_s", z.T},
          {"gain", Kc},
          {"unit_circle_crossings", c},
          {"stable_gain_intervals", st},
          {"stable_at_gain", stable},
          {"open_loop_poles_z", poles_json(z.locus.poles)},
          {"open_loop_zeros_z", poles_json(z.locus.zeros)},
          {"branches", z.locus.branches.size()},
          {"gains_sampled", z.locus.gains.size()}};
}

nlohmann::json to_json(const LimitCycleReport& r) {
  nlohmann::json a = nlohmann::json::array();
  for (const LimitCycle& c : r.cycles)
    a.push_back({{"velocity_amplitude_m_s", num(c.velocity_amplitude)},
                 {"amplitude_m", num(c.amplitude)},
                 {"frequency_rad_s", num(c.frequency)},
                 {"period_s", num(c.period)},
                 {"stable", c.stable},
                 {"converged", c.converged}});
  return {{"cycles", a}, {"note", r.note}};
}

nlohmann::json to_json(const HuntingReport& r) {
  nlohmann::json a = nlohmann::json::array();
  for (const HuntingCycle& c : r.cycles)
    a.push_back({{"force_amplitude_N", num(c.force_amplitude)},
                 {"frequency_rad_s", num(c.frequency)},
                 {"period_s", num(c.period)},
                 {"amplitude_m", num(c.amplitude)},
                 {"first_harmonic_m", num(c.first_harmonic)},
                 {"waveform_error", num(c.waveform_error)},
                 {"phase_residual_deg", num(c.phase_residual * 180.0 / std::numbers::pi)},
                 {"stable", c.stable},
                 {"converged", c.converged},
                 {"valid", c.valid}});
  return {{"cycles", a}, {"wave", to_string(r.wave)}, {"break_away_N", num(r.break_away)},
          {"integral_gain_N_per_m_s", num(r.integral_gain)}, {"waveform_error_limit", kHuntingWaveformLimit},
          {"note", r.note}};
}

namespace {
std::string coeffs(const std::vector<double>& v) {
  std::string s;
  char buf[40];
  for (double x : v) {
    std::snprintf(buf, sizeof buf, "%.17g", x);
    s += (s.empty() ? "" : ", ") + std::string(buf);
  }
  return "[" + s + "]";
}
}  // namespace

std::string compensator_matlab(const LeadCompensator& c) {
  const TransferFunction t = c.tf();
  return "C = tf(" + coeffs(t.num.descending_coeffs()) + ", " + coeffs(t.den.descending_coeffs()) + ");";
}
std::string compensator_python(const LeadCompensator& c) {
  const TransferFunction t = c.tf();
  return "import control\nC = control.tf(" + coeffs(t.num.descending_coeffs()) + ", " + coeffs(t.den.descending_coeffs()) + ")";
}
nlohmann::json compensator_json(const LeadCompensator& c) {
  const TransferFunction t = c.tf();
  nlohmann::json sections = nlohmann::json::array();
  for (int i = 0; i < c.sections(); ++i) sections.push_back({{"z", c.section(i).z}, {"p", c.section(i).p}});
  return {{"num", t.num.descending_coeffs()}, {"den", t.den.descending_coeffs()}, {"Kc", c.Kc}, {"z", c.z}, {"p", c.p},
          {"sections", sections}, {"matlab", compensator_matlab(c)}, {"python", compensator_python(c)}};
}

nlohmann::json to_json(const LoopMetrics& m) {
  return {{"steady_state_error_m", num(m.steady_state_error)},
          {"tail_max_error_m", num(m.tail_max_error)},
          {"rms_error_m", num(m.rms_error)},
          {"overshoot_percent", num(m.overshoot)},
          {"settling_time_s", num(m.settling_time)},
          {"hunting", m.hunting},
          {"cycle_amplitude_m", num(m.cycle_amplitude)},
          {"cycle_period_s", num(m.cycle_period)}};
}

}  // namespace gmslab::control

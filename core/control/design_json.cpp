#include "core/control/design_json.hpp"

#include <cmath>
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

// gmslab ui: the Design panel - phase-lead design on the root locus with the largest reachable
// error constant (docs/references.md), linked to the loop simulated with the
// scenario's friction. Left: controls and results; right: the root-locus canvas
// (ui/design/design_locus.cpp) above the linked responses (ui/design/design_responses.cpp).
#include <imgui.h>

#include "ui/param_editor.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <imgui_stdlib.h>

#include "core/control/design_json.hpp"
#include "core/error.hpp"
#include "ui/design/design_view.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

namespace {
using control::cplx;
const ImVec4 kErr(0.75f, 0.10f, 0.10f, 1.0f);
const ImVec4 kOk(0.0f, 0.50f, 0.30f, 1.0f);
const ImVec4 kDim(0.35f, 0.35f, 0.38f, 1.0f);

void tip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

// The app's one number field (ui/param_editor.hpp: click to type, drag the handle), then the label.
bool input_double(const char* label, double* v, double lo, double hi, const char* /*fmt*/, const char* help,
                  bool log = false) {
  const std::string text(label);
  const auto open = text.find('['), close = text.find(']');
  const std::string unit = open != std::string::npos && close > open ? text.substr(open + 1, close - open - 1) : "-";
  const ParamSpec spec{label, label, unit, help, lo, hi, false, log};
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  const bool ch = edit_param(label, spec, *v, 0.0);
  ImGui::SameLine();
  ImGui::TextUnformatted(text.substr(0, text.find("##")).c_str());
  tip(help);
  return ch;
}

std::string poles_text(const std::vector<cplx>& poles) {
  std::string s;
  char buf[64];
  for (const cplx& p : poles) {
    if (p.imag() < 0) continue;
    if (p.imag() > 0) std::snprintf(buf, sizeof buf, "%.4g +- j%.4g\n", p.real(), p.imag());
    else std::snprintf(buf, sizeof buf, "%.4g\n", p.real());
    s += buf;
  }
  return s;
}

void sync(DesignViewState& d, const Scenario& scenario, int generation) {
  if (d.generation != generation || !(d.in.scenario == scenario)) {
    d.generation = generation;
    d.in.scenario = scenario;
    d.dirty = true;
  }
}

// The Plant tab's assembled plant, when it changed (or went away).
void sync_assembly(DesignViewState& d, const AssemblyScenario* assembly) {
  const bool same = assembly ? d.in.assembly && *d.in.assembly == *assembly : !d.in.assembly;
  if (same) return;
  if (assembly) d.in.assembly = *assembly;
  else d.in.assembly.reset();
  if (d.settings.plant.source == control::PlantSource::Assembly) d.dirty = true, d.in.locus_view.reset();
}

}  // namespace

bool apply_coefficient_edit(DesignViewState& d, bool den, const std::string& text) {
  std::string& error = den ? d.den_error : d.num_error;
  std::string& value = den ? d.settings.plant.den : d.settings.plant.num;
  try {
    control::typed_plant(den ? d.settings.plant.num : text, den ? text : d.settings.plant.den, "num", "den");
  } catch (const InputError& e) {
    error = std::string("rejected: ") + e.what() + "; in force: \"" + value + "\"";
    return false;
  }
  error.clear();
  (den ? d.num_error : d.den_error).clear();  // the pair is valid now
  if (value != text) {
    value = text;
    d.dirty = true, d.in.locus_view.reset(), d.picked = false;
  }
  return true;
}

namespace {
// One typed coefficient field: edited as text, applied when the edit ends and the pair is valid;
// a rejected edit shows why under the field, which goes back to the value in force.
void coefficient_field(DesignViewState& d, bool den) {
  std::string& edit = den ? d.den_edit : d.num_edit;
  std::string& error = den ? d.den_error : d.num_error;
  std::string& value = den ? d.settings.plant.den : d.settings.plant.num;
  const char* id = den ? "den(s)##typed_den" : "num(s)##typed_num";
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 12.0f);
  if (!error.empty()) ImGui::PushStyleColor(ImGuiCol_FrameBg, ImVec4(0.95f, 0.80f, 0.80f, 1.0f));
  ImGui::InputText(id, &edit);
  if (!error.empty()) ImGui::PopStyleColor();
  const bool active = ImGui::IsItemActive();
  tip(den ? "Denominator coefficients, highest power of s first, e.g. \"1 2 0\" for s^2 + 2 s; the leading "
            "coefficient must be non-zero and deg num <= deg den. Applied when you leave the field (Enter / Tab / click)"
          : "Numerator coefficients, highest power of s first, e.g. \"4\" or \"1 5\" for s + 5 (u -> y, e.g. [m/N]). "
            "Applied when you leave the field");
  if (ImGui::IsItemDeactivatedAfterEdit()) apply_coefficient_edit(d, den, edit);
  if (!active) edit = value;  // shows the value in force
  if (!error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErr);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(error.c_str());
    ImGui::PopTextWrapPos();
    ImGui::PopStyleColor();
  }
}

// Where G(s) comes from: the scenario's one body, the Plant tab's assembled plant from a drive to
// an output, or typed coefficients (core/control/design_plant.hpp).
void plant_source_section(DesignViewState& d, const AssemblyScenario* assembly) {
  control::PlantChoice& p = d.settings.plant;
  int src = static_cast<int>(p.source);  // the combo's items in PlantSource order
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 11.0f);
  if (ImGui::Combo("plant source", &src, "scenario (one body)\0assembled plant\0typed num/den\0")) {
    p.source = static_cast<control::PlantSource>(src);
    d.dirty = true, d.in.locus_view.reset(), d.picked = false;
  }
  tip("scenario: force -> position of the scenario's mass, with its friction.\n"
      "assembled plant: the Plant tab's plant (e.g. presets/two_mass_drive.json) from a drive to an output, "
      "the loops run on the assembled nonlinear plant.\ntyped num/den: your G(s), no friction (no loop with friction)");
  if (p.source == control::PlantSource::Typed) {
    coefficient_field(d, false);
    coefficient_field(d, true);
    return;
  }
  if (p.source != control::PlantSource::Assembly) return;
  if (!assembly) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErr);
    ImGui::TextWrapped("No assembled plant loaded: open a schema-2 preset (e.g. presets/two_mass_drive.json) in the Plant tab.");
    ImGui::PopStyleColor();
    return;
  }
  const Assembly& a = assembly->plant;
  auto combo = [&](const char* label, std::string& value, const std::vector<std::string>& names,
                   const std::vector<std::string>& items, const std::string& shown, const char* help) {
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 11.0f);
    if (ImGui::BeginCombo(label, shown.c_str())) {
      for (std::size_t i = 0; i < names.size(); ++i)
        if (ImGui::Selectable(items[i].c_str(), names[i] == value) && names[i] != value)
          value = names[i], d.dirty = true, d.in.locus_view.reset(), d.picked = false;
      ImGui::EndCombo();
    }
    tip(help);
  };
  std::vector<std::string> drives, drive_items, outputs, output_items;
  for (const auto& x : a.drives)
    if (x.kind == DrivePart::Kind::Force || x.kind == DrivePart::Kind::Pull) {
      drives.push_back(x.name);
      drive_items.push_back(x.name + " (" + to_string(x.kind) + " on " + a.bodies[static_cast<std::size_t>(x.body)].name + ")");
    }
  for (const std::string& y : control::assembly_outputs(a))
    outputs.push_back(y), output_items.push_back(y + (y[0] == 'v' ? " [m/s]" : " [m]"));
  // The names resolved as the design resolves them ("" = the first drive, its body's position).
  std::string drive_shown = p.drive.empty() ? "(first force / pull drive)" : p.drive;
  std::string output_shown = p.output.empty() ? "(the drive's body)" : p.output;
  try {
    const control::AssemblyPort port = control::assembly_port(a, p.drive, p.output);
    drive_shown = port.drive_name, output_shown = port.output;
  } catch (const InputError&) {  // the design reports it (red, under Results)
  }
  combo("drive u", p.drive, drives, drive_items, drive_shown,
        "The drive the controller acts through: a force drive (u = F [N]) or a pull drive (u = x_p [m])");
  combo("output y", p.output, outputs, output_items, output_shown,
        "The measured output, a position x [m] or a velocity v [m/s]: the drive's own body's position is collocated "
        "control (poles and zeros interlace), another body non-collocated (no finite zeros for an undamped chain; a "
        "damper c adds -k/c)");
  const auto port_body = [&]() -> std::string {
    try {
      const auto port = control::assembly_port(a, p.drive, p.output);
      return a.bodies[static_cast<std::size_t>(a.drives[port.drive].body)].name == port.output.substr(2) ? "collocated"
                                                                                                         : "non-collocated";
    } catch (const InputError&) {
      return "";
    }
  }();
  if (!port_body.empty()) ImGui::TextColored(kDim, "%s control of '%s'", port_body.c_str(), assembly->name.c_str());
}

void recompute(DesignViewState& d) {
  if (!d.dirty) return;
  control::set_design_inputs(d.settings, d.in);  // the panel only offers valid names
  const auto t0 = std::chrono::steady_clock::now();
  try {
    d.out = control::compute_design(d.in);
  } catch (const std::exception& e) {  // not a typed error: a bug; shown in this panel, not lost
    d.out = {};
    d.out.error = std::string("internal error: ") + e.what();
    d.out.error_kind = ErrorKind::Internal;
  }
  d.compute_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (d.picked) d.picked_poles = control::closed_loop_poles(d.out.loop, d.picked_k);
  d.dirty = false;
  hunting_map_request(d);  // the map of this design, in the background
}

// The plant of an assembled or typed source: what G(s) is (and, assembled, the regime of its
// contacts). Returns false for the scenario's plant (plant_section draws it).
bool plant_other_source(DesignViewState& d) {
  const control::PlantSource src = d.settings.plant.source;
  if (src == control::PlantSource::Scenario) return false;
  DesignSettings& s = d.settings;
  if (src == control::PlantSource::Assembly) {
    int regime = s.regime == "presliding" ? 0 : 1;
    bool ch = ImGui::RadioButton("contacts stuck", &regime, 0);
    tip("Every contact stuck: its elements add their stiffness sum k_i and micro-damping between its bodies");
    ImGui::SameLine();
    ch |= ImGui::RadioButton("sliding at v0", &regime, 1);
    tip("Every contact sliding at v0 (default 10 Vs of each contact): the local Stribeck slope plus sigma2 as a damper");
    if (ch) s.regime = regime == 0 ? "presliding" : "sliding", d.dirty = true, d.in.locus_view.reset(), d.picked = false;
    if (s.regime == "sliding") {  // 0: each contact at its own 10 Vs; shown as the first contact's
      double v0 = s.velocity;
      if (!(v0 > 0.0) && d.in.assembly && !d.in.assembly->plant.contacts.empty())
        v0 = control::default_sliding_velocity(d.in.assembly->plant.contacts.front().friction);
      if (!(v0 > 0.0)) v0 = 0.01;
      if (input_double("v0 [m/s]##assembly_v0", &v0, 1e-5, 1.0, "%.3g",
                       "Sliding velocity of every contact (until set: each contact's own 10 Vs)", true))
        s.velocity = v0, d.dirty = true, d.in.locus_view.reset();
    }
    d.dirty |= ImGui::Checkbox("show the other regime's locus (grey)", &s.other_regime);
    tip("Overlay the locus of the other regime's plant with the same compensator");
  }
  d.dirty |= ImGui::Checkbox("show the 0-degree locus (k < 0, light blue)", &s.zero_degree);
  tip("The complementary locus: negative gain / positive feedback");
  if (d.out.source == src && !d.out.plant_label.empty()) {
    const auto& g = d.out.plant.g;
    ImGui::PushStyleColor(ImGuiCol_Text, kDim);
    ImGui::PushTextWrapPos(0.0f);
    ImGui::Text("G(s) = (%s) / (%s)\n%s", control::to_string(g.num).c_str(), control::to_string(g.den).c_str(),
                d.out.plant_label.c_str());
    ImGui::PopTextWrapPos();
    ImGui::PopStyleColor();
  }
  return true;
}

void plant_section(DesignViewState& d) {
  DesignSettings& s = d.settings;
  if (plant_other_source(d)) return;
  ImGui::TextUnformatted("Plant: force -> position of the mass");
  int regime = s.regime == "presliding" ? 0 : 1;
  bool ch = ImGui::RadioButton("presliding", &regime, 0);
  tip("Friction elements stuck: they add their stiffness sum k_i and micro-damping");
  ImGui::SameLine();
  ch |= ImGui::RadioButton("gross sliding", &regime, 1);
  tip("Sliding at v0: friction acts through the local Stribeck slope plus sigma2 (damping)");
  if (ch) {
    s.regime = regime == 0 ? "presliding" : "sliding", d.dirty = true;
    // Another plant: its poles lie elsewhere (presliding: near +-460j for Fig. 4), so the view
    // fits the new locus again and a gain picked on the old one is gone.
    d.in.locus_view.reset();
    d.picked = false;
  }
  if (s.regime == "sliding") {
    double v0 = s.velocity > 0 ? s.velocity : d.out.plant.velocity;
    if (input_double("v0 [m/s]", &v0, 1e-5, 1.0, "%.3g", "Sliding operating velocity (default 10 Vs)", true))
      s.velocity = v0, d.dirty = true;
  }
  d.dirty |= ImGui::Checkbox("show the other regime's locus (grey)", &s.other_regime);
  tip("Overlay the locus of the other regime's plant with the same compensator");
  d.dirty |= ImGui::Checkbox("show the 0-degree locus (k < 0, light blue)", &s.zero_degree);
  tip("The complementary locus: negative gain / positive feedback");
  const auto& p = d.out.plant;
  ImGui::TextColored(kDim, "G(s) = 1 / (%.4g s^2 + %.4g s + %.4g)  [m/N]", p.mass, p.damping, p.stiffness);
  tip("m [kg], c_eff [N s/m], k_eff [N/m]");
}

void root_section(DesignViewState& d) {
  ImGui::Separator();
  ImGui::TextUnformatted("Desired dominant roots s_d (drag the diamond)");
  DesignSettings& s = d.settings;
  d.dirty |= input_double("zeta [-]", &s.zeta, 0.02, 0.98, "%.3f", "Damping ratio of s_d, in (0, 1)");
  d.dirty |= input_double("wn [rad/s]", &s.wn, 0.01, 1e5, "%.4g", "Natural frequency of s_d", true);
  d.dirty |= ImGui::Checkbox("target error constant K", &s.use_K);
  tip("On: design for this K (relocate s_d when out of reach). Off: the usable maximum (p/z bound)");
  if (s.use_K) d.dirty |= input_double("K", &s.K, 1e-3, 1e7, "%.4g", "Desired Kp / Kv / Ka (by plant type)", true);
  d.dirty |= input_double("max p/z [-]", &s.max_ratio, 1.5, 100.0, "%.3g",
                          "Bound on the lead ratio p/z for the usable maximum K", true);
}

void result_section(DesignViewState& d) {
  ImGui::Separator();
  const auto& o = d.out;
  if (!o.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErr);
    TextWrappedAtSpaces(o.error);
    ImGui::PopStyleColor();
  }
  if (!o.report) return;
  const auto& r = *o.report;
  const auto& L = r.limits;
  const std::string kname = control::error_constant_name(r.type.n);
  ImGui::TextColored(L.applicable ? kOk : kErr, "single lead %s", L.applicable ? "applicable" : "NOT applicable");
  tip("A single lead places s_d iff 0 < phi < 180 deg - beta");
  if (!L.applicable) TextWrappedAtSpaces(L.reason);
  ImGui::Text("phi = %.2f deg (limit %.2f deg)", L.phi * 180 / std::numbers::pi, 180 - L.beta * 180 / std::numbers::pi);
  // Units: the plant is force -> position [m/N], the compensator [N/m]; the loop is dimensionless,
  // so the type-n error constant is in s^-n and K0 = lim s^n G(s) in m/(N s^n).
  const char* kunit = r.type.n == 0 ? "-" : r.type.n == 1 ? "1/s" : r.type.n == 2 ? "1/s^2" : "s^-n";
  const std::string gunit = control::loop_units(o.source, o.port).plant;  // m/N; m/m for a pull drive
  const std::string k0unit = gunit == "m/N" ? (r.type.n == 0 ? "m/N" : r.type.n == 1 ? "m/(N s)" : r.type.n == 2 ? "m/(N s^2)" : "m/(N s^n)")
                             : r.type.n == 0 ? gunit : "(" + gunit + ")/s" + (r.type.n == 1 ? "" : "^" + std::to_string(r.type.n));
  ImGui::Text("type %d, K0 = %.4g %s", r.type.n, r.type.K0, k0unit.c_str());
  tip("K0 = lim s^n G(s): the plant's own gain at the type's order");
  if (L.applicable) {
    ImGui::Text("%s_max = %.5g %s (PD limit)", kname.c_str(), L.K_max, kunit);
    tip("Supremum of the error constant at s_d: reached only as p -> infinity");
    if (std::isfinite(r.K_max_usable)) {
      ImGui::Text("usable %s (p/z <= %.3g) = %.5g %s", kname.c_str(), d.settings.max_ratio, r.K_max_usable, kunit);
    } else {
      ImGui::TextColored(kErr, "no lead with p/z <= %.3g reaches s_d", d.settings.max_ratio);
      tip("Every lead that places the closed-loop poles at s_d needs a larger pole/zero ratio: raise max p/z, "
          "or choose a slower s_d (lower wn) or more damping");
    }
  }
  if (o.compensator) {
    const auto& c = *o.compensator;
    const std::string gunit = control::loop_units(o.source, o.port).gain;
    if (!c.second && c.p > 0.0) {
      ImGui::Text("Gc = %.5g (s + %.4g) / (s + %.4g) [%s]", c.Kc, c.z, c.p, gunit.c_str());
      ImGui::TextColored(kDim, "%s, %s = %.5g %s, p/z = %.3g", o.compensator_kind.c_str(), kname.c_str(),
                         c.Kc * c.z / c.p * r.type.K0, kunit, c.p / c.z);
    } else {
      ImGui::TextWrapped("Gc = %s [%s]", c.text().c_str(), gunit.c_str());
      ImGui::TextColored(kDim, "%s, %s = %.5g %s", o.compensator_kind.c_str(), kname.c_str(),
                         c.static_gain() * r.type.K0, kunit);
    }
  }
  if (o.step.t.size() > 4) {
    // The linear step against the requirements (the zero and the extra poles move it off the
    // second-order values of zeta and wn).
    control::LoopTrace st;
    st.t = o.step.t;
    st.x = o.step.y;
    st.r.assign(o.step.t.size(), o.step.y.back());
    const control::LoopMetrics m = control::loop_metrics(st);
    const bool os_ok = m.overshoot <= d.settings.max_overshoot;
    const bool ts_ok = std::isfinite(m.settling_time) && m.settling_time <= d.settings.settling_time;
    ImGui::TextColored(os_ok ? kOk : kErr, "linear step: overshoot %.3g %%", m.overshoot);
    tip("Overshoot of the linear closed-loop step (requirement in Requirements below)");
    ImGui::SameLine();
    if (std::isfinite(m.settling_time))
      ImGui::TextColored(ts_ok ? kOk : kErr, "settling %.3g s", m.settling_time);
    else
      ImGui::TextColored(kErr, "does not settle within %.3g s", o.horizon);
  }
  if (o.compensator)
    for (const auto& n : o.dominance.notes) {
      ImGui::PushStyleColor(ImGuiCol_Text, kErr);
      TextWrappedAtSpaces("! " + n);
      ImGui::PopStyleColor();
    }
  for (const auto& rel : r.relocations) {
    ImGui::PushID(rel.path.c_str());
    if (rel.found) {
      ImGui::Text("%s: zeta %.3f, wn %.4g", rel.path.c_str(), rel.root.zeta, rel.root.wn);
      ImGui::SameLine();
      if (ImGui::SmallButton("use"))
        d.settings.zeta = rel.root.zeta, d.settings.wn = rel.root.wn, d.dirty = true;
      tip("Move s_d to this point of the path (K_max = K (1 + margin) there)");
    } else {
      ImGui::PushTextWrapPos(0.0f);
      ImGui::TextColored(kDim, "%s: %s", rel.path.c_str(), rel.reason.c_str());
      ImGui::PopTextWrapPos();
    }
    ImGui::PopID();
  }
  if (!o.closed_loop_poles.empty())
    ImGui::TextColored(kDim, "closed-loop poles:\n%s", poles_text(o.closed_loop_poles).c_str());
}

void compensator_section(DesignViewState& d) {
  ImGui::Separator();
  // The type: the compensator built from the design (a drag or an edit then makes it manual).
  int type = static_cast<int>(d.settings.compensator);  // the combo's items in CompensatorType order
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  if (ImGui::Combo("compensator", &type, "lead\0lag\0lead-lag\0PI\0PID\0")) {
    d.settings.compensator = static_cast<control::CompensatorType>(type);
    d.in.manual.reset();
    d.dirty = true;
  }
  tip("lead: Kc (s+z)/(s+p) for the error constant reachable at s_d\n"
      "lag: Kc (s+z)/(s+p), z > p: Kc puts a pole on the zeta line of the plant's own locus, the lag buys K\n"
      "lead-lag: the usable-maximum lead, then a lag buying K (or 10x without a target K)\n"
      "PI: Kc (s+z)/s at the lag's gain point\n"
      "PID: Kc (s+z)(s+zi)/((s+p) s): the lead (p: derivative filter) and an integral section");
  if (!d.out.compensator) return;
  control::LeadCompensator c = *d.out.compensator;
  ImGui::TextUnformatted(d.in.manual ? "Compensator: manual (dragged)" : "Compensator: from the design");
  const control::LoopUnits units = control::loop_units(d.out.source, d.out.port);
  const std::string kc_label = "Kc [" + units.gain + "]###Kc";
  const std::string kc_tip = "Compensator gain (the locus gain), controller output u [" + units.input + "] per measured " +
                             "output y [" + units.output + "]" +
                             (units.input == "m" ? ": with a pull drive u is the pull point's position, a displacement" : "");
  bool ch = input_double(kc_label.c_str(), &c.Kc, 1e-3, 1e8, "%.5g", kc_tip.c_str(), true);
  ch |= input_double("z [rad/s]", &c.z, 1e-4, 1e5, "%.4g", "Compensator zero at -z (drag the green o)", true);
  ch |= input_double("p [rad/s]", &c.p, 1e-4, 1e6, "%.4g", "Compensator pole at -p (drag the green x)", true);
  if (c.second) {
    ch |= input_double("z2 [rad/s]", &c.second->z, 1e-4, 1e5, "%.4g", "Second section's zero at -z2 (drag its green o)", true);
    ch |= input_double("p2 [rad/s]", &c.second->p, 0.0, 1e6, "%.4g",
                       "Second section's pole at -p2 (drag its green x); 0: integrator", false);
  }
  if (ch) d.in.manual = c, d.dirty = true;
  if (d.out.lag) {
    const control::LagCost& lc = *d.out.lag;
    const std::string kn = d.out.report ? control::error_constant_name(d.out.report->type.n) : "K";
    ImGui::TextColored(kDim, "lag: %s = %.4g (x%.3g over %s: %.4g)\ncost: slow closed-loop pole %.4g%s, tau = %.3g s",
                       kn.c_str(), lc.K, lc.factor, c.second ? "the lead alone" : "Kc alone", lc.K_gain_only,
                       lc.slow_pole.real(), lc.slow_pole.imag() != 0.0 ? " (complex)" : "", lc.time_constant);
    tip("The lag's zero and pole (z > p) buy the error constant factor z/p; the closed-loop pole left near -z "
        "settles with time constant tau");
  }
  if (ImGui::SmallButton("copy MATLAB")) ImGui::SetClipboardText(control::compensator_matlab(c).c_str());
  tip("C = tf(num, den) with num = Kc prod (s + z_i), den = prod (s + p_i); to the clipboard");
  ImGui::SameLine();
  if (ImGui::SmallButton("copy python-control")) ImGui::SetClipboardText(control::compensator_python(c).c_str());
  tip("control.tf(num, den), the same coefficients, to the clipboard");
  if (d.in.manual) {
    if (ImGui::Button("back to the design")) d.in.manual.reset(), d.dirty = true;
    tip("Drop the manual compensator and use the computed one again");
  }
  if (d.picked) {
    const double wn = std::abs(d.picked_s);
    ImGui::TextColored(kDim, "picked: k = %.5g %s, zeta = %.3f, wn = %.4g rad/s\nall closed-loop poles [rad/s]:\n%s", d.picked_k,
                       units.gain.c_str(),
                       wn > 0 ? -d.picked_s.real() / wn : 0.0, wn, poles_text(d.picked_poles).c_str());
    if (ImGui::SmallButton("set Kc = k")) c.Kc = d.picked_k, d.in.manual = c, d.dirty = true;
  }
}

void simulation_section(DesignViewState& d) {
  ImGui::Separator();
  DesignSettings& s = d.settings;
  ImGui::TextUnformatted("Requirements (shaded where they fail)");
  input_double("max overshoot [%]", &s.max_overshoot, 0.1, 90.0, "%.3g", "-> minimum damping ratio");
  input_double("settling time [s]", &s.settling_time, 1e-3, 100.0, "%.3g", "2 % band: Re s < -4 / Ts", true);
  ImGui::Separator();
  ImGui::TextUnformatted("Loop with the scenario's friction");
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  int reference = static_cast<int>(s.reference);  // the combo's items in DesignReference order
  if (ImGui::Combo("reference", &reference, "step\0ramp\0sine\0")) {
    s.reference = static_cast<DesignReference>(reference);
    d.dirty = true;
  }
  if (s.reference != DesignReference::Ramp) d.dirty |= input_double("amplitude [m]", &s.amplitude, 1e-6, 1.0, "%.3g", "Step height / sine amplitude", true);
  if (s.reference == DesignReference::Ramp) d.dirty |= input_double("slope [m/s]", &s.slope, 1e-6, 1.0, "%.3g", "Ramp velocity", true);
  if (s.reference == DesignReference::Sine) d.dirty |= input_double("frequency [Hz]", &s.frequency, 0.01, 100.0, "%.3g", "Sine frequency", true);
  int comp = s.compensation == "coulomb" ? 0 : 1;
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  if (ImGui::Combo("compensation", &comp, "Coulomb feedforward\0GMS feedforward\0"))
    s.compensation = comp == 0 ? "coulomb" : "gms", d.dirty = true;
  tip("Coulomb: Fc sgn(v). GMS: a GMS model inside the controller, with its own state, driven by v (the "
      "velocity chosen below)");
  int source = s.feedforward_source == control::FeedforwardSource::Measured ? 1 : 0;
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9.0f);
  if (ImGui::Combo("driven by", &source, "reference velocity\0measured velocity\0")) {
    s.feedforward_source = source == 1 ? control::FeedforwardSource::Measured : control::FeedforwardSource::Reference;
    d.dirty = true;
  }
  tip("What drives the compensation's feedforward. Reference: v_ref = dx_ref/dt; it cannot chatter but is 0 "
      "at a constant set point, so there it does nothing (the DF prediction is the uncompensated one). "
      "Measured: the plant's velocity v; the loop then sees F(v) - F_hat(v), and the DF row of the "
      "compensated loop is predicted with that compensated nonlinearity");
  d.dirty |= input_double("model force x [-]", &s.mismatch_force, 0.2, 2.0, "%.2f", "Compensator's Fs, Fc / plant's");
  d.dirty |= input_double("model stiffness x [-]", &s.mismatch_stiffness, 0.1, 10.0, "%.2f", "Compensator's k_i / plant's", true);
  d.dirty |= input_double("sample time [s]", &s.sample_time, 0.0, 0.01, "%.2g", "0: continuous; else Tustin at T with hold");
  ImGui::TextColored(kDim, "recomputed in %.1f ms (locus, design, step, 2 loops)", d.compute_ms);
}
}  // namespace

void draw_design_panel(DesignViewState& d, const Scenario& scenario, int generation, const AssemblyScenario* assembly) {
  sync(d, scenario, generation);
  sync_assembly(d, assembly);
  recompute(d);
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const float left = std::min(ImGui::GetFontSize() * 24.0f, 0.34f * avail.x);
  ImGui::BeginChild("##design_controls", ImVec2(left, avail.y), true);
  plant_source_section(d, assembly);
  plant_section(d);
  root_section(d);
  result_section(d);
  compensator_section(d);
  simulation_section(d);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("##design_plots", ImVec2(0, avail.y), false);
  const ImVec2 r = ImGui::GetContentRegionAvail();
  const float top = 0.52f * r.y;
  const float locus_w = std::floor(0.42f * r.x);
  draw_design_locus(d, ImVec2(locus_w, top));
  ImGui::SameLine();
  draw_design_frequency(d, ImVec2(r.x - locus_w - ImGui::GetStyle().ItemSpacing.x, top));
  draw_design_responses(d, ImVec2(r.x, r.y - top - ImGui::GetStyle().ItemSpacing.y));
  ImGui::EndChild();
  recompute(d);  // drags this frame show next frame; recompute now so the state is never stale
}

}  // namespace gmslab::ui

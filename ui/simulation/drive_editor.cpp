#include "ui/simulation/drive_editor.hpp"

#include <imgui.h>

#include <string>

#include "ui/param_editor.hpp"

namespace gmslab::ui {

namespace {
// A labelled row: "label [unit]" on the left, the field on the right.
bool row(FieldMarks* m, const char* label, const ParamSpec& spec, double& v, double ref = 0.0) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::AlignTextToFramePadding();
  ImGui::Text("%s [%.*s]", label, static_cast<int>(spec.unit.size()), spec.unit.data());
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("%.*s\nallowed: %s", static_cast<int>(spec.help.size()), spec.help.data(),
                      spec.range_text().c_str());
  ImGui::TableNextColumn();
  ImGui::SetNextItemWidth(-1);
  ImGui::PushID(label);
  const bool c = edit_param("##v", spec, v, ref, m);
  ImGui::PopID();
  return c;
}

bool begin_rows(const char* id) {
  if (!ImGui::BeginTable(id, 2, ImGuiTableFlags_SizingStretchProp)) return false;
  ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthFixed, ImGui::GetFontSize() * 10.5f);
  ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch);
  return true;
}

// Unit strings that outlive the ParamSpecs made from them.
const char* rate_unit(Drive::Kind k) {
  switch (k) {
    case Drive::Kind::Velocity: return "m/s^2";
    case Drive::Kind::Force: return "N/s";
    default: return "m/s";
  }
}

// Default signal of a kind, scaled to the driven quantity.
Signal default_signal(Signal::Kind kind, Drive::Kind d) {
  const double a = d == Drive::Kind::Force ? 1.0 : d == Drive::Kind::Velocity ? 0.01 : 1e-5;
  switch (kind) {
    case Signal::Kind::Constant: return Signal::constant(a);
    case Signal::Kind::Ramp: return Signal::ramp(0.0, d == Drive::Kind::Pull ? 0.1 : a);
    case Signal::Kind::Sine: return Signal::sine(0.0, a, 1.0);
    case Signal::Kind::Triangle: return Signal::triangle(-a, a, 4.0 * a, 2);
    case Signal::Kind::TurningPoints: return Signal::turning_points(0.0, a, {a, -a, 0.5 * a});
    default: return Signal::constant(0.0);
  }
}

bool edit_signal_fields(Signal& s, Drive::Kind dk, FieldMarks* m) {
  const std::string_view u = drive_unit(dk), ru = rate_unit(dk);
  const ParamSpec val{"value", "y", u, "signal value", -1e9, 1e9};
  const ParamSpec slope{"slope", "dy/dt", ru, "rate of change", -1e9, 1e9};
  const ParamSpec rate{"rate", "|dy/dt|", ru, "speed between turning points", 0, 1e9, true};
  const ParamSpec freq{"frequency", "f", "Hz", "frequency of the sine", 0, 1e6};
  const ParamSpec phase{"phase", "phi", "rad", "phase of the sine at t = 0", -1e3, 1e3};
  bool c = false;
  switch (s.kind) {
    case Signal::Kind::Constant: c |= row(m, "value", val, s.value); break;
    case Signal::Kind::Ramp:
      c |= row(m, "value at t = 0", val, s.value);
      c |= row(m, "slope", slope, s.slope);
      break;
    case Signal::Kind::Sine:
      c |= row(m, "offset", val, s.offset);
      c |= row(m, "amplitude", val, s.amplitude);
      c |= row(m, "frequency", freq, s.frequency);
      c |= row(m, "phase", phase, s.phase);
      break;
    case Signal::Kind::Triangle: {
      c |= row(m, "low", val, s.low);
      c |= row(m, "high", val, s.high);
      c |= row(m, "rate", rate, s.rate);
      double cyc = s.cycles;
      const ParamSpec cs{"cycles", "n", "-", "number of low-high-low cycles", 1, 1e6};
      if (row(m, "cycles", cs, cyc)) s.cycles = static_cast<int>(cyc), c = true;
      break;
    }
    case Signal::Kind::TurningPoints:
      c |= row(m, "start", val, s.start);
      c |= row(m, "rate", rate, s.rate);
      for (std::size_t i = 0; i < s.points.size(); ++i) {
        ImGui::PushID(static_cast<int>(i));
        const std::string name = "point " + std::to_string(i + 1);
        c |= row(m, name.c_str(), val, s.points[i]);
        ImGui::PopID();
      }
      break;
    default: break;
  }
  if (c) s.compile();
  return c;
}
}  // namespace

const char* drive_unit(Drive::Kind k) {
  switch (k) {
    case Drive::Kind::Velocity: return "m/s";
    case Drive::Kind::Force: return "N";
    default: return "m";
  }
}

bool edit_plant(Plant& p, FieldMarks* m) {
  static const ParamSpec mass{"mass", "m", "kg", "moving mass", 0, 1e6, true, true};
  static const ParamSpec spring{"spring", "k", "N/m", "spring from the mass to ground", 0, 1e12};
  static const ParamSpec damper{"damper", "c", "N s/m", "damper from the mass to ground", 0, 1e9};
  bool c = false;
  if (!begin_rows("##plant")) return false;
  c |= row(m, "mass m", mass, p.mass, 1.0);
  c |= row(m, "spring k", spring, p.spring);
  c |= row(m, "damper c", damper, p.damper);
  ImGui::EndTable();
  return c;
}

bool edit_drive(Drive& d, FieldMarks* m) {
  bool c = false;
  static const char* kinds[] = {"displacement x(t): friction alone (hysteresis)",
                                "velocity v(t) prescribed", "force F(t) on the mass",
                                "pull: point x_p(t) pulls through a spring"};
  int k = static_cast<int>(d.kind);
  ImGui::SetNextItemWidth(-1);
  if (ImGui::Combo("##drivekind", &k, kinds, 4)) {
    d.kind = static_cast<Drive::Kind>(k);
    d.signal = default_signal(d.signal.kind, d.kind);
    if (d.kind == Drive::Kind::Pull && d.pull_spring <= 0.0) d.pull_spring = 2.0;
    c = true;
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("What drives the body. Changing it restarts the run.");
  static const char* skinds[] = {"constant", "ramp", "sine", "piecewise linear (edit in JSON)",
                                 "turning points", "triangle", "sequence (edit in JSON)"};
  int sk = static_cast<int>(d.signal.kind);
  ImGui::SetNextItemWidth(-1);
  if (ImGui::Combo("##signalkind", &sk, skinds, 7) && sk != static_cast<int>(d.signal.kind)) {
    const auto nk = static_cast<Signal::Kind>(sk);
    if (nk != Signal::Kind::PiecewiseLinear && nk != Signal::Kind::Sequence) {
      d.signal = default_signal(nk, d.kind);
      c = true;
    }
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Shape of the drive signal, in %s. Piecewise-linear and sequence signals are "
                      "edited in the scenario JSON.", drive_unit(d.kind));
  if (begin_rows("##signal")) {
    c |= edit_signal_fields(d.signal, d.kind, m);
    if (d.kind == Drive::Kind::Pull) {
      static const ParamSpec ks{"spring", "k_p", "N/m", "pulling spring", 0, 1e12};
      static const ParamSpec cs{"damper", "c_p", "N s/m", "pulling damper", 0, 1e9};
      c |= row(m, "pull spring k_p", ks, d.pull_spring);
      c |= row(m, "pull damper c_p", cs, d.pull_damper);
    }
    ImGui::EndTable();
  }
  return c;
}

bool edit_run(RunSettings& r, FieldMarks* m) {
  static const ParamSpec dt{"dt", "h", "s", "integration step; smaller resolves stiffer elements", 0, 1,
                            true, true};
  static const ParamSpec dur{"duration", "T", "s", "simulated time of the run", 0, 1e6, true, true};
  static const ParamSpec rec{"record_every", "n", "-", "keep every n-th step in the trace", 1, 1e6};
  bool c = false;
  if (!begin_rows("##run")) return false;
  c |= row(m, "step dt", dt, r.dt, 1e-5);
  c |= row(m, "duration", dur, r.duration, 10.0);
  double n = r.record_every;
  if (row(m, "record every", rec, n)) r.record_every = static_cast<int>(n), c = true;
  ImGui::EndTable();
  return c;
}

}  // namespace gmslab::ui

#include "core/control/design_plant.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "core/control/assembly_plant.hpp"
#include "core/error.hpp"

namespace gmslab::control {

const char* to_string(PlantSource s) {
  switch (s) {
    case PlantSource::Scenario: return "scenario";
    case PlantSource::Assembly: return "assembly";
    case PlantSource::Typed: return "typed";
  }
  return "scenario";
}

std::optional<PlantSource> plant_source_from_string(std::string_view s) {
  for (auto p : {PlantSource::Scenario, PlantSource::Assembly, PlantSource::Typed})
    if (s == to_string(p)) return p;
  return std::nullopt;
}

namespace {
// The coefficients of `text` (highest power first), or why not (`why` set, result empty).
std::vector<double> coefficients(const std::string& text, bool denominator, std::string& why) {
  const std::vector<double> v = parse_coefficients(text, why);
  if (!why.empty()) return {};
  if (denominator && v.front() == 0.0) {
    why = "the leading coefficient (of s^" + std::to_string(v.size() - 1) + ") must be non-zero";
    return {};
  }
  return v;
}
}  // namespace

std::string coefficients_problem(const std::string& text, bool denominator) {
  std::string why;
  coefficients(text, denominator, why);
  return why;
}

TransferFunction typed_plant(const std::string& num, const std::string& den, const std::string& num_field,
                             const std::string& den_field) {
  std::string why;
  const auto n = coefficients(num, false, why);
  if (!why.empty()) throw InputError(num_field + " '" + num + "': " + why);
  const auto d = coefficients(den, true, why);
  if (!why.empty()) throw InputError(den_field + " '" + den + "': " + why);
  TransferFunction g{Poly::descending(n), Poly::descending(d)};
  if (g.num.degree() > g.den.degree())
    throw InputError(num_field + " '" + num + "': degree " + std::to_string(g.num.degree()) +
                     " is above the denominator's " + std::to_string(g.den.degree()) +
                     " (the plant must be proper: deg num <= deg den)");
  return g;
}

AssemblyPort assembly_port(const Assembly& a, const std::string& drive, const std::string& output) {
  AssemblyPort p;
  std::string names;
  bool found = false;
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const DrivePart& d = a.drives[i];
    const bool input = d.kind == DrivePart::Kind::Force || d.kind == DrivePart::Kind::Pull;
    if (input) names += (names.empty() ? "" : ", ") + d.name;
    if (!found && ((drive.empty() && input) || d.name == drive)) p.drive = i, found = true;
  }
  if (!found)
    throw InputError("drive '" + drive + "': " +
                     (names.empty() ? std::string("the plant has no force or pull drive to design from")
                                    : "not a drive of the plant (force / pull drives: " + names + ")"));
  const DrivePart& d = a.drives[p.drive];
  if (d.kind != DrivePart::Kind::Force && d.kind != DrivePart::Kind::Pull)
    throw InputError("drive '" + d.name + "': a " + std::string(to_string(d.kind)) +
                     " drive prescribes motion; the design's input is a force or pull drive (" + names + ")");
  p.drive_name = d.name;
  p.pull = d.kind == DrivePart::Kind::Pull;
  std::string body = output.empty() ? a.bodies[static_cast<std::size_t>(d.body)].name : output;
  if (body.rfind("x.", 0) == 0) body = body.substr(2);
  else if (body.rfind("v.", 0) == 0) body = body.substr(2), p.velocity = true;
  p.body = -1;
  std::string bodies;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    bodies += (bodies.empty() ? "" : ", ") + a.bodies[i].name;
    if (a.bodies[i].name == body) p.body = static_cast<int>(i);
  }
  if (p.body < 0)
    throw InputError("output '" + output + "': expected x.BODY or v.BODY with a body of the plant (" + bodies + ")");
  p.output = (p.velocity ? "v." : "x.") + body;
  return p;
}

std::vector<std::string> assembly_outputs(const Assembly& a) {
  std::vector<std::string> out;
  for (const auto& b : a.bodies) out.push_back("x." + b.name), out.push_back("v." + b.name);
  return out;
}

LoopUnits loop_units(PlantSource source, const AssemblyPort& port) {
  LoopUnits u;
  if (source != PlantSource::Assembly) return u;
  u.input = port.pull ? "m" : "N";
  u.output = port.velocity ? "m/s" : "m";
  if (port.pull)
    u.gain = port.velocity ? "m/(m/s)" : "m/m", u.plant = port.velocity ? "(m/s)/m" : "m/m";
  else
    u.gain = port.velocity ? "N s/m" : "N/m", u.plant = port.velocity ? "(m/s)/N" : "m/N";
  return u;
}

DesignPlant design_plant(const PlantChoice& c, Regime r, double v0, const Scenario* scenario,
                         const Assembly* assembly) {
  DesignPlant out;
  out.source = c.source;
  out.linear.regime = r;
  switch (c.source) {
    case PlantSource::Scenario:
      if (!scenario) throw InputError("plant source 'scenario': no scenario to take the plant from");
      out.linear = linear_plant(*scenario, r, v0);
      out.label = "force -> position of the mass";
      break;
    case PlantSource::Assembly: {
      if (!assembly)
        throw InputError("plant source 'assembly': no assembled plant is loaded (open a schema-2 preset, "
                         "e.g. presets/two_mass_drive.json, in the Plant tab or give it as --preset)");
      out.port = assembly_port(*assembly, c.drive, c.output);
      out.linear.g = assembly_transfer_function(*assembly, out.port.drive, out.port.output, r, v0);
      // v = s x: a velocity output of a plant with a free rigid-body mode (a pole at s = 0) has the
      // factor s above and below; it cancels (the design refuses a zero at s = 0). A pull drive's
      // spring holds the chain, so its v output keeps the zero and the design says why.
      while (out.linear.g.num.degree() > 0 && out.linear.g.num.coeff(0) == 0.0 && out.linear.g.den.coeff(0) == 0.0) {
        auto shift = [](const Poly& p) {
          std::vector<double> c;
          for (int i = 1; i <= p.degree(); ++i) c.push_back(p.coeff(i));
          return Poly(c);
        };
        out.linear.g = {shift(out.linear.g.num), shift(out.linear.g.den)};
      }
      out.linear.velocity = r == Regime::Sliding ? v0 : 0.0;
      const DrivePart& d = assembly->drives[out.port.drive];
      out.label = d.name + (d.kind == DrivePart::Kind::Pull ? " (pull: x_p [m])" : " (force [N])") + " -> " +
                  out.port.output + (out.port.velocity ? " [m/s]" : " [m]");
      break;
    }
    case PlantSource::Typed:
      out.linear.g = typed_plant(c.num, c.den, "plant num", "plant den");
      out.linear.velocity = 0.0;
      out.label = "typed num/den (linear, no friction)";
      break;
  }
  return out;
}

}  // namespace gmslab::control

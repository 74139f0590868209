// gmslab core/control: where the design's plant G(s) comes from - one function, design_plant(), for
// the Design tab, the headless renderer and `gmslab design`.
//
//   scenario  the one-body scenario's force -> position of the mass (scenario_plant.hpp),
//             friction elements stuck (presliding) or sliding at v0
//   assembly  an assembled plant (core/sim/assembly.hpp) from a chosen force / pull drive to a chosen
//             output x.BODY [m] or v.BODY [m/s] (assembly_plant.hpp), every contact stuck or sliding at v0
//   typed     G(s) = num(s) / den(s) from typed coefficients, highest power of s first (no friction:
//             nothing to simulate a friction loop with)
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/control/scenario_plant.hpp"
#include "core/control/transfer_function.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab::control {

// Saved as "scenario" | "assembly" | "typed".
enum class PlantSource { Scenario, Assembly, Typed };
const char* to_string(PlantSource s);
std::optional<PlantSource> plant_source_from_string(std::string_view s);  // nullopt for other text

// The user's choice of plant (DesignSettings::plant; the session's "design.plant").
struct PlantChoice {
  PlantSource source = PlantSource::Scenario;
  // typed: coefficients, highest power of s first, spaces or commas between them. Always a valid
  // pair (the value in force; the Design tab keeps a rejected edit in its own text buffer).
  std::string num = "1";
  std::string den = "1 2 0";
  // assembly: the drive's name ("" = the first force or pull drive) and the output "x.BODY" |
  // "v.BODY" ("" = the position of the drive's body: the collocated plant).
  std::string drive;
  std::string output;
  bool operator==(const PlantChoice&) const = default;
};

// Why one typed coefficient list is rejected ("" when it is valid): empty, a token that is not a
// finite number, all zero, degree above 40, or (denominator) a zero leading coefficient.
std::string coefficients_problem(const std::string& text, bool denominator);
// The typed plant. Throws InputError naming the field (`num_field` / `den_field`) with the reason:
// each list as above, and deg num <= deg den (proper).
TransferFunction typed_plant(const std::string& num, const std::string& den,
                             const std::string& num_field = "num", const std::string& den_field = "den");

// An assembled plant's drive by name ("" = the first force or pull drive) and output ("" = x of the
// drive's body; "BODY" means x.BODY). Throws InputError listing the names there are.
struct AssemblyPort {
  std::size_t drive = 0;
  std::string drive_name;
  int body = 0;           // output body index
  bool velocity = false;  // output v.BODY (else x.BODY)
  bool pull = false;      // the drive is a pull drive: u is its point's position x_p [m] (else a force [N])
  std::string output;     // "x.BODY" | "v.BODY"
};
AssemblyPort assembly_port(const Assembly& a, const std::string& drive, const std::string& output);
// The outputs a design can measure, as assembly_port() accepts them: x.BODY then v.BODY, per body.
std::vector<std::string> assembly_outputs(const Assembly& a);

// Units of the designed loop, for every label of the Design view: the controller output u (a force
// [N]; a pull drive's point position [m]), the measured output y (a position [m]; v.BODY [m/s]),
// the compensator gain Kc = u / y (N/m; m/m for a pull drive and a position; N s/m; m/(m/s)) and
// the plant G = y / u. The scenario and a typed G(s) are force -> position (N/m).
struct LoopUnits {
  std::string input = "N", output = "m", gain = "N/m", plant = "m/N";
};
LoopUnits loop_units(PlantSource source, const AssemblyPort& port);

struct DesignPlant {
  PlantSource source = PlantSource::Scenario;
  LinearPlant linear;  // g for every source; mass, stiffness, damping, velocity: scenario only
  AssemblyPort port;   // assembly only
  std::string label;   // what G(s) is, for the view and the CLI's JSON
};

// The design's plant for `choice` in regime r (v0 = 0: the default sliding velocity). `scenario` /
// `assembly` may be null when the choice does not use them; throws InputError when the chosen
// source has none ("no assembled plant: ...") or its inputs are invalid.
DesignPlant design_plant(const PlantChoice& choice, Regime r, double v0, const Scenario* scenario,
                         const Assembly* assembly);

}  // namespace gmslab::control

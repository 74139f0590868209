// libFuzzer target: scenario presets from arbitrary bytes.
//
// parse_json + scenario_from_json must either accept the bytes or throw InputError (never crash,
// hang or throw anything else). An accepted scenario must (1) survive a save/load round trip
// unchanged and (2) simulate a few hundred steps with finite results or stop with InputError
// (step too large) / SimulationError (divergence) - never produce NaN silently.
#include <cmath>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/assembly.hpp"

namespace {
constexpr std::size_t kSteps = 300;

bool finite_trace(const gmslab::Trace& tr) {
  for (std::size_t i = 0; i < tr.size(); ++i)
    if (!std::isfinite(tr.x[i]) || !std::isfinite(tr.v[i]) || !std::isfinite(tr.friction[i]) ||
        !std::isfinite(tr.applied[i]))
      return false;
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace gmslab;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scenario sc;
  try {
    sc = scenario_from_json(parse_json(text, "fuzz.json"), "fuzz.json");
  } catch (const InputError&) {
    return 0;  // rejected with a message: the expected outcome for most inputs
  }
  // Round trip: what we save, we load back identically.
  const std::string saved = to_json(sc).dump(2);
  if (!(scenario_from_json(parse_json(saved, "saved.json"), "saved.json") == sc))
    __builtin_trap();
  try {
    AssemblySimulation sim = one_body_simulation(sc);
    sim.advance(kSteps);
    if (!finite_trace(sim.one_body_trace())) __builtin_trap();
  } catch (const InputError&) {
  } catch (const SimulationError&) {
  }
  return 0;
}

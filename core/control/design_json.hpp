// gmslab core/control: JSON form of a lead design report and of loop metrics (the CLI's output).
// Non-finite numbers (K_max where no lead applies, NaN metrics) are written as null.
// Keys: applicable, reason, phi_deg, beta_deg, s_d [re, im], type, constant ("Kp"/"Kv"/"Ka"),
// K0, M, K_max, K_max_usable, max_ratio, pd_limit {Kd, z}, usable_design {z, p, Kc, K},
// and when a design exists: z, p, Kc, K, ratio (p/z), within_max_ratio, closed_loop_poles
// [[re, im], ...], dominant, notes; when K is out of reach: relocations [{path (= name), found, wn, zeta,
// z, p, Kc, K, K_max, closed_loop_poles | reason, peak_K, peak_wn, peak_zeta}].
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>

#include "core/control/lead_design.hpp"
#include "core/control/loop_simulation.hpp"

namespace gmslab::control {

nlohmann::json to_json(const LeadReport& r);
nlohmann::json to_json(const LoopMetrics& m);
nlohmann::json poles_json(const std::vector<cplx>& poles);

// The design `gmslab design` reports (and Python's gmslab.design): lead_design() for plant g, its
// JSON (to_json) with "max_ratio" and the chosen design: the requested one, the best relocation,
// or the usable maximum ("design_kind"; a design that is not the requested one is also written at
// the top level: z, p, Kc, K, closed_loop_poles). Throws InputError for a bad root or K.
struct DesignResult {
  LeadReport report;
  std::optional<std::pair<std::string, LeadDesign>> chosen;  // kind, design
  nlohmann::json json;
};
DesignResult design_report(const TransferFunction& g, const DominantRoot& root, std::optional<double> K,
                           const LeadOptions& options);

}  // namespace gmslab::control

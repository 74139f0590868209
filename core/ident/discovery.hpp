// gmslab identification: terms beyond the catalog. After the catalog's credit by ablation, when
// the validation residual stays above near_floor x the floor, a sparse regression of the final
// model's training residual on a library of candidate columns proposes the smallest set of terms
// that passes the catalog's credit test (ablation.hpp) on the validation record.
//
// The library (library.hpp) is computed from the record alone, and from the final model's force f
// where named; the direction-gated ripple's wavelength lambda is the strongest of the training
// residual's position spectrum for that direction (evidence.hpp: position_spectrum).
//
// Selection: forward stepwise (orthogonal matching pursuit) on the used training samples: at each
// step the column most correlated with the current residual (columns standardised), then least
// squares of the residual on the chosen set; up to max_terms steps. Every set on the path is
// scored on the validation record (its training coefficients applied there). The set with the
// lowest validation RMS is the best; the smallest set on the path that the block test cannot
// tell from the best (z < z_crit) is proposed. It is kept when it passes the credit test:
// block test of the validation MSE without against with the terms z >= z_crit (or a rise of at
// least floor^2), the terms' contribution on training >= min_size x the floor, and the model
// without them above near_floor x the floor on validation (the run condition). The loop then fits
// the kept terms jointly with the model (Effect::Discovered, effects.hpp) and credits every effect
// again with them in the model (loop_stages.hpp: join_discovered).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/ident/ablation.hpp"
#include "core/ident/fit.hpp"
#include "core/ident/library.hpp"

namespace gmslab::ident {

// The library for a training record (the ripple wavelengths from the residual r on train).
std::vector<LibraryColumn> discovery_library(const Dataset& train, const EffectContext& c,
                                             const std::vector<double>& r);

struct DiscoveryStep {                       // one set on the selection path
  std::vector<std::size_t> columns;          // library indices
  double rms_train = 0, rms_validation = 0;  // residual after the set's terms [N]
};

struct Discovery {
  bool ran = false;
  bool found = false;
  std::string summary;  // one line for a person (CLI, panel)
  std::size_t library_size = 0;
  std::vector<LibraryColumn> library;
  std::vector<DiscoveryStep> path;
  std::vector<DiscoveredTerm> terms;  // the proposed set (kept when found)
  // The kept terms are part of the final model (Effect::Discovered, fitted jointly with the shape
  // and the catalog effects and credited by ablation with them); their coefficients are those of
  // the joint fit. Else they are fitted on the final model's residual.
  bool joined = false;
  double rms_validation_before = 0, rms_validation_after = 0;  // [N]
  BlockTest test;           // validation MSE without against with the proposed terms
  double contribution = 0;  // RMS of the terms on training [N]
  double floor = 0;         // [N]
  double z_crit = 3;
};

struct DiscoveryOptions {
  std::size_t max_terms = 4;
  double z_crit = 3.0;
  double min_size = 0.5;
  double near_floor = 1.15;
  std::size_t blocks = 20;
};

// f_train, f_val: the final model's force along train and val; floor as the credit test uses.
Discovery discover(const Dataset& train, const Dataset& val, const EffectContext& c,
                   const std::vector<double>& f_train, const std::vector<double>& f_val,
                   double floor, const DiscoveryOptions& o = {});
// The kept terms' force along d (zeros when nothing was found).
std::vector<double> discovered_force(const Discovery& s, const Dataset& d, const EffectContext& c,
                                     const std::vector<double>& f);
// "+0.12 N * sgn(v) exp(-s / 1 mm)"
std::string discovered_formula(const Discovery& s);
nlohmann::json to_json(const Discovery& s);

}  // namespace gmslab::ident

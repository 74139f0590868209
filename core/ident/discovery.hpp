// gmslab identification: terms beyond the catalog. After the catalog's credit by ablation, when
// the validation residual stays above near_floor x the floor, a sparse regression of the final
// model's training residual on a library of candidate columns proposes the smallest set of terms
// that passes the catalog's credit test (ablation.hpp) on the validation record.
//
// The library (every column computed from the record alone, and from the final model's force f
// where named; sgn v is the direction of the last motion while |v| > v_rest, else 0):
//   basic        v / v_ref, a [m/s^2], (x - x_mid) / x_half, sgn v, v |v| / v_ref^2
//   reversal     sgn(v) exp(-s / L), s = travel since the last reversal of the direction of
//                motion, L on a factor-2 grid from 1 um to the stroke
//   rest         sgn(v) exp(-tau / T), tau = time since the last rest (|v| <= v_rest), T on a
//                factor-sqrt(10) grid from 0.01 s to 100 s
//   history |v|  sgn(v) LP_T(|v| / v_ref), LP_T a first-order low-pass (exact for
//   piecewise-constant
//                input), T on a factor-sqrt(10) grid from 0.1 s to 100 s
//   history |Fv| sgn(v) LP_T(|f v| / (f_level v_ref)), the same grid (f: the model's force)
//   force lag    df/dt [N/s] (local slope of the model's force): a lag of the force channel
//   dir. ripple  sin and cos(2 pi x / lambda) for v > 0 only, and for v < 0 only; lambda the
//                strongest wavelength of the training residual's position spectrum for that
//                direction (evidence.hpp: position_spectrum)
//
// Selection: forward stepwise (orthogonal matching pursuit) on the used training samples: at each
// step the column most correlated with the current residual (columns standardised), then least
// squares of the residual on the chosen set; up to max_terms steps. Every set on the path is
// scored on the validation record (its training coefficients applied there). The set with the
// lowest validation RMS is the best; the smallest set on the path that the block test cannot
// tell from the best (z < z_crit) is proposed. It is kept when it passes the credit test:
// block test of the validation MSE without against with the terms z >= z_crit (or a rise of at
// least floor^2), the terms' contribution on training >= min_size x the floor, and the model
// without them above near_floor x the floor on validation (the run condition).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/ident/ablation.hpp"
#include "core/ident/fit.hpp"

namespace gmslab::ident {

enum class LibraryFamily {
  Velocity,
  Acceleration,
  Position,
  Sign,
  VelocitySquared,
  Reversal,
  Rest,
  HistoryV,
  HistoryFv,
  ForceLag,
  DirRippleSin,
  DirRippleCos
};

// One candidate column. scale: L [m] (Reversal), T [s] (Rest, History*), wavelength [m]
// (DirRipple*); direction: +1 / -1 for the direction-gated ripple.
struct LibraryColumn {
  LibraryFamily family = LibraryFamily::Sign;
  double scale = 0;
  int direction = 0;
};
std::string family_name(LibraryFamily f);              // "reversal transient", ...
std::string column_formula(const LibraryColumn& c);    // "sgn(v) exp(-s / 1 mm)"
std::string coefficient_unit(const LibraryColumn& c);  // "N", "N s^2/m", "s"

// The library for a training record (the ripple wavelengths from the residual r on train).
std::vector<LibraryColumn> discovery_library(const Dataset& train, const EffectContext& c,
                                             const std::vector<double>& r);
// Column values on d (f: the model's force along d) [one value per sample].
std::vector<double> library_values(const LibraryColumn& col, const Dataset& d,
                                   const EffectContext& c, const std::vector<double>& f);

struct DiscoveredTerm {
  LibraryColumn column;
  double coefficient = 0;  // in coefficient_unit(column)
};

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
  std::vector<DiscoveredTerm> terms;                           // the proposed set (kept when found)
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

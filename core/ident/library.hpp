// gmslab identification: the library of candidate terms beyond the catalog (discovery.hpp), and
// the terms discovery keeps. The library's columns are computed from the record alone, and from a
// model force f where named; sgn v is the direction of the last motion while |v| > v_rest, else 0:
//   basic        v / v_ref, a [m/s^2], (x - x_mid) / x_half, sgn v, v |v| / v_ref^2
//   reversal     sgn(v) exp(-s / L), s = travel since the last reversal of the direction of
//                motion, L on a factor-2 grid from 1 um to the stroke
//   rest         sgn(v) exp(-tau / T), tau = time since the last rest (|v| <= v_rest), T on a
//                factor-sqrt(10) grid from 0.01 s to 100 s
//   history |v|  sgn(v) LP_T(|v| / v_ref), LP_T a first-order low-pass (exact for piecewise-
//                constant input), T on a factor-sqrt(10) grid from 0.1 s to 100 s
//   history |Fv| sgn(v) LP_T(|f v| / (f_level v_ref)), the same grid
//   force lag    df/dt [N/s] (local slope of f): a lag of the force channel
//   dir. ripple  sin and cos(2 pi x / lambda) for v > 0 only, and for v < 0 only
#pragma once

#include <string>
#include <vector>

#include "core/ident/dataset.hpp"

namespace gmslab::ident {

struct EffectContext;

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

// Whether the column is computed from a model force f (|F v| history, force lag).
bool needs_model_force(const LibraryColumn& c);
// Column values on d (f: the model's force along d; read only where needs_model_force) [one value
// per sample].
std::vector<double> library_values(const LibraryColumn& col, const Dataset& d,
                                   const EffectContext& c, const std::vector<double>& f);

struct DiscoveredTerm {
  LibraryColumn column;
  double coefficient = 0;  // in coefficient_unit(column)
};

}  // namespace gmslab::ident

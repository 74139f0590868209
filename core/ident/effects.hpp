// gmslab identification: the catalog of effects that real friction data shows and a base friction
// model lacks. Each effect adds linear terms (columns) to the force model
//
//   F_meas(t) = Fc g(t) + sigma2 v(t) + sum_effects sum_j theta_j c_j(t) + noise
//
// where g is the base model's friction force simulated along the measured motion with unit force
// level (Fc = 1 N, sigma2 = 0) and the theta are solved by least squares inside the nonlinear fit
// (variable projection). The columns, with the unit of their coefficient:
//   inertia              a                                               M [kg]
//   offset               1                                               F0 [N]
//   direction_asymmetry  |g|, |v|: friction level and viscous slope differing per direction
//                        (dF [N], dFv [N s/m]); |g| is an offset while sliding but not in
//                        presliding and at rest, where |g| < 1: that tells the two apart
//   position_periodic    per ripple wavelength L_i (ripple_search in structure.hpp, over position
//                        on sliding samples): sin, cos(2 pi x / L_i), g sin, g cos       [N]
//   position_dependent   P1..P3(xi), g P1(xi), g P2(xi); xi = (x - x_mid) / x_half (Legendre)   [N]
//   time_drift           tau, g tau; tau = (t - t_mid) / t_half, t_mid and t_half the training
//                        record's: a rate per second from the same time origin in every record [N]
//   velocity_extra       v|v| / v_ref, g exp(-|v| / (0.2 v_ref))  (drag; low-speed shape)      [N]
//   dwell_stiction       after each rest of T_d >= dwell_min: phi = ln(1 + T_d / tau_d), the
//                        break-away ratio Fs/Fc raised by rho w, w = phi e^-q with q = s / s0
//                        (s = travel since the start; dwell_weight); columns g_rho - g, the
//                        model simulated with that raised level less the model (fit.cpp computes
//                        it; its coefficient is about Fc when the rise is rho), and w g. rho
//                        [-] and s0 [m] are searched on the training residual              [N]
//   normal_load          g (Fn / Fn0 - 1)   (friction proportional to the normal force)         [N]
// Measurement and transmission effects: the model seen through the channel; each adds one column
// (model through the channel - model) whose coefficient is the force level (about Fc when the
// effect is all there is), and one scalar found by a 1-D search on the training residual:
//   time_shift           u_tau - u, u = g + rho v: the force channel lags the position channel by
//                        tau > 0 (sub-sample); u_tau is the model along the motion tau earlier
//                        (shifted_motion: the record's own path between samples)      [N], tau [s]
//   sensor_filter        lowpass_T(u) - u: first-order force sensor (filter) with time constant
//                        T, exact for a piecewise-constant input on the record's grid  [N], T [s]
//                        (rho = sigma2 / Fc of the current fit, held in the context: the lagged
//                        viscous force, about -sigma2 tau a, comes along and is not read as a
//                        negative inertia; a free viscous column would mimic inertia itself)
//   backlash             g_b - g: lost motion b between the encoder and the contact: after each
//                        reversal the contact stays until the motor has travelled b, then follows
//                        b behind (g_b: g at travel s - b since the reversal; held below b) [N], b
//                        [m]
// Normalisations (x_mid, v_ref, L, s0, ...) are learned on the training record and applied
// unchanged to validation records (EffectContext).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/ident/dataset.hpp"
#include "core/ident/library.hpp"

namespace gmslab::ident {

enum class Effect {
  Inertia,
  Offset,
  DirectionAsymmetry,
  PositionPeriodic,
  PositionDependent,
  TimeDrift,
  VelocityExtra,
  DwellStiction,
  NormalLoad,
  TimeShift,
  SensorFilter,
  Backlash,
  // Not in the catalog: the terms discovery kept (library.hpp), as one effect of up to four
  // columns, each a kept term as discovery fitted it (its coefficient times its library column,
  // the force-lag and |F v|-history terms on the force of the model discovery ran on,
  // EffectContext::discovered_force), so each column's coefficient is a dimensionless scale (1: as
  // discovered). Unused slots are zero. No column depends on the fit's own g.
  Discovered
};

// The catalog: every Effect but Discovered.
const std::vector<Effect>& effect_catalog();
std::string_view effect_name(Effect e);
std::string_view effect_meaning(Effect e);
// Throws InputError listing the catalog names.
Effect effect_from_name(std::string_view name);

// Scales learned on the training record.
struct EffectContext {
  double x_mid = 0.0, x_half = 1.0;  // position normalisation [m]
  double t_mid = 0.0, t_half = 1.0;  // time normalisation [s]
  double v_ref = 1.0;                // 95th percentile of |v| on used samples [m/s]
  double x_ba = 1e-5;                // break-away displacement estimated after reversals [m]
  double x_hi_factor = 20.0;         // the softest element the fits allow: x_hi_factor x x_ba
                                     // (widened by identify when the data asks for softer ones)
  double vs_hi_factor = 2.0;         // the highest Stribeck velocity the fits allow: vs_hi_factor
                                     // x v_ref (widened by identify when the fit pins it there)
  double fs_hi_factor = 5.0;         // the highest break-away ratio Fs/Fc the fits allow (widened
                                     // five-fold by identify when the fit pins it there)
  double f_level = 1.0;              // Coulomb level estimated from sliding [N]
  std::vector<double> wavelengths;   // position_periodic wavelengths L_i [m] (empty: none found)
  double time_shift = 0.0;           // time_shift tau [s] (0: not searched yet)
  double filter_T = 0.0;             // sensor_filter time constant T [s] (0: not searched yet)
  double backlash = 0.0;             // backlash lost motion b [m] (0: not searched yet)
  double h_med = 1e-3;               // median sampling step [s]
  double viscous_ratio = 0.0;        // sigma2 / Fc of the fit the channel effects were found on [s/m]
  double Fn0 = 0.0;                  // mean normal force [N] (0: no Fn column)
  double v_rest = 0.0;               // |v| below this is rest [m/s]
  double dwell_min = 0.05;           // shortest rest that counts as a dwell [s]
  double dwell_tau = 0.1;            // tau_d of phi = ln(1 + T_d / tau_d) [s]
  double dwell_s0 = 1e-5;            // decay length of the dwell term s0 [m]
  double dwell_rise = 0.3;           // rise rho of Fs/Fc per unit phi after a rest [-]
  std::vector<DiscoveredTerm> discovered;  // the Discovered effect's terms (at most 4)
  // The force of the model discovery ran on, along a record [N] (the f of the terms that need one);
  // set with `discovered`.
  std::function<std::vector<double>(const Dataset&)> discovered_force;
  // The element grid fit's stand-in for g in effect columns that multiply the friction (the unit
  // output at a warm shape, one value per sample); empty: such effects need the shape search.
  std::vector<double> g_frozen;
};

// Scales from the training record (robust statistics of the used samples).
EffectContext make_context(const Dataset& train);

// A second simulation of the model some columns take besides g (unit_outputs, fit.hpp).
enum class ExtraOutput {
  None,
  Dwell,    // the model with the dwell rise less the model (dwell_stiction)
  Shifted,  // the model along the motion tau earlier (shifted_motion; time_shift)
  Contact   // the model along the contact's motion behind the dead band (backlash)
};

// One linear column: its coefficient's name and unit, whether it depends on g (recomputed at each
// evaluation of the nonlinear fit) and how to compute it.
struct Column {
  std::string name;  // e.g. "M", "ripple_sin1"
  std::string unit;  // unit of the coefficient, e.g. "kg"
  bool uses_g = false;  // g: the unit model output (n samples), followed by the n values of
                        // the column's extra output when it has one (then g.size() == 2 n)
  std::function<void(const Dataset&, const EffectContext&, std::span<const double> g,
                     std::span<double> out)>
      fill;
  ExtraOutput extra = ExtraOutput::None;
};

// The extra outputs a fit with these effects simulates, in the order unit_outputs appends them
// after g.
std::vector<ExtraOutput> extra_outputs(const std::vector<Effect>& effects);
// What `col` takes as g from the unit outputs of a fit whose extra outputs are `extras`
// (extra_outputs of its effects; n samples each: g, then the extra outputs in that order): all of
// them for a column without an extra output, else g and its own extra output (copied into `scratch`
// unless they lie side by side).
std::span<const double> column_input(const Column& col, std::span<const double> outputs,
                                     std::size_t n, const std::vector<ExtraOutput>& extras,
                                     std::vector<double>& scratch);

std::vector<Column> effect_columns(Effect e);
// Whether the effect can be tested on this record (normal_load needs Fn, dwell_stiction dwells,
// position_periodic a wavelength found in the residual, backlash reversals).
bool effect_applicable(Effect e, const Dataset& d, const EffectContext& c);

// Travel since the last reversal of the motion [m] (from the start before the first one).
// turn (if given): per sample, the index of that reversal (0 before the first).
std::vector<double> travel_since_reversal(const Dataset& d, const EffectContext& c,
                                          std::vector<std::size_t>* turn = nullptr);

// The channel transformations of the force-channel effects, applied to a series y on d's grid:
// y(t - tau) (linear interpolation, held at the ends); first-order low-pass with time constant T.
void shifted(const Dataset& d, std::span<const double> y, double tau, std::span<double> out);
void lowpass(const Dataset& d, std::span<const double> y, double T, std::span<double> out);

// The contact's motion behind a lost motion (a dead band of width b) between the encoder and the
// contact: the contact stays where it is while the encoder is within b / 2 of it, and is dragged
// along b / 2 behind it beyond; at the start it sits at the encoder's position (the middle of the
// band). Returns d with every step's velocity (vstep, and sv along curved paths) the contact's,
// x the contact's position and v its velocity at each sample (0 where it rests in the band): the
// record the friction model sees through the play. The encoder moves by the measured displacement
// over each step, as the steps of d do.
Dataset through_dead_band(const Dataset& d, double b);

// The record's motion tau earlier (tau >= 0; the force channel lags the position channel by
// tau): each sample k at t_k - tau on d's path (its steps and substeps; at rest at x_0 before the
// record starts), v and a interpolated linearly in time, t, F and the mask those of d; between
// the shifted samples the cubic through their positions and slopes, in as many parts as the most
// any step of d it overlaps has (straight where d is). The model along it is the friction the
// force channel records at t_k.
Dataset shifted_motion(const Dataset& d, double tau);

// Standing still: |v| below a twentieth of the rest threshold c.v_rest [m/s].
double standstill(const EffectContext& c);

// Motion starts after rests of at least c.dwell_min (|v| below c.v_rest, standing still at
// |v| < 0.05 c.v_rest within it; the rest the record begins in only where the position stays
// within two encoder counts): index of the first moving sample, rest duration [s] (from the rest's
// first standstill sample), direction.
struct MotionStart {
  std::size_t k;
  double dwell;
  double dir;
};
std::vector<MotionStart> motion_starts(const Dataset& d, const EffectContext& c);
// Per sample, the dwell weight w = phi e^-q of the motion that started after the last rest
// (phi = ln(1 + T_d / c.dwell_tau), q = |x - x_start| / c.dwell_s0), from the sample before the
// start until the motion comes to rest again or q > 30; 0 elsewhere.
std::vector<double> dwell_weight(const Dataset& d, const EffectContext& c);

}  // namespace gmslab::ident

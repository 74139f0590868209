// gmslab identification: the residual loop that finds what the base model lacks.
//
//   1. Fit the base model (several starts) on the training record; estimate the force noise from
//      the data (structure.hpp: second differences during rests).
//   2. Each round: residual r on training. The ripple search (structure.hpp) gives the
//      position_periodic wavelengths (significant peaks only); the dwell decay length and the
//      channel effects' scalars (time_shift tau, sensor_filter T, backlash b) are searched by
//      linear refits. Every applicable catalog effect not yet in the model is screened: its
//      columns re-solved at the current shape -> explained training variance, validation RMS and
//      a training F-test of its columns (the signature). When no screened effect brings the
//      validation RMS within 1.15x the noise, the channel effects are searched again with short
//      shape refits (a lagging force channel looks like softer presliding to the base model) and
//      screened at their own shapes; this deep search runs once per effect (in later rounds its
//      scalar is tuned by linear refits only).
//   3. Candidates in order of screening validation RMS (held-out data decides between effects
//      that look alike on training, e.g. offset and a level asymmetry; inertia and a force lag):
//      refit everything with the effect (shape warm-started + linear terms). An effect is kept
//      only when all hold: the validation RMS drops by at least min_gain (relative), also against
//      a control refit of the current model with the same budget (better optimisation is never
//      credited to an effect); its training F-test p-value times the number of candidates is
//      below max_p; the validation BIC (n ln SSR/n + p ln n) drops; its contribution's RMS is at
//      least min_size x the noise floor (noise and encoder quantisation), and below sure_size x the
//      floor it explains min_excess of the validation MSE above the floor. The first
//      tries_per_round candidates are all refitted (the base shape may have absorbed part of an
//      effect, e.g. an offset taken up by a soft element, so the screening order alone does not
//      decide; a candidate whose screening RMS is above 1.5x a kept refit's is not refitted) and
//      the kept one with the lowest validation RMS is added; when another fits the
//      validation record alike the report says the data cannot tell them apart (notes). An
//      attempt that a guard refused (too small, a negative mass, within what the sampling
//      changes) does not use up a try (at most 2 x tries_per_round attempts). When none is kept
//      and the validation RMS stays above refit_above_floor x the floor, up to train_tries more
//      candidates are refitted in order of their screening training RMS (the current shape may
//      have bent to the missing effect and hide it from the validation screening). No candidate
//      kept: stop.
//   4. The final model gets one more refit (as the control), the standard errors of its linear
//      terms and effect scalars (linearised least squares at the fitted shape), and the final
//      validation residual is tested for remaining structure (by velocity, position, time, after
//      reversals, position spectrum), each against the noise (IdentReport::remaining).
// Validation: a second record, or the hold-out of the training record (dataset.hpp).
#pragma once

#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/figures/figure.hpp"
#include "core/ident/ablation.hpp"
#include "core/ident/discovery.hpp"
#include "core/ident/fit.hpp"
#include "core/ident/structure.hpp"
#include "core/sim/scenario.hpp"

namespace gmslab::ident {

struct LoopOptions {
  FitOptions base;              // the base fit
  FitOptions refit;             // refits after adding an effect (warm start)
  double min_gain = 0.03;       // relative validation RMS drop needed to keep an effect [-]
  double min_explained = 0.002; // smallest explained training variance worth a refit [-]
  double max_p = 1e-3;          // largest chance (training F-test of the effect's columns, times
                                // the candidates screened) that still counts as a signature [-]
  double min_size = 0.5;        // smallest effect contribution (RMS on training) / noise floor [-]
  double sure_size = 1.5;       // below this contribution / floor, an effect must also explain
  double min_excess = 0.4;      // this share of the validation MSE above the floor [-]
  int tries_per_round = 3;
  // When no candidate is kept and the validation RMS stays above refit_above_floor x the floor,
  // up to train_tries more candidates (in order of their screening *training* RMS, signature
  // required) are refitted: the shape may have bent to the missing effect.
  double refit_above_floor = 1.3;
  int train_tries = 2;
  int max_rounds = 9;
  // A training record of at least 2 x screen_samples samples is screened on every k-th sample
  // (k = samples / screen_samples): the base fit and the loop's refits and decisions run there;
  // the noise floor, the final refit (one local search from the screened shape), the parameter
  // errors and all validation RMS use every sample. 0: never.
  std::size_t screen_samples = 2000;
  // The rounds are not run when the base fit's validation MSE above the floor is below the
  // floor's variance (base within sqrt(2) x the floor): an effect could lower the validation MSE
  // by no more than that, less than the rise the credit test needs to name it by size
  // (ablation.hpp), and no candidate's screening (round 1's linear refits at the current shape)
  // predicts the held-out record better by the credit's block test (z >= z_crit), the clause
  // the size does not bound. IdentReport::rounds_skipped says so. false: the rounds always run.
  bool credit_bound = true;
  std::vector<Effect> candidates;  // empty = the whole catalog
  LoopOptions();
};

struct Attempt {
  Effect effect = Effect::Offset;
  double rms_train = 0, rms_validation = 0;  // after the refit [N]
  bool kept = false;
  std::vector<LinearTerm> terms;             // the effect's fitted coefficients
  double size = 0;                           // RMS of the effect's contribution (training) [N]
  double bic_change = 0;                     // BIC(with) - BIC(without), validation SSR [-]
  std::string verdict;                       // why kept or not
};

struct Candidate {
  Effect effect;
  double explained = 0;           // fraction of training residual variance explained (screen)
  double screen_rms_train = 0;    // [N]
  double screen_rms_validation = 0;
  // Block test (ablation.hpp) of the screening fit against the current model on the validation
  // record: z of the drop in squared residual over time blocks [-]; NaN when not computed.
  double screen_z = std::numeric_limits<double>::quiet_NaN();
  double p_value = 1;             // training F-test of the columns at the current shape [-]
  std::size_t columns = 0;        // columns the effect adds
  nlohmann::json evidence;
};

struct Round {
  double rms_train_before = 0, rms_validation_before = 0;
  double rms_train_after = 0, rms_validation_after = 0;
  std::vector<Candidate> candidates;  // sorted, most explaining first
  std::vector<Attempt> attempts;
  std::optional<Effect> added;
};

// Default time limit of each comparison fit [s] (FitOptions::max_seconds for compare_models).
inline constexpr double kCompareSeconds = 60.0;

// A parameter of the final model with its standard error: the linearised least squares at the
// fitted shape, with the shape's coordinates as nuisance columns (their correlation carried), the
// covariance cluster-robust over time blocks and never below the white-noise one. Scalars of the
// measurement effects (tau, T, b) and ripple wavelengths get theirs from the derivative of their
// columns. No standard error (NaN, and `no_error` says why) when the fit is not at a verified
// minimum (IdentReport::optimum), or for the Coulomb level and the viscous coefficient of a
// Stribeck curve that the record does not slide fast enough to reach (stribeck_reach below): the
// value is then an extrapolation of the curve's form, which a local error does not describe.
struct ParameterEstimate {
  std::string effect, name, unit;
  double value = 0, std_error = 0;
  // The part of std_error (added in quadrature) from the unmeasured path between samples: the
  // shift of the estimate when the model runs along straight steps instead of the cubic, over
  // sqrt(3) [unit].
  double path_error = 0;
  std::string no_error;  // why std_error is NaN (empty when it is given)
  // The part of std_error (in quadrature) from the encoder's rounding: the shift of the estimate
  // when the model runs along the smoothest positions within half an encoder step of the recorded
  // ones (dataset.hpp: within_encoder_step) instead of the recorded ones [unit].
  double encoder_error = 0;
};

// How far the record's sliding reaches down a Stribeck curve S(v) = Fc + (Fs - Fc)
// exp(-(v/Vs)^delta): at the record's top sliding speed v_top (the 99th percentile of |v| over the
// used samples) the curve still stands `excess` x Fc above the Coulomb level Fc. Empty for a model
// without the scalars Fs, Fc, Vs, delta, or a record that does not move.
struct StribeckReach {
  double v_top = 0;     // [m/s]
  double excess = 0;    // (S(v_top) - Fc) / Fc [-]
  double v_needed = 0;  // the speed at which excess falls to `limit` [m/s] (0: at any speed)
};
std::optional<StribeckReach> stribeck_reach(const ModelParams& p, const Dataset& d, double limit);
// Above this excess the Coulomb level Fc and the viscous coefficient sigma2 (which trades with
// the level over the speeds the record holds) are reported without a standard error: their
// values extrapolate the curve's form beyond the data. 1 % of Fc: on the random-truth records of
// seeds 7000-7029 (gmslab_study coverage) every fit whose Fc missed the truth by more than 20 %
// stood 3.6 % or more above Fc at its top speed, every fit within 2 standard errors 0.07 % or less.
inline constexpr double kStribeckReachLimit = 0.01;

// One model of a comparison: fitted on the same training record, with the same effects.
// Whether the final fit sits at a verified minimum of the training cost (loop.cpp:
// check_optimum). Where it does not, the parameters carry no standard error (NaN).
struct OptimumCheck {
  bool verified = true;
  std::string reason;  // why not (empty when verified)
  // A shape parameter ends at an end of its search range (the reason says which).
  bool pinned = false;
};

struct ModelComparison {
  std::string model;           // registry tag
  std::size_t elements = 0;    // element count used (0: the model has none)
  std::size_t shape_parameters = 0;  // searched (nonlinear) parameters
  double rms_train = 0, rms_validation = 0;  // [N]
  int evaluations = 0;
  double seconds = 0;          // wall time of the fit [s]
  bool time_limited = false;   // the fit hit FitOptions::max_seconds (not converged)
};

struct IdentReport {
  std::string model;
  std::size_t elements = 0;
  std::string train_source, validation_source, force_unit = "N";
  std::size_t train_samples = 0, validation_samples = 0;
  EffectContext context;
  std::vector<FitResult> stages;  // base fit, then the fit after each kept effect
  double rms_before_train = 0, rms_before_validation = 0;
  double rms_after_train = 0, rms_after_validation = 0;
  std::vector<Effect> effects_added;
  std::vector<Round> rounds;
  std::vector<ModelComparison> comparison;  // compare_models(); empty unless asked for
  NoiseEstimate noise;                      // force noise sigma estimated from the training record
  RippleSearch ripples;                     // ripple search on the base fit's residual
  std::vector<ParameterEstimate> parameters;  // final model's linear terms and effect scalars
  ResidualStructure remaining;              // what the final validation residual still holds;
                                            // remaining.summary is one line for CLI and panel
  std::vector<std::string> notes;           // undecided choices, said in words
  // Credit by ablation (ablation.hpp): effects_added holds the credited effects only; the table
  // has the validation RMS with all of them and with each left out, and what was dropped.
  Ablation ablation;
  // Terms beyond the catalog (discovery.hpp), run after the credit when structure remains; the
  // kept terms are part of the final prediction (predict_final) and of rms_after_*.
  Discovery discovery;
  OptimumCheck optimum;                     // standard errors only where verified
  // The path between samples: the base fit's friction along the fine path (every interval along
  // the cubic, kFinePath) minus along the adaptive one, RMS over the training record [N];
  // measured only where the attraction is fast (C / Fs x median step >= 0.1), else 0. Above a
  // quarter of the noise the whole identification runs on the fine path (fine_path = true).
  double path_difference = 0;
  bool fine_path = false;
  // The base fit was retried from other starts (its probe grid cost was 1.3-5x the floor).
  bool base_retried = false;
  // The element range was widened beyond 20 x the swing estimate (softer elements in the data).
  bool range_widened = false;
  // The Stribeck velocity's range was widened beyond 2 x v_ref (widen_stribeck_range: the record
  // stays on the falling branch of the Stribeck curve).
  bool stribeck_range_widened = false;
  // The break-away ratio's range was widened beyond Fs/Fc = 5 (widen_break_away_range: the base
  // fit pinned Fs/Fc at the top of its range).
  bool break_away_range_widened = false;
  // The loop screened the training record on every screen_every-th sample (1: all of them;
  // LoopOptions::screen_samples). Training RMS of the stages before the final one are on those.
  std::size_t screen_every = 1;
  // Why the rounds were not run (LoopOptions::credit_bound), empty when they ran.
  std::string rounds_skipped;
  const FitResult& final_fit() const { return stages.back(); }
};

// The base fit: fit_model, or with base.elements == 0 (--elements auto) the element count chosen
// by the validation record (element_fit.hpp).
FitResult fit_base(const FitSpec& base, const Dataset& train, const Dataset& validation,
                   const EffectContext& c, const FitOptions& o);

// "nothing added: no catalog effect is credited by the data", or with the rounds skipped by the
// credit bound, why no effect could be credited, or where one more element explained what the
// effects took up, that the data call for more elements (ablation.hpp: more_elements_summary);
// empty when effects were named.
std::string nothing_added(const IdentReport& r);

// "the loop screened every 12th training sample; the final fit used all" (empty when it used all).
std::string screen_summary(const IdentReport& r);

IdentReport identify(const Dataset& train, const Dataset& validation, const FitSpec& base,
                     const LoopOptions& o);

// Fits each model (registry tags) on the training record with the effects the loop added, so the
// models are compared like for like, and reports their training and validation RMS. Multi-element
// models use the report's element count (clamped to the model's range). Options as the base fit
// (progress, cancel); o.max_seconds bounds each model's fit (slow models are reported as such).
std::vector<ModelComparison> compare_models(const IdentReport& r, const Dataset& train,
                                            const Dataset& validation, const std::vector<std::string>& models,
                                            const FitOptions& o);
// "all" -> every registered model; "a,b,c" -> those tags (InputError naming an unknown one).
std::vector<std::string> parse_model_list(std::string_view spec);

// The final model's force along d with the discovered terms (IdentReport::discovery) added.
std::vector<double> predict_final(const IdentReport& r, const Dataset& d);

nlohmann::json to_json(const IdentReport& r);
// Data vs final fit (validation), and the residual of each stage over time (training).
Figure report_figure(const IdentReport& r, const Dataset& train, const Dataset& validation);
// A scenario that replays the training motion (displacement drive) through the identified
// friction model; plant mass = the identified inertia when found (else 1 kg). Effects that a
// scenario cannot hold (offset, ripple, ...) are listed in the description.
Scenario identified_scenario(const IdentReport& r, const Dataset& train);

}  // namespace gmslab::ident

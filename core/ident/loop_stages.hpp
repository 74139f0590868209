// The residual loop's stages (loop.hpp describes the method). identify() runs them in order on
// one LoopState:
//
//   screen_record      the base fit, on every k-th sample of a long record when that drives the
//                      friction as the full record does
//   choose_path        the fine path between samples where the attraction is fast enough for it
//                      to matter, and the floor's quantisation and sampling shares
//   retry_base_fit     the base fit again from other starts when it stays 1.3-5x above the floor
//   widen_element_range softer elements than the swing estimate allows (before and after rounds)
//   no_effect_creditable the credit bound: base within sqrt(2) x the floor, no round run
//   run_round          one round: screen the catalog, refit the best candidates, keep one
//   final_refit        the final model refitted on all samples
//   credit             credit by ablation (ablation.hpp): the effects and elements named
//                      (with a count it raised, also the fit at that count from the data)
//   descend_to_minimum a pattern search from a final shape the optimum test finds short of a
//                      minimum (not from one pinned at an end of its range)
//   discover_terms     terms beyond the catalog (discovery.hpp) when structure remains
//   join_discovered    the kept terms fitted jointly with the model (Effect::Discovered), every
//                      effect credited again with them in the model
//   finish_report      parameter errors at a verified optimum, what the residual still holds
//
// Internal to the identification: not a public interface.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/ident/loop.hpp"

namespace gmslab::ident::detail {

// What the stages share: the records, the context, the model so far and the report.
struct LoopState {
  LoopState(const Dataset& train, const Dataset& validation, const FitSpec& base, const LoopOptions& o);

  const Dataset& train_in;  // the training record as given
  const Dataset& val_in;    // the validation record as given
  const FitSpec& base;
  const LoopOptions& o;
  EffectContext c;
  IdentReport rep;
  std::size_t every = 1;    // the loop screens on every k-th training sample
  Dataset screen_rec;       // every k-th sample (of the fine-path record when fine_path)
  Dataset train_fine, val_fine;  // the records on the fine path (when rep.fine_path)
  FitResult cur;            // the model so far
  double cur_val = 0;       // its validation RMS [N]
  NoiseEstimate noise_data; // the noise estimated from the data, before the model's shares
  double floor = 0;         // the floor the rounds judge against [N]
  double credit_floor = 0;  // the floor the credit and the discovery are judged against [N]
  std::set<Effect> deep_done;  // channel effects whose scalar was searched with shape refits
  // Round 1's control refit (the base model with the refit budget), made ahead by the credit
  // bound (no_effect_creditable) when it did not skip the rounds.
  std::optional<FitResult> control;
  // The base model as fit_base made it from the data with the base options (a fixed element
  // count only) and the record it was fitted on, with the context as it was then: the credit's
  // ablation fits that spec from the data on that record again where no round ran (credit()).
  // Reset where the context changes (the element range widened).
  std::optional<FitResult> base_from_data;
  const Dataset* base_from_data_on = nullptr;
  // fit_base(base, d, v, c, o.base), recorded as above.
  FitResult fit_base_from_data(const Dataset& d, const Dataset& v);
  // The optimum test of cur made by descend_to_minimum (cur has not moved since); finish_report
  // uses it instead of testing again.
  std::optional<OptimumCheck> optimum;

  // All training samples, on the path the loop decided on.
  const Dataset& full() const { return rep.fine_path ? train_fine : train_in; }
  const Dataset& val() const { return rep.fine_path ? val_fine : val_in; }
  // The record the loop's fits and decisions run on (screened or full).
  const Dataset& train() const { return every > 1 ? screen_rec : full(); }
  // f's friction force along d (straight: with straight steps between samples) [N].
  std::vector<double> friction_force(const FitResult& f, const Dataset& d, bool straight = false) const;
  // e with the quantisation and sampling shares through model f along d.
  void add_model_shares(NoiseEstimate& e, const FitResult& f, const Dataset& d) const;
  // rep.noise: the data's noise with the shares through the current model along full(), and the
  // credit bound's halving estimate of the sampling share.
  void add_shares();
  // The report's last stage and the last round's numbers after it follow cur and cur_val (a
  // stage that moved the model it ended with).
  void set_last_stage();
};

void screen_record(LoopState& s);
void choose_path(LoopState& s);
void retry_base_fit(LoopState& s);
void widen_element_range(LoopState& s, bool before_rounds);
// The Stribeck velocity's range a decade wider where the base fit pins Vs at its upper end.
void widen_stribeck_range(LoopState& s);
// The break-away ratio's range five-fold wider where the base fit (before_rounds) or the final
// model pins Fs/Fc at its upper end.
void widen_break_away_range(LoopState& s, bool before_rounds);
// Why f is no verified minimum where its break-away ratio presses on the top of the widest range
// the loop searches (125); none below it.
std::optional<std::string> beyond_widest_break_away_range(const FitResult& f,
                                                          const EffectContext& c);
// Whether the base fit is so close to the floor that no effect can be credited by size (the
// credit bound, LoopOptions::credit_bound); then rep.rounds_skipped says why.
bool no_effect_creditable(LoopState& s);
// One round of the loop; whether it added an effect.
bool run_round(LoopState& s, int round);
// Round 1's screening alone (its context tuning and every candidate's linear refit at the current
// shape), for the credit bound: the candidate whose screening fit predicts the held-out record
// better than the current model by the credit's block test (z >= z_crit), the best such; none
// when no screening does. s's context is left as it was (round 1 tunes it again).
std::optional<Candidate> screening_resolves(LoopState& s, double z_crit);
void final_refit(LoopState& s);
void credit(LoopState& s);
// A compass search from the final shape on the optimum test's steps (check_optimum).
void descend_to_minimum(LoopState& s);
void discover_terms(LoopState& s);
void join_discovered(LoopState& s);
void finish_report(LoopState& s);

// Shared by the stages.
std::string fmt(double x);
std::string ordinal(std::size_t n);  // 2 -> "2nd"
bool contains(const std::vector<Effect>& v, Effect e);
std::vector<double> residual(const FitResult& f, const Dataset& d, const EffectContext& c);
std::vector<LinearTerm> terms_of(const FitResult& f, Effect e);
FitSpec with(const FitSpec& s, Effect e);
// Whether one of e's columns multiplies the friction (needs g, the unit model output).
bool multiplies_friction(Effect e);
// spec with the additive effects a shape or a soft element could stand in for added as probes.
FitSpec with_additive_probes(FitSpec spec, bool inertia = true);
FitSpec additive_probes_for(const FitResult& f, const Dataset& d, const EffectContext& c);
// Effect e screened at the shape of cur (or at `shape`): its columns re-solved by least squares.
// With r_val (cur's residual on val), also the block test of the screening fit against cur on
// val (Candidate::screen_z).
Candidate screen(Effect e, const FitResult& cur, const Dataset& train, const Dataset& val,
                 const EffectContext& c, const std::vector<double>* shape = nullptr,
                 const std::vector<double>* r_val = nullptr);

}  // namespace gmslab::ident::detail

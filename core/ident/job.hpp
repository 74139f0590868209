// gmslab identification: the one identification job behind every front end. The CLI
// (`gmslab identify`), the Identify panel, `render --view identify` and any API call fill an
// IdentifyJob (one struct, one set of defaults) and call run_identification().
//
//   load the training record (and the validation record, or hold out a part of the training
//   record) -> the residual loop (identify) -> optionally the model comparison
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "core/ident/loop.hpp"

namespace gmslab::ident {

struct IdentifyJob {
  RecordSpec train;              // path, column map, masks (RecordSpec defaults: no masks)
  RecordSpec validation;         // path "" = hold out `holdout` of the training record
  double holdout = 0.25;         // fraction held out without a validation record [0.1, 0.5]
  FitSpec spec;                  // model (default gms) and element count (4; 0 = auto)
  std::string method = "bobyqa";
  int starts = 3;                // starts of the base fit (models fitted without the grid)
  int max_evaluations = 500;     // cost evaluations per start / per polish
  double min_gain = 0.03;        // relative validation RMS drop to keep an effect
  std::vector<Effect> candidates;  // empty = the whole catalog
  std::vector<std::string> compare;  // models to compare after the loop (registry tags)
  double compare_seconds = kCompareSeconds;
};

struct IdentifyOutcome {
  Dataset train, validation;
  IdentReport report;
  std::vector<std::string> notes;  // e.g. a mask column the record lacks
};

// Runs the job. progress may be empty; a set *cancel throws Cancelled. Throws InputError for a
// bad record, mask, model or element count (naming the file, line or option).
IdentifyOutcome run_identification(const IdentifyJob& job,
                                   const std::function<void(const FitProgress&)>& progress = {},
                                   const std::atomic<bool>* cancel = nullptr);

// "4" -> 4, "auto" -> 0 (the validation chooses); throws InputError naming `what` otherwise
// (whole numbers 1..64).
std::size_t parse_element_count(std::string_view text, std::string_view what = "--elements");

}  // namespace gmslab::ident

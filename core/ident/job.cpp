#include "core/ident/job.hpp"

#include <charconv>

#include "core/error.hpp"

namespace gmslab::ident {

IdentifyOutcome run_identification(const IdentifyJob& job,
                                   const std::function<void(const FitProgress&)>& progress,
                                   const std::atomic<bool>* cancel) {
  IdentifyOutcome out;
  if (!(job.holdout >= 0.1 && job.holdout <= 0.5))
    throw InputError("holdout " + std::to_string(job.holdout) + ": allowed 0.1 to 0.5");
  FitSpec spec = job.spec;
  spec.model = std::string(model_info(spec.model).tag);  // names the known tags when unknown
  for (const auto& m : job.compare) (void)model_info(m);  // fail before the run
  std::string note;
  out.train = load_dataset(job.train, &note);
  if (!note.empty()) out.notes.push_back(note);
  if (!job.validation.path.empty()) {
    note.clear();
    out.validation = load_dataset(job.validation, &note);
    if (!note.empty()) out.notes.push_back(note);
  } else {
    auto split = split_holdout(out.train, job.holdout);
    out.train = std::move(split.first);
    out.validation = std::move(split.second);
  }
  LoopOptions lo;
  lo.base.method = lo.refit.method = job.method;
  lo.base.starts = job.starts;
  lo.base.max_evaluations = job.max_evaluations;
  lo.min_gain = job.min_gain;
  if (!job.candidates.empty()) lo.candidates = job.candidates;
  lo.base.progress = lo.refit.progress = progress;
  lo.base.cancel = lo.refit.cancel = cancel;
  out.report = identify(out.train, out.validation, spec, lo);
  if (!job.compare.empty()) {
    FitOptions co = lo.base;
    co.max_seconds = job.compare_seconds;
    out.report.comparison = compare_models(out.report, out.train, out.validation, job.compare, co);
  }
  return out;
}

std::size_t parse_element_count(std::string_view text, std::string_view what) {
  if (text == "auto") return 0;
  int n = 0;
  const auto* end = text.data() + text.size();
  const auto [p, ec] = std::from_chars(text.data(), end, n);
  if (ec != std::errc() || p != end || n < 1 || n > 64)
    throw InputError(std::string(what) + " '" + std::string(text) +
                     "': expected a whole number from 1 to 64, or 'auto' (the validation record "
                     "chooses)");
  return static_cast<std::size_t>(n);
}

}  // namespace gmslab::ident

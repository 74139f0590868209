// gmslab's own trace of a one-body scenario as a measured record, identified with the generating
// model: the tests of what the report says about a fit whose truth is known exactly.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>

#include "core/ident/loop.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab::ident::own {

struct OwnTraceFit {
  IdentReport report;
  Dataset train;
};

// Simulates sc, keeps every 20th sample with noise of 0.3 % of the largest friction force (drawn
// from rng), and holds out a quarter for validation: (training, validation).
inline std::pair<Dataset, Dataset> own_records(const Scenario& sc, std::mt19937& rng,
                                               const char* source) {
  AssemblySimulation sim = one_body_simulation(sc);
  sim.run_to_end();
  const Trace& tr = sim.one_body_trace();
  double fmax = 0;
  for (double f : tr.friction) fmax = std::max(fmax, std::abs(f));
  std::normal_distribution<double> N(0.0, 1.0);
  MeasuredRecord rec;
  rec.source = source;
  for (std::size_t i = 0; i < tr.size(); i += 20) {
    rec.t.push_back(tr.t[i]);
    rec.x.push_back(tr.x[i]);
    rec.F.push_back(tr.friction[i] + 0.003 * fmax * N(rng));
  }
  return split_holdout(prepare_dataset(rec));
}

// The records of own_records identified with the scenario's model and element count, base fit
// only (max_rounds 0).
inline OwnTraceFit identify_own_trace(const Scenario& sc, std::mt19937& rng, const char* source) {
  auto [train, val] = own_records(sc, rng, source);
  FitSpec spec;
  spec.model = sc.friction.model;
  spec.elements = sc.friction.elements.size();
  LoopOptions o;
  o.max_rounds = 0;
  OwnTraceFit out;
  out.report = identify(train, val, spec, o);
  out.train = std::move(train);
  return out;
}

}  // namespace gmslab::ident::own

#include "core/sim/phases.hpp"

#include <cmath>

namespace gmslab {

Phase phase_at(const Trace& tr, std::size_t k, double slip_velocity) {
  if (std::fabs(tr.v[k]) > slip_velocity) return Phase::Slip;
  const std::size_t ne = tr.n_elements;
  if (ne == 0 || (k + 1) * ne > tr.element_slip.size()) return Phase::Stick;
  for (std::size_t i = 0; i < ne; ++i)
    if (tr.element_slip[k * ne + i] == 0) return Phase::Stick;
  return Phase::Slip;
}

void classify_phases(const Trace& tr, double slip_velocity, std::vector<std::uint8_t>& out) {
  out.resize(tr.size());
  for (std::size_t k = 0; k < tr.size(); ++k)
    out[k] = static_cast<std::uint8_t>(phase_at(tr, k, slip_velocity));
}

std::span<const std::uint8_t> PhaseSeries::update(const Trace& tr, double slip_velocity) {
  const bool same = trace_ == &tr && revision_ == tr.revision && threshold_ == slip_velocity &&
                    phase_.size() <= tr.size();
  if (!same) {
    phase_.clear();
    trace_ = &tr;
    revision_ = tr.revision;
    threshold_ = slip_velocity;
  }
  phase_.reserve(tr.size());
  for (std::size_t k = phase_.size(); k < tr.size(); ++k)
    phase_.push_back(static_cast<std::uint8_t>(phase_at(tr, k, slip_velocity)));
  return phase_;
}

}  // namespace gmslab

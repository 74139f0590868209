#include "core/sim/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace gmslab {

const char* to_string(Drive::Kind k) {
  switch (k) {
    case Drive::Kind::Displacement: return "displacement";
    case Drive::Kind::Velocity: return "velocity";
    case Drive::Kind::Force: return "force";
    case Drive::Kind::Pull: return "pull";
  }
  return "?";
}

double stability_limit_dt(const Scenario& s) {
  if (s.drive.kind == Drive::Kind::Displacement || s.drive.kind == Drive::Kind::Velocity)
    return std::numeric_limits<double>::infinity();
  double k = s.plant.spring + (s.drive.kind == Drive::Kind::Pull ? s.drive.pull_spring : 0.0);
  const auto& info = model_info(s.friction.model);
  if (const auto c = info.column_index("k"); c >= 0)
    for (const auto& row : s.friction.elements) k += row[static_cast<std::size_t>(c)];
  if (const auto i = info.scalar_index("sigma0"); i >= 0) k += s.friction.scalars[i];
  if (k <= 0.0) return std::numeric_limits<double>::infinity();
  return 2.0 / std::sqrt(k / s.plant.mass);
}

void Trace::clear() {
  t.clear();
  x.clear();
  v.clear();
  friction.clear();
  applied.clear();
  element_force.clear();
  element_slip.clear();
  ++revision;
}

void Trace::swap_samples(Trace& o) noexcept {
  t.swap(o.t);
  x.swap(o.x);
  v.swap(o.v);
  friction.swap(o.friction);
  applied.swap(o.applied);
  element_force.swap(o.element_force);
  element_slip.swap(o.element_slip);
}

void check_scenario(const Scenario& s) {
  std::vector<std::string> bad = validate(s.friction, "friction");
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) bad.push_back(what);
  };
  const bool massive = s.drive.kind == Drive::Kind::Force || s.drive.kind == Drive::Kind::Pull;
  need(std::isfinite(s.plant.mass) && s.plant.mass > 0, "plant.mass: must be > 0 kg");
  need(std::isfinite(s.plant.spring) && s.plant.spring >= 0, "plant.spring: must be >= 0 N/m");
  need(std::isfinite(s.plant.damper) && s.plant.damper >= 0, "plant.damper: must be >= 0 N s/m");
  append_run_problems(s.run, bad);
  if (bad.empty() && massive) {
    const double lim = stability_limit_dt(s);
    if (s.run.dt >= lim) {
      std::ostringstream o;
      o << "run.dt: " << s.run.dt << " s is too large for the stiffest mode of this plant "
        << "(stuck friction elements + springs): it must be < " << lim
        << " s = 2/sqrt(sum k / m); about a tenth of that is accurate";
      bad.push_back(o.str());
    }
  }
  throw_if_invalid(s.name, bad);
}

void append_run_problems(const RunSettings& r, std::vector<std::string>& bad) {
  if (!(std::isfinite(r.dt) && r.dt > 0 && r.dt <= 1.0)) bad.push_back("run.dt: must be in (0, 1] s");
  if (!(std::isfinite(r.duration) && r.duration > 0 && r.duration <= 1e6))
    bad.push_back("run.duration: must be in (0, 1e6] s");
  if (r.record_every < 1) bad.push_back("run.record_every: must be >= 1");
  if (bad.empty() && r.duration / r.dt > 1e10)
    bad.push_back("run: duration / dt exceeds 1e10 steps; raise dt or shorten the run");
}

void throw_if_invalid(const std::string& name, const std::vector<std::string>& bad) {
  if (bad.empty()) return;
  std::string msg = "invalid scenario '" + name + "':";
  for (const auto& b : bad) msg += "\n  " + b;
  throw InputError(msg);
}

void compact_minmax(Trace& tr, double dt, std::uint64_t bucket_steps) {
  const std::size_t n = tr.size();
  const std::size_t ne = tr.element_force.size() == n * tr.n_elements && tr.element_slip.size() == n * tr.n_elements
                             ? tr.n_elements
                             : 0;
  if (ne == 0) {
    tr.element_force.clear();
    tr.element_slip.clear();
  }
  auto bucket = [&](std::size_t k) { return static_cast<std::uint64_t>(std::llround(tr.t[k] / dt)) / bucket_steps; };
  const std::vector<double>* cols[4] = {&tr.x, &tr.v, &tr.friction, &tr.applied};
  std::size_t out = 0;
  for (std::size_t i = 0; i < n;) {
    const std::uint64_t b = bucket(i);
    std::size_t j = i + 1;
    while (j < n && bucket(j) == b) ++j;
    std::size_t keep[10];
    int nk = 0;
    keep[nk++] = i;
    keep[nk++] = j - 1;
    for (const auto* c : cols) {
      const double* y = c->data();
      std::size_t lo = i, hi = i;
      for (std::size_t k = i + 1; k < j; ++k) {
        if (y[k] < y[lo]) lo = k;
        if (y[k] > y[hi]) hi = k;
      }
      keep[nk++] = lo;
      keep[nk++] = hi;
    }
    std::sort(keep, keep + nk);
    nk = static_cast<int>(std::unique(keep, keep + nk) - keep);
    for (int q = 0; q < nk; ++q, ++out) {  // out <= keep[q]: moving forward in place is safe
      const std::size_t k = keep[q];
      if (k == out) continue;
      tr.t[out] = tr.t[k];
      for (auto* c : {&tr.x, &tr.v, &tr.friction, &tr.applied}) (*c)[out] = (*c)[k];
      for (std::size_t e = 0; e < ne; ++e) {
        tr.element_force[out * ne + e] = tr.element_force[k * ne + e];
        tr.element_slip[out * ne + e] = tr.element_slip[k * ne + e];
      }
    }
    i = j;
  }
  for (auto* c : {&tr.t, &tr.x, &tr.v, &tr.friction, &tr.applied}) c->resize(out);
  tr.element_force.resize(out * ne);
  tr.element_slip.resize(out * ne);
  ++tr.revision;
}

namespace {
// Largest explicit step for the damping of a mass-driven plant: 2 m / sum c, where sum c adds the
// plant and pull dampers and the friction's velocity terms (sigma2, sigma1, micro-damping sigma_i),
// all of which the frozen-velocity step applies explicitly. +inf for prescribed motion.
double damping_limit_dt(const Scenario& s, double& c) {
  c = 0.0;
  if (s.drive.kind == Drive::Kind::Displacement || s.drive.kind == Drive::Kind::Velocity)
    return std::numeric_limits<double>::infinity();
  c = s.plant.damper + (s.drive.kind == Drive::Kind::Pull ? s.drive.pull_damper : 0.0);
  const auto& info = model_info(s.friction.model);
  for (const char* key : {"sigma1", "sigma2"})
    if (const auto i = info.scalar_index(key); i >= 0) c += s.friction.scalars[i];
  if (const auto col = info.column_index("sigma"); col >= 0)
    for (const auto& row : s.friction.elements) c += row[static_cast<std::size_t>(col)];
  return c > 0.0 ? 2.0 * s.plant.mass / c : std::numeric_limits<double>::infinity();
}

}  // namespace

std::string divergence_cause(const Scenario& s) {
  const double h = s.run.dt, lim_k = stability_limit_dt(s);
  double c = 0.0;
  const double lim_c = damping_limit_dt(s, c);
  std::ostringstream o;
  o << "Likely cause: ";
  if (h >= lim_c)
    o << "run.dt = " << h << " s is too large for the damping: sum c = " << c
      << " N s/m (dampers + friction damping) on m = " << s.plant.mass
      << " kg needs dt < 2 m / sum c = " << lim_c << " s.";
  else if (h >= lim_k)
    o << "run.dt = " << h << " s is too large for the stiffest element: it needs dt < " << lim_k
      << " s = 2 / sqrt(sum k / m) (springs + stuck friction elements).";
  else if (h >= 0.5 * std::min(lim_k, lim_c))
    o << "run.dt = " << h << " s is close to the stability limit (stiffness: dt < " << lim_k
      << " s, damping: dt < " << lim_c << " s); a tenth of the limit is accurate.";
  else
    o << "a parameter is extreme (run.dt = " << h << " s is within the stability limits: "
      << "stiffness dt < " << lim_k << " s, damping dt < " << lim_c << " s).";
  o << " Lower run.dt or soften the stiffest element.";
  return o.str();
}

double friction_storage(const FrictionModel& m, const ModelParams& p) {
  const auto& info = m.info();
  double kmin = std::numeric_limits<double>::infinity();
  if (const auto col = info.column_index("k"); col >= 0)
    for (const auto& row : p.elements) kmin = std::min(kmin, row[static_cast<std::size_t>(col)]);
  if (const auto i = info.scalar_index("sigma0"); i >= 0) kmin = std::min(kmin, p.scalars[i]);
  const double fb = m.break_away();
  return std::isfinite(kmin) && kmin > 0.0 ? fb * fb / (2.0 * kmin) : 0.0;
}

double energy_margin(double budget, double dt, double dt_limit) {
  const double ratio = std::min(dt / dt_limit, 0.99);
  return (4.0 + 4.0 * ratio / (1.0 - ratio)) * budget + 1e-12;
}

std::string energy_growth_message(double t, double e, double e0, double work, double storage) {
  std::ostringstream o;
  o << "simulation diverged at t = " << t << " s: the energy of the mass and springs grew to " << e
    << " J, more than it started with (" << e0 << " J) plus what the drive put in (" << work
    << " J) plus what the friction can store (" << storage << " J) - the integration creates energy. ";
  return o.str();
}

}  // namespace gmslab

#include "core/sim/simulation.hpp"

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
}

namespace {
void check_scenario(const Scenario& s) {
  std::vector<std::string> bad = validate(s.friction, "friction");
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) bad.push_back(what);
  };
  const bool massive = s.drive.kind == Drive::Kind::Force || s.drive.kind == Drive::Kind::Pull;
  need(std::isfinite(s.plant.mass) && s.plant.mass > 0, "plant.mass: must be > 0 kg");
  need(std::isfinite(s.plant.spring) && s.plant.spring >= 0, "plant.spring: must be >= 0 N/m");
  need(std::isfinite(s.plant.damper) && s.plant.damper >= 0, "plant.damper: must be >= 0 N s/m");
  need(std::isfinite(s.run.dt) && s.run.dt > 0 && s.run.dt <= 1.0, "run.dt: must be in (0, 1] s");
  need(std::isfinite(s.run.duration) && s.run.duration > 0 && s.run.duration <= 1e6,
       "run.duration: must be in (0, 1e6] s");
  need(s.run.record_every >= 1, "run.record_every: must be >= 1");
  if (bad.empty() && s.run.duration / s.run.dt > 1e10)
    bad.push_back("run: duration / dt exceeds 1e10 steps; raise dt or shorten the run");
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
  if (!bad.empty()) {
    std::string msg = "invalid scenario '" + s.name + "':";
    for (const auto& b : bad) msg += "\n  " + b;
    throw InputError(msg);
  }
}
}  // namespace

Simulation::Simulation(const Scenario& scenario) : sc_(scenario) {
  check_scenario(sc_);
  model_ = build_model(sc_.friction);
  reset();
}

void Simulation::reset() {
  state_.assign(model_->state_size(), 0.0);
  model_->reset(state_);
  trace_.clear();
  trace_.n_elements = std::min(model_->element_count(), kMaxRecordedElements);
  step_ = 0;
  total_steps_ = static_cast<std::uint64_t>(std::llround(sc_.run.duration / sc_.run.dt));
  until_record_ = static_cast<std::uint64_t>(sc_.run.record_every);
  const std::size_t expected = static_cast<std::size_t>(total_steps_ / until_record_ + 2);
  for (auto* vec : {&trace_.t, &trace_.x, &trace_.v, &trace_.friction, &trace_.applied})
    vec->reserve(expected);
  trace_.element_force.reserve(expected * trace_.n_elements);
  trace_.element_slip.reserve(expected * trace_.n_elements);
  x_ = 0.0;
  v_ = 0.0;
  if (sc_.drive.kind == Drive::Kind::Displacement) x_ = sc_.drive.signal(0.0);
  if (sc_.drive.kind == Drive::Kind::Velocity) v_ = sc_.drive.signal(0.0);
  record(0.0, 0.0);
}

void Simulation::set_friction(const ModelParams& p) {
  auto m = build_model(p);
  const bool same_shape = p.model == sc_.friction.model && m->state_size() == state_.size();
  sc_.friction = p;
  model_ = std::move(m);
  if (!same_shape) {
    state_.assign(model_->state_size(), 0.0);
    model_->reset(state_);
    // Keep the trace's element columns aligned with its samples: earlier samples get zeros.
    trace_.n_elements = std::min(model_->element_count(), kMaxRecordedElements);
    trace_.element_force.assign(trace_.size() * trace_.n_elements, 0.0);
    trace_.element_slip.assign(trace_.size() * trace_.n_elements, 0);
  }
}

void Simulation::set_plant(const Plant& p) {
  Scenario s = sc_;
  s.plant = p;
  check_scenario(s);
  sc_.plant = p;
}

void Simulation::record(double ff, double fapp) {
  trace_.t.push_back(time());
  trace_.x.push_back(x_);
  trace_.v.push_back(v_);
  trace_.friction.push_back(ff);
  trace_.applied.push_back(fapp);
  const std::size_t ne = trace_.n_elements;
  if (ne > 0 && trace_.element_force.size() == (trace_.t.size() - 1) * ne) {
    for (std::size_t i = 0; i < ne; ++i) {
      const auto e = model_->element(state_, i);
      trace_.element_force.push_back(e.force);
      trace_.element_slip.push_back(e.slipping ? 1 : 0);
    }
  }
}

std::size_t Simulation::advance(std::size_t n) {
  switch (sc_.drive.kind) {
    case Drive::Kind::Displacement: return advance_as<Drive::Kind::Displacement>(n);
    case Drive::Kind::Velocity: return advance_as<Drive::Kind::Velocity>(n);
    case Drive::Kind::Force: return advance_as<Drive::Kind::Force>(n);
    case Drive::Kind::Pull: return advance_as<Drive::Kind::Pull>(n);
  }
  return 0;
}

template <Drive::Kind K>
std::size_t Simulation::advance_as(std::size_t n) {
  const double h = sc_.run.dt;
  const Drive& d = sc_.drive;
  const Plant& pl = sc_.plant;
  const double inv_m = 1.0 / pl.mass;
  const auto every = static_cast<std::uint64_t>(sc_.run.record_every);
  std::size_t done = 0;
  for (; done < n && step_ < total_steps_; ++done) {
    const double t = time();
    double ff = 0.0, fapp = 0.0;
    if constexpr (K == Drive::Kind::Displacement) {
      const double x1 = d.signal(t + h);
      const double v = (x1 - x_) / h;
      ff = model_->step(state_, {v, h, 0.0, 0.0});
      fapp = ff;
      x_ = x1;
      v_ = v;
    } else if constexpr (K == Drive::Kind::Velocity) {
      const double v1 = d.signal(t + h);
      const double vm = 0.5 * (d.signal(t) + v1);
      ff = model_->step(state_, {vm, h, 0.0, 0.0});
      fapp = ff;
      x_ += vm * h;
      v_ = v1;
    } else {
      if constexpr (K == Drive::Kind::Force)
        fapp = d.signal(t);
      else
        fapp = d.pull_spring * (d.signal(t) - x_) + d.pull_damper * (d.signal.rate_at(t) - v_);
      const double f_other = fapp - pl.spring * x_ - pl.damper * v_;
      ff = model_->step(state_, {v_, h, f_other, pl.mass});
      v_ += h * (f_other - ff) * inv_m;
      x_ += h * v_;
    }
    ++step_;
    if (!std::isfinite(ff + x_ + v_)) diverged(ff);
    if (--until_record_ == 0 || step_ == total_steps_) {
      record(ff, fapp);
      until_record_ = every;
    }
  }
  return done;
}

void Simulation::diverged(double ff) const {
  std::ostringstream o;
  o << "simulation diverged at t = " << time() << " s (non-finite "
    << (!std::isfinite(ff) ? "friction force" : "state")
    << "). Likely cause: run.dt = " << sc_.run.dt << " s is too large for the stiffest element "
    << "(limit " << stability_limit_dt(sc_) << " s), or a parameter is extreme.";
  throw SimulationError(o.str());
}

void Simulation::run_to_end() {
  while (!finished()) advance(1u << 20);
}

Trace simulate(const Scenario& scenario) {
  Simulation s(scenario);
  s.run_to_end();
  return s.trace();
}

}  // namespace gmslab

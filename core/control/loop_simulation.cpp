#include "core/control/loop_simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "core/friction/stribeck.hpp"

namespace gmslab::control {

const char* to_string(Compensation c) {
  switch (c) {
    case Compensation::None: return "none";
    case Compensation::Coulomb: return "coulomb";
    case Compensation::Gms: return "gms";
  }
  return "?";
}

Compensation compensation_from_string(const std::string& s) {
  if (s == "none") return Compensation::None;
  if (s == "coulomb") return Compensation::Coulomb;
  if (s == "gms") return Compensation::Gms;
  throw InputError("--compensation '" + s + "': expected none, coulomb or gms");
}

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool has_scalar(const ModelParams& p, const char* key) {
  return model_info(p.model).scalar_index(key) >= 0;
}

void scale_column(ModelParams& p, const char* key, double f) {
  const auto c = model_info(p.model).column_index(key);
  if (c < 0) return;
  for (auto& row : p.elements) row[static_cast<std::size_t>(c)] *= f;
}

void check_config(const Scenario& s, const LoopConfig& c) {
  std::vector<std::string> bad;
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) bad.push_back(what);
  };
  need(s.plant.mass > 0.0, "plant.mass must be > 0 kg");
  need(c.C.Kc > 0.0 && c.C.z > 0.0 && c.C.p >= 0.0 && std::isfinite(c.C.Kc + c.C.z + c.C.p),
       "compensator: Kc, z must be finite and > 0, p finite and >= 0 (p = 0: PI)");
  need(c.dt > 0.0 && c.dt <= 0.1, "dt must be in (0, 0.1] s");
  need(c.duration > 0.0 && c.duration / c.dt <= 1e8, "duration must be > 0 s and at most 1e8 steps of dt");
  need(c.record_every >= 1, "record_every must be >= 1");
  need(c.sample_time == 0.0 || (c.sample_time >= c.dt && c.sample_time <= c.duration),
       "sample time T must be 0 (continuous) or in [dt, duration] s");
  need(c.mismatch.force > 0.0 && c.mismatch.stiffness > 0.0 && c.mismatch.velocity > 0.0,
       "mismatch factors must be > 0");
  if (bad.empty()) {
    Scenario f = s;
    f.drive.kind = Drive::Kind::Force;
    // The lead's high-frequency gain Kc acts as one more spring on the mass.
    const double k_lim = stability_limit_dt(f);
    const double k_eq = 4.0 / (k_lim * k_lim) * s.plant.mass + c.C.Kc;
    const double lim = 2.0 / std::sqrt(k_eq / s.plant.mass);
    if (c.dt >= lim) {
      std::ostringstream o;
      o << "dt = " << c.dt << " s is too large for the stiffest mode (stuck friction elements, "
        << "springs and the controller gain Kc = " << c.C.Kc << " N/m): it must be < " << lim << " s";
      bad.push_back(o.str());
    }
  }
  if (!bad.empty()) {
    std::string msg = "closed-loop simulation:";
    for (const auto& b : bad) msg += "\n  " + b;
    throw InputError(msg);
  }
}

// The lead Kc (s + z)/(s + p), continuous (exact over each step) or Tustin at T with hold.
class LeadController {
 public:
  LeadController(const LeadCompensator& c, double h, double T) : c_(c), T_(T) {
    decay_ = std::exp(-c.p * h);
    gain_ = c.p > 0.0 ? (1.0 - decay_) / c.p : h;  // p = 0: the PI's integrator
    if (T > 0.0) {
      const double w = 2.0 / T;
      a_ = -(c.p - w) / (w + c.p);
      b0_ = c.Kc * (w + c.z) / (w + c.p);
      b1_ = c.Kc * (c.z - w) / (w + c.p);
      every_ = std::max<long long>(1, std::llround(T / h));
    }
  }
  double update(long long step, double e) {
    if (T_ == 0.0) {
      const double u = c_.Kc * e + c_.Kc * (c_.z - c_.p) * w_;
      w_ = decay_ * w_ + gain_ * e;
      return u;
    }
    if (step % every_ == 0) {
      u_prev_ = a_ * u_prev_ + b0_ * e + b1_ * e_prev_;
      e_prev_ = e;
    }
    return u_prev_;
  }

 private:
  LeadCompensator c_;
  double T_;
  double decay_ = 0.0, gain_ = 0.0, w_ = 0.0;
  double a_ = 0.0, b0_ = 0.0, b1_ = 0.0, u_prev_ = 0.0, e_prev_ = 0.0;
  long long every_ = 1;
};
}  // namespace

ModelParams feedforward_model(const ModelParams& plant, const Mismatch& m) {
  ModelParams g = plant.model == "gms" ? plant : model_info("gms").defaults();
  if (plant.model != "gms")
    for (const char* key : {"Fs", "Fc", "Vs", "delta", "sigma2"})
      if (has_scalar(plant, key)) g.set_scalar(key, plant.scalar(key));
  g.set_scalar("Fs", g.scalar("Fs") * m.force);
  g.set_scalar("Fc", g.scalar("Fc") * m.force);
  g.set_scalar("Vs", g.scalar("Vs") * m.velocity);
  scale_column(g, "k", m.stiffness);
  scale_column(g, "sigma", m.stiffness);
  return g;
}

double coulomb_feedforward_level(const ModelParams& plant, const Mismatch& m) {
  return (has_scalar(plant, "Fc") ? plant.scalar("Fc") : build_model(plant)->break_away()) * m.force;
}

LoopTrace simulate_loop(const Scenario& s, const LoopConfig& c) {
  check_config(s, c);
  const auto plant_f = build_model(s.friction);
  std::vector<double> st(plant_f->state_size());
  plant_f->reset(st);
  std::unique_ptr<FrictionModel> ff_model;
  std::vector<double> ff_st;
  double fc_hat = 0.0;
  if (c.comp == Compensation::Gms) {
    ff_model = build_model(feedforward_model(s.friction, c.mismatch));
    ff_st.resize(ff_model->state_size());
    ff_model->reset(ff_st);
  } else if (c.comp == Compensation::Coulomb) {
    fc_hat = coulomb_feedforward_level(s.friction, c.mismatch);
  }
  LeadController ctrl(c.C, c.dt, c.sample_time);
  const Plant& pl = s.plant;
  const double h = c.dt;
  const long long steps = std::llround(c.duration / h);
  double x = 0.0, v = 0.0;
  LoopTrace tr;
  auto record = [&](double t, double r, double u, double ff, double f) {
    tr.t.push_back(t), tr.r.push_back(r), tr.x.push_back(x), tr.v.push_back(v);
    tr.u.push_back(u), tr.ff.push_back(ff), tr.friction.push_back(f);
  };
  const std::size_t n_rec = static_cast<std::size_t>(steps / c.record_every + 2);
  for (auto* vec : {&tr.t, &tr.r, &tr.x, &tr.v, &tr.u, &tr.ff, &tr.friction}) vec->reserve(n_rec);
  record(0.0, c.reference(0.0), 0.0, 0.0, 0.0);
  for (long long k = 0; k < steps; ++k) {
    const double t = static_cast<double>(k) * h;
    const double r = c.reference(t);
    const double u = ctrl.update(k, r - x);
    const double v_ref = (c.reference(t + h) - r) / h;  // reference velocity over the step
    double ff = 0.0;
    if (ff_model) ff = ff_model->step(ff_st, {v_ref, h, 0.0, 0.0});
    else if (c.comp == Compensation::Coulomb) ff = fc_hat * sgn(v_ref);
    const double f_other = u + ff - pl.spring * x - pl.damper * v;
    const double f = plant_f->step(st, {v, h, f_other, pl.mass});
    v += h * (f_other - f) / pl.mass;
    x += h * v;
    if (!std::isfinite(x) || !std::isfinite(v) || !std::isfinite(f)) {
      std::ostringstream o;
      o << "closed loop diverged at t = " << t << " s (the loop is unstable or dt is too large)";
      throw SimulationError(o.str());
    }
    if ((k + 1) % c.record_every == 0 || k + 1 == steps) record(t + h, c.reference(t + h), u, ff, f);
  }
  return tr;
}

std::vector<double> tracking_error(const LoopTrace& tr) {
  std::vector<double> e(tr.t.size());
  for (std::size_t i = 0; i < e.size(); ++i) e[i] = tr.r[i] - tr.x[i];
  return e;
}

LoopMetrics loop_metrics(const LoopTrace& tr) {
  LoopMetrics m;
  const std::size_t n = tr.t.size();
  if (n < 5) return m;
  const double t_end = tr.t.back();
  const std::size_t tail0 = static_cast<std::size_t>(0.8 * static_cast<double>(n - 1));
  double se = 0.0, se2 = 0.0, sx = 0.0;
  for (std::size_t i = 0; i < n; ++i) se2 += std::pow(tr.r[i] - tr.x[i], 2);
  m.rms_error = std::sqrt(se2 / static_cast<double>(n));
  for (std::size_t i = tail0; i < n; ++i) {
    const double e = tr.r[i] - tr.x[i];
    se += e;
    sx += tr.x[i];
    m.tail_max_error = std::max(m.tail_max_error, std::abs(e));
  }
  const double nt = static_cast<double>(n - tail0);
  m.steady_state_error = se / nt;
  const double x_final = sx / nt;
  // A step: the reference is constant over the tail (and over the run after t = 0).
  bool constant_tail = true;
  for (std::size_t i = tail0; i < n; ++i) constant_tail &= tr.r[i] == tr.r.back();
  const double r_final = tr.r.back();
  const double step = r_final - tr.x.front();
  if (!constant_tail || step == 0.0) {
    m.overshoot = m.settling_time = kNaN;
    return m;
  }
  double peak = 0.0;
  for (std::size_t i = 0; i < n; ++i) peak = std::max(peak, (tr.x[i] - r_final) / step);
  m.overshoot = 100.0 * peak;
  const double band = 0.02 * std::abs(step);
  m.settling_time = 0.0;
  for (std::size_t i = n; i-- > 0;)
    if (std::abs(tr.x[i] - x_final) > band) {
      m.settling_time = i + 1 < n ? tr.t[i + 1] : kNaN;
      break;
    }
  if (m.settling_time > 0.8 * t_end) m.settling_time = kNaN;
  // Limit cycle in the tail: x oscillating around its mean.
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = tail0; i < n; ++i) lo = std::min(lo, tr.x[i]), hi = std::max(hi, tr.x[i]);
  const double amp = 0.5 * (hi - lo);
  const double mid = 0.5 * (hi + lo);
  std::vector<double> ups;
  bool below = tr.x[tail0] < mid;
  for (std::size_t i = tail0 + 1; i < n; ++i) {
    // Hysteresis of a quarter amplitude keeps noise from counting as crossings.
    if (below && tr.x[i] > mid + 0.25 * amp) ups.push_back(tr.t[i]), below = false;
    else if (!below && tr.x[i] < mid - 0.25 * amp) below = true;
  }
  if (ups.size() >= 3 && amp > 1e-4 * std::abs(step) && amp > 1e-12) {
    m.hunting = true;
    m.cycle_amplitude = amp;
    m.cycle_period = (ups.back() - ups.front()) / static_cast<double>(ups.size() - 1);
  }
  return m;
}

}  // namespace gmslab::control

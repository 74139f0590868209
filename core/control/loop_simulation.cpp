#include "core/control/loop_simulation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <unsupported/Eigen/MatrixFunctions>

#include "core/error.hpp"
#include "core/friction/param_specs.hpp"
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

const char* to_string(FeedforwardSource f) {
  return f == FeedforwardSource::Measured ? "measured" : "reference";
}

std::optional<FeedforwardSource> feedforward_source_from_string(const std::string& s) {
  if (s == "reference") return FeedforwardSource::Reference;
  if (s == "measured") return FeedforwardSource::Measured;
  return std::nullopt;
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

// The config's own problems (what does not depend on the plant).
std::vector<std::string> config_problems(const LoopConfig& c) {
  std::vector<std::string> bad;
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) bad.push_back(what);
  };
  bool comp_ok = c.C.Kc > 0.0 && std::isfinite(c.C.Kc);
  for (int i = 0; i < c.C.sections(); ++i) {
    const Section sec = c.C.section(i);
    comp_ok = comp_ok && sec.z > 0.0 && sec.p >= 0.0 && std::isfinite(sec.z + sec.p);
  }
  need(comp_ok, "compensator: Kc and every zero z_i must be finite and > 0, every pole p_i finite and >= 0 "
                "(p_i = 0: integrator)");
  need(c.dt > 0.0 && c.dt <= 0.1, "dt must be in (0, 0.1] s");
  need(c.duration > 0.0 && c.duration / c.dt <= 1e8, "duration must be > 0 s and at most 1e8 steps of dt");
  need(c.record_every >= 1, "record_every must be >= 1");
  need(c.sample_time == 0.0 || (c.sample_time >= c.dt && c.sample_time <= c.duration),
       "sample time T must be 0 (continuous) or in [dt, duration] s");
  need(c.mismatch.force > 0.0 && c.mismatch.stiffness > 0.0 && c.mismatch.velocity > 0.0,
       "mismatch factors must be > 0");
  return bad;
}

void throw_problems(const std::vector<std::string>& bad) {
  if (bad.empty()) return;
  std::string msg = "closed-loop simulation:";
  for (const auto& b : bad) msg += "\n  " + b;
  throw InputError(msg);
}

std::string dt_problem(double dt, double lim, double Kc) {
  if (dt < lim) return "";
  std::ostringstream o;
  o << "dt = " << dt << " s is too large for the stiffest mode (stuck friction elements, "
    << "springs and the controller gain Kc = " << Kc << " N/m): it must be < " << lim << " s";
  return o.str();
}

void check_config(const Scenario& s, const LoopConfig& c) {
  std::vector<std::string> bad = config_problems(c);
  if (!(s.plant.mass > 0.0)) bad.push_back("plant.mass must be > 0 kg");
  if (bad.empty()) {
    Scenario f = s;
    f.drive.kind = Drive::Kind::Force;
    // The lead's high-frequency gain Kc acts as one more spring on the mass.
    const double k_lim = stability_limit_dt(f);
    const double k_eq = 4.0 / (k_lim * k_lim) * s.plant.mass + c.C.Kc;
    const double lim = 2.0 / std::sqrt(k_eq / s.plant.mass);
    if (auto p = dt_problem(c.dt, lim, c.C.Kc); !p.empty()) bad.push_back(p);
  }
  throw_problems(bad);
}

// The friction compensation's feedforward u_ff [N] for the given friction contacts (each driven by
// the reference velocity, or the measured one: LoopConfig::feedforward_source): none, Coulomb Fc_hat sgn(v_ref) with Fc_hat the sum of the contacts' Fc
// (their break-away without Fc), or each contact's GMS model (feedforward_model) stepped along.
class Feedforward {
 public:
  Feedforward(const std::vector<ModelParams>& frictions, const LoopConfig& c)
      : comp_(c.comp), measured_(c.feedforward_source == FeedforwardSource::Measured) {
    for (const auto& fr : frictions) {
      if (comp_ == Compensation::Gms) {
        models_.push_back(build_model(feedforward_model(fr, c.mismatch)));
        states_.emplace_back(models_.back()->state_size());
        models_.back()->reset(states_.back());
      } else if (comp_ == Compensation::Coulomb) {
        fc_hat_ += coulomb_feedforward_level(fr, c.mismatch);
      }
    }
  }
  // v_ref: the reference velocity over the step; v: the measured one (the source chooses).
  double step(double v_ref, double v, double h) {
    const double vf = measured_ ? v : v_ref;
    if (comp_ == Compensation::Coulomb) return fc_hat_ * sgn(vf);
    double ff = 0.0;
    for (std::size_t j = 0; j < models_.size(); ++j) ff += models_[j]->step(states_[j], {vf, h, 0.0, 0.0});
    return ff;
  }

  std::size_t state_size() const {
    std::size_t n = 0;
    for (const auto& st : states_) n += st.size();
    return n;
  }
  void get(std::vector<double>& z) const {
    for (const auto& st : states_) z.insert(z.end(), st.begin(), st.end());
  }
  std::size_t set(std::span<const double> z, std::size_t o) {
    for (auto& st : states_)
      for (double& v : st) v = z[o++];
    return o;
  }
  // A GMS compensator's element forces are continuous, its slip flags are not; driven by the
  // reference velocity around a constant set point they are constants.
  void mask(std::vector<std::uint8_t>& m) const {
    for (const auto& st : states_)
      for (std::size_t i = 0; i < st.size(); ++i)
        m.push_back(measured_ && 2 * i < st.size() ? 1 : 0);
  }

 private:
  Compensation comp_;
  bool measured_ = false;
  std::vector<std::unique_ptr<FrictionModel>> models_;
  std::vector<std::vector<double>> states_;
  double fc_hat_ = 0.0;
};

// The compensator Kc prod_i (s + z_i)/(s + p_i), continuous (exact over each step, e held) or
// Tustin at T with hold. One section: the state w' = -p w + e, u = Kc e + Kc (z - p) w (exact:
// w <- e^{-ph} w + (1 - e^{-ph})/p e). Two sections in series: the cascade's states
// w1' = -p1 w1 + e, w2' = -p2 w2 + y1, y1 = e + (z1 - p1) w1, u = Kc (y1 + (z2 - p2) w2), advanced
// by the exact zero-order-hold discretisation [Ad Bd] = exp([A B; 0 0] h). Tustin: each section
// y[j] = a y[j-1] + b0 x[j] + b1 x[j-1] (Kc folded into the first), in series.
class LeadController {
 public:
  LeadController(const LeadCompensator& c, double h, double T) : c_(c), T_(T) {
    decay_ = std::exp(-c.p * h);
    gain_ = c.p > 0.0 ? (1.0 - decay_) / c.p : h;  // p = 0: the PI's integrator
    if (c.second && T == 0.0) {
      const double p1 = c.p, p2 = c.second->p;
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      M(0, 0) = -p1;
      M(1, 0) = c.z - p1, M(1, 1) = -p2;
      M(0, 2) = 1.0, M(1, 2) = 1.0;  // B = [1, 1]
      const Eigen::Matrix3d E = (M * h).exp();
      Ad_ = E.topLeftCorner<2, 2>();
      Bd_ = E.topRightCorner<2, 1>();
    }
    if (T > 0.0) {
      const double w = 2.0 / T;
      for (int i = 0; i < c.sections(); ++i) {
        const Section s = c.section(i);
        const double k = i == 0 ? c.Kc : 1.0;
        Tustin t;
        t.a = -(s.p - w) / (w + s.p);
        t.b0 = k * (w + s.z) / (w + s.p);
        t.b1 = k * (s.z - w) / (w + s.p);
        tustin_.push_back(t);
      }
      every_ = std::max<long long>(1, std::llround(T / h));
    }
  }
  double update(long long step, double e) {
    if (T_ == 0.0) {
      if (c_.second) {
        const double y1 = e + (c_.z - c_.p) * x_(0);
        const double u = c_.Kc * (y1 + (c_.second->z - c_.second->p) * x_(1));
        x_ = Ad_ * x_ + Bd_ * e;
        return u;
      }
      const double u = c_.Kc * e + c_.Kc * (c_.z - c_.p) * w_;
      w_ = decay_ * w_ + gain_ * e;
      return u;
    }
    if (step % every_ == 0) {
      double x = e;
      for (Tustin& t : tustin_) {
        t.y = t.a * t.y + t.b0 * x + t.b1 * t.x_prev;
        t.x_prev = x;
        x = t.y;
      }
      u_prev_ = x;
    }
    return u_prev_;
  }
  long long every() const { return T_ > 0.0 ? every_ : 1; }
  void get(std::vector<double>& z) const {
    if (T_ > 0.0) {
      for (const Tustin& t : tustin_) z.push_back(t.y), z.push_back(t.x_prev);
      z.push_back(u_prev_);
    } else if (c_.second) {
      z.push_back(x_(0)), z.push_back(x_(1));
    } else {
      z.push_back(w_);
    }
  }
  std::size_t set(std::span<const double> z, std::size_t o) {
    if (T_ > 0.0) {
      for (Tustin& t : tustin_) t.y = z[o++], t.x_prev = z[o++];
      u_prev_ = z[o++];
    } else if (c_.second) {
      x_(0) = z[o++], x_(1) = z[o++];
    } else {
      w_ = z[o++];
    }
    return o;
  }

 private:
  struct Tustin {
    double a = 0.0, b0 = 0.0, b1 = 0.0, y = 0.0, x_prev = 0.0;
  };
  LeadCompensator c_;
  double T_;
  double decay_ = 0.0, gain_ = 0.0, w_ = 0.0;
  Eigen::Matrix2d Ad_ = Eigen::Matrix2d::Zero();
  Eigen::Vector2d Bd_ = Eigen::Vector2d::Zero(), x_ = Eigen::Vector2d::Zero();
  std::vector<Tustin> tustin_;
  double u_prev_ = 0.0;
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

double assembly_loop_dt_limit(const Assembly& a, std::size_t drive, double Kc) {
  if (drive >= a.drives.size()) throw InputError("loop: drive " + std::to_string(drive) + " is not a drive of the plant");
  Assembly f = a;
  const DrivePart& d = a.drives[drive];
  const double k = d.kind == DrivePart::Kind::Pull ? Kc * d.pull_spring : Kc;
  f.springs.push_back({"controller", d.body, kGround, std::max(0.0, k)});
  return stability_limit_dt(f);
}

struct LoopStepper::Impl {
  Impl(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c, double horizon)
      : cfg(c),
        port(port),
        sim(run_of(s, c, horizon)),
        feedforward(ground_frictions(s.plant), c),
        ctrl(c.C, c.dt, c.sample_time) {
    const DrivePart& d = s.plant.drives[port.drive];
    pull_k = d.kind == DrivePart::Kind::Pull ? d.pull_spring : 0.0;
    body = static_cast<std::size_t>(port.body);
    drive_body = static_cast<std::size_t>(d.body);
    for (std::size_t j = 0; j < s.plant.contacts.size(); ++j) {
      const ContactPart& ct = s.plant.contacts[j];
      if (ct.b == kGround)
        ground.push_back({j, 1.0});
      else if (ct.a == kGround)
        ground.push_back({j, -1.0});
    }
  }
  static AssemblyScenario run_of(const AssemblyScenario& s, const LoopConfig& c, double horizon) {
    AssemblyScenario run = s;
    run.run.dt = c.dt;
    run.run.duration = horizon;
    run.run.record_every = 1 << 20;  // the loop keeps its own trace
    return run;
  }
  // The contacts to ground carry the friction the feedforward cancels.
  static std::vector<ModelParams> ground_frictions(const Assembly& a) {
    std::vector<ModelParams> f;
    for (const ContactPart& ct : a.contacts)
      if (ct.b == kGround || ct.a == kGround) f.push_back(ct.friction);
    return f;
  }
  double output() const { return port.velocity ? sim.velocities()[body] : sim.positions()[body]; }

  LoopConfig cfg;
  AssemblyPort port;
  AssemblySimulation sim;
  Feedforward feedforward;
  LeadController ctrl;
  double pull_k = 0.0;
  std::size_t body = 0, drive_body = 0;
  std::vector<std::pair<std::size_t, double>>
      ground;  // contact index, sign of its force on the body
};

LoopStepper::LoopStepper(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c,
                         double horizon)
    : p_(std::make_unique<Impl>(s, port, c, horizon)) {}
LoopStepper::~LoopStepper() = default;
LoopStepper::LoopStepper(LoopStepper&&) noexcept = default;
LoopStepper& LoopStepper::operator=(LoopStepper&&) noexcept = default;

double LoopStepper::output() const { return p_->output(); }
double LoopStepper::velocity() const { return p_->sim.velocities()[p_->body]; }
double LoopStepper::dt() const { return p_->cfg.dt; }
double LoopStepper::time() const { return static_cast<double>(k_) * p_->cfg.dt; }
double LoopStepper::reference() const { return p_->cfg.reference(time()); }
long long LoopStepper::sample_every() const { return p_->ctrl.every(); }

LoopStepper::Forces LoopStepper::step() {
  Impl& q = *p_;
  const double h = q.cfg.dt;
  const double t = time();
  const double r = q.cfg.reference(t);
  Forces out;
  out.u = q.ctrl.update(k_, r - q.output());
  const double v_ref = (q.cfg.reference(t + h) - r) / h;
  // Measured: the drive's body velocity (the compensation treats the train as rigid, as with
  // v_ref).
  out.ff = q.feedforward.step(v_ref, q.sim.velocities()[q.drive_body], h);
  // A pull drive's input is its point's position: the feedforward force acts through its spring.
  q.sim.set_drive_input(q.port.drive, q.pull_k > 0.0 ? out.u + out.ff / q.pull_k : out.u + out.ff);
  const auto diverged = [&] {
    std::ostringstream o;
    o << "closed loop diverged at t = " << t << " s (the loop is unstable or dt is too large)";
    return SimulationError(o.str());
  };
  std::size_t done = 0;
  try {
    done = q.sim.advance(1);
  } catch (const SimulationError&) {
    throw diverged();
  }
  if (done != 1)
    throw InputError("closed loop: stepped past its horizon of " +
                     specs::num(q.sim.scenario().run.duration) + " s");
  ++k_;
  for (const auto& [j, sign] : q.ground) out.friction += sign * q.sim.contact_force(j);
  if (!std::isfinite(q.output()) || !std::isfinite(out.friction)) throw diverged();
  return out;
}

std::vector<double> LoopStepper::state() const {
  std::vector<double> z;
  state_into(z);
  return z;
}

void LoopStepper::state_into(std::vector<double>& z) const {
  p_->sim.state_into(z);
  p_->ctrl.get(z);
  p_->feedforward.get(z);
}

void LoopStepper::set_state(std::span<const double> z, long long step_index) {
  const std::size_t np = p_->sim.contact_state_offset(p_->sim.scenario().plant.contacts.size());
  if (z.size() != state().size())
    throw InputError("loop state: expected " + std::to_string(state().size()) + " values, got " +
                     std::to_string(z.size()));
  p_->sim.set_state_vector(z.subspan(0, np));
  std::size_t o = p_->ctrl.set(z, np);
  p_->feedforward.set(z, o);
  k_ = step_index;
  p_->sim.set_step(static_cast<std::uint64_t>(std::max(0LL, step_index)));
}

std::vector<std::uint8_t> LoopStepper::continuous_mask() const {
  const AssemblySimulation& sim = p_->sim;
  const auto& contacts = sim.scenario().plant.contacts;
  std::vector<std::uint8_t> m(sim.contact_state_offset(0), 1);
  for (std::size_t j = 0; j < contacts.size(); ++j) {
    // Element models keep each element's force, then its slip flag (GMS, Maxwell-slip, Leuven).
    const FrictionModel& f = sim.contact_model(j);
    const std::size_t n = f.state_size(), ne = f.element_count();
    for (std::size_t i = 0; i < n; ++i) m.push_back(ne > 0 && n == 2 * ne && i >= ne ? 0 : 1);
  }
  std::vector<double> c;
  p_->ctrl.get(c);
  m.insert(m.end(), c.size(), 1);
  p_->feedforward.mask(m);
  return m;
}

std::size_t LoopStepper::output_index() const {
  const std::size_t nb = p_->sim.scenario().plant.bodies.size();
  return p_->port.velocity ? nb + p_->body : p_->body;
}
std::size_t LoopStepper::velocity_index() const {
  return p_->sim.scenario().plant.bodies.size() + p_->body;
}

namespace {
// The one-body loop's plant: the scenario's one-body assembly, the controller acting through a
// force drive "drive", output x.mass.
std::pair<AssemblyScenario, AssemblyPort> one_body_loop_plant(const Scenario& s) {
  Scenario plant = s;
  plant.drive = Drive{};
  AssemblyPort port;
  port.drive_name = "drive";
  port.output = "x.mass";
  return {assembly_from_scenario(plant), port};
}

void check_assembly_loop(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c) {
  std::vector<std::string> bad = config_problems(c);
  const Assembly& a = s.plant;
  if (port.drive >= a.drives.size() || port.body < 0 || static_cast<std::size_t>(port.body) >= a.bodies.size())
    bad.push_back("drive / output: not a drive and a body of the plant");
  if (bad.empty()) {
    const DrivePart& d = a.drives[port.drive];
    if (d.kind != DrivePart::Kind::Force && d.kind != DrivePart::Kind::Pull)
      bad.push_back("drive '" + d.name + "': the controller acts through a force or pull drive");
    else if (auto p = dt_problem(c.dt, assembly_loop_dt_limit(a, port.drive, c.C.Kc), c.C.Kc); !p.empty())
      bad.push_back(p);
  }
  throw_problems(bad);
}

LoopTrace run_loop(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c) {
  LoopStepper loop(s, port, c, c.duration);
  const long long steps = std::llround(c.duration / c.dt);
  LoopTrace tr;
  auto record = [&](double t, const LoopStepper::Forces& f) {
    tr.t.push_back(t), tr.r.push_back(c.reference(t)), tr.x.push_back(loop.output()),
        tr.v.push_back(loop.velocity());
    tr.u.push_back(f.u), tr.ff.push_back(f.ff), tr.friction.push_back(f.friction);
  };
  const std::size_t n_rec = static_cast<std::size_t>(steps / c.record_every + 2);
  for (auto* vec : {&tr.t, &tr.r, &tr.x, &tr.v, &tr.u, &tr.ff, &tr.friction}) vec->reserve(n_rec);
  record(0.0, {});
  for (long long k = 0; k < steps; ++k) {
    const LoopStepper::Forces f = loop.step();
    if ((k + 1) % c.record_every == 0 || k + 1 == steps)
      record(static_cast<double>(k) * c.dt + c.dt, f);
  }
  return tr;
}
}  // namespace

LoopTrace simulate_loop(const Scenario& s, const LoopConfig& c) {
  check_config(s, c);
  const auto [a, port] = one_body_loop_plant(s);
  return run_loop(a, port, c);
}

LoopTrace simulate_loop(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c) {
  check_assembly_loop(s, port, c);
  return run_loop(s, port, c);
}

LoopStepper loop_stepper(const Scenario& s, const LoopConfig& c, double horizon) {
  check_config(s, c);
  const auto [a, port] = one_body_loop_plant(s);
  return LoopStepper(a, port, c, horizon);
}

LoopStepper loop_stepper(const AssemblyScenario& s, const AssemblyPort& port, const LoopConfig& c,
                         double horizon) {
  check_assembly_loop(s, port, c);
  return LoopStepper(s, port, c, horizon);
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

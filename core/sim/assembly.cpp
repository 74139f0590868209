#include "core/sim/assembly.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/friction/gms.hpp"

namespace gmslab {

const char* to_string(DrivePart::Kind k) {
  switch (k) {
    case DrivePart::Kind::Force: return "force";
    case DrivePart::Kind::Displacement: return "displacement";
    case DrivePart::Kind::Velocity: return "velocity";
    case DrivePart::Kind::Pull: return "pull";
  }
  return "?";
}

namespace {
bool prescribes(DrivePart::Kind k) { return k == DrivePart::Kind::Displacement || k == DrivePart::Kind::Velocity; }

std::vector<std::uint8_t> prescribed_bodies(const Assembly& a) {
  std::vector<std::uint8_t> p(a.bodies.size(), 0);
  for (const auto& d : a.drives)
    if (prescribes(d.kind) && d.body >= 0 && static_cast<std::size_t>(d.body) < p.size()) p[d.body] = 1;
  return p;
}
}  // namespace

std::vector<std::string> validate(const Assembly& a, const std::string& where) {
  std::vector<std::string> bad;
  const int nb = static_cast<int>(a.bodies.size());
  if (a.bodies.empty() || a.bodies.size() > kMaxBodies)
    bad.push_back(where + ".bodies: " + std::to_string(a.bodies.size()) + " bodies; a plant has 1 to " +
                  std::to_string(kMaxBodies));
  std::set<std::string> names;
  auto name_ok = [&](const std::string& path, const std::string& name) {
    if (name.empty()) bad.push_back(path + ".name: must not be empty");
    else if (name == "ground") bad.push_back(path + ".name: 'ground' is reserved for the fixed frame");
    else if (!names.insert(name).second) bad.push_back(path + ".name: '" + name + "' is used twice; names must be unique");
  };
  for (int i = 0; i < nb; ++i) {
    const std::string p = where + ".bodies[" + std::to_string(i) + "]";
    name_ok(p, a.bodies[i].name);
    if (!(std::isfinite(a.bodies[i].mass) && a.bodies[i].mass > 0 && a.bodies[i].mass <= 1e9))
      bad.push_back(p + ".mass: " + std::to_string(a.bodies[i].mass) + " kg; must be in (0, 1e9] kg");
  }
  auto ends = [&](const std::string& p, int ia, int ib) {
    bool ok = true;
    if (ia < 0 || ia >= nb) {
      bad.push_back(p + ".a: body index " + std::to_string(ia) + " is not a body of the plant (0.." +
                    std::to_string(nb - 1) + ")");
      ok = false;
    }
    if (ib != kGround && (ib < 0 || ib >= nb)) {
      bad.push_back(p + ".b: body index " + std::to_string(ib) + " is not a body of the plant (0.." +
                    std::to_string(nb - 1) + " or ground)");
      ok = false;
    }
    if (ok && ia == ib) bad.push_back(p + ": connects body '" + a.bodies[ia].name + "' to itself");
  };
  // Springs and dampers: a name, two ends and one coefficient in [0, 1e12].
  auto links = [&](const auto& parts, const char* key, auto coefficient, const char* field, const char* unit) {
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const std::string p = where + "." + key + "[" + std::to_string(i) + "]";
      name_ok(p, parts[i].name);
      ends(p, parts[i].a, parts[i].b);
      const double c = coefficient(parts[i]);
      if (!(std::isfinite(c) && c >= 0 && c <= 1e12))
        bad.push_back(p + "." + field + ": must be in [0, 1e12] " + unit);
    }
  };
  links(a.springs, "springs", [](const auto& x) { return x.stiffness; }, "stiffness", "N/m");
  links(a.dampers, "dampers", [](const auto& x) { return x.damping; }, "damping", "N s/m");
  for (std::size_t i = 0; i < a.contacts.size(); ++i) {
    const std::string p = where + ".contacts[" + std::to_string(i) + "]";
    name_ok(p, a.contacts[i].name);
    ends(p, a.contacts[i].a, a.contacts[i].b);
    for (auto& m : validate(a.contacts[i].friction, p + ".friction")) bad.push_back(std::move(m));
  }
  std::vector<int> motion(static_cast<std::size_t>(std::max(nb, 0)), -1);
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto& d = a.drives[i];
    const std::string p = where + ".drives[" + std::to_string(i) + "]";
    name_ok(p, d.name);
    if (d.body < 0 || d.body >= nb) {
      bad.push_back(p + ".body: body index " + std::to_string(d.body) + " is not a body of the plant");
      continue;
    }
    if (prescribes(d.kind)) {
      if (motion[d.body] >= 0)
        bad.push_back(p + ": body '" + a.bodies[d.body].name + "' already has its motion prescribed by " +
                      where + ".drives[" + std::to_string(motion[d.body]) + "]");
      motion[d.body] = static_cast<int>(i);
    }
    if (d.kind == DrivePart::Kind::Pull) {
      if (!(std::isfinite(d.pull_spring) && d.pull_spring > 0 && d.pull_spring <= 1e12))
        bad.push_back(p + ".spring: must be in (0, 1e12] N/m");
      if (!(std::isfinite(d.pull_damper) && d.pull_damper >= 0 && d.pull_damper <= 1e12))
        bad.push_back(p + ".damper: must be in [0, 1e12] N s/m");
    }
  }
  if (!bad.empty() || nb == 0) return bad;
  // Groups of connected bodies (springs, dampers, contacts between bodies): each must reach ground
  // (a part to ground) or carry a drive; otherwise it floats undefined.
  std::vector<int> parent(nb);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<std::uint8_t> anchored(nb, 0);
  auto link = [&](int ia, int ib) {
    if (ib == kGround) anchored[ia] = 1;
    else parent[find(ia)] = find(ib);
  };
  for (const auto& s : a.springs) link(s.a, s.b);
  for (const auto& s : a.dampers) link(s.a, s.b);
  for (const auto& s : a.contacts) link(s.a, s.b);
  for (const auto& d : a.drives) anchored[d.body] = 1;
  std::vector<std::uint8_t> root_ok(nb, 0);
  for (int i = 0; i < nb; ++i)
    if (anchored[i]) root_ok[find(i)] = 1;
  for (int i = 0; i < nb; ++i)
    if (!root_ok[find(i)])
      bad.push_back(where + ".bodies[" + std::to_string(i) + "]: body '" + a.bodies[i].name +
                    "' is connected neither to ground nor to a drive (directly or through other bodies); "
                    "add a spring, damper or contact to ground, or a drive");
  return bad;
}

AssemblyScenario assembly_from_scenario(const Scenario& s) {
  AssemblyScenario a;
  a.name = s.name;
  a.description = s.description;
  a.run = s.run;
  a.plant.bodies.push_back({"mass", s.plant.mass});
  a.plant.springs.push_back({"spring", 0, kGround, s.plant.spring});
  a.plant.dampers.push_back({"damper", 0, kGround, s.plant.damper});
  a.plant.contacts.push_back({"friction", 0, kGround, s.friction});
  DrivePart d;
  d.name = "drive";
  d.body = 0;
  d.signal = s.drive.signal;
  switch (s.drive.kind) {
    case Drive::Kind::Displacement: d.kind = DrivePart::Kind::Displacement; break;
    case Drive::Kind::Velocity: d.kind = DrivePart::Kind::Velocity; break;
    case Drive::Kind::Force: d.kind = DrivePart::Kind::Force; break;
    case Drive::Kind::Pull:
      d.kind = DrivePart::Kind::Pull;
      d.pull_spring = s.drive.pull_spring;
      d.pull_damper = s.drive.pull_damper;
      break;
  }
  a.plant.drives.push_back(d);
  return a;
}

std::optional<Scenario> one_body_scenario(const AssemblyScenario& a) {
  const Assembly& p = a.plant;
  if (p.bodies.size() != 1 || p.springs.size() != 1 || p.dampers.size() != 1 || p.contacts.size() != 1 ||
      p.drives.size() != 1)
    return std::nullopt;
  const auto& sp = p.springs[0];
  const auto& dp = p.dampers[0];
  const auto& ct = p.contacts[0];
  const auto& dr = p.drives[0];
  if (p.bodies[0].name != "mass" || sp.name != "spring" || dp.name != "damper" || ct.name != "friction" ||
      dr.name != "drive")
    return std::nullopt;
  if (sp.a != 0 || sp.b != kGround || dp.a != 0 || dp.b != kGround || ct.a != 0 || ct.b != kGround || dr.body != 0 ||
      dr.point_velocity)
    return std::nullopt;
  Scenario s;
  s.name = a.name;
  s.description = a.description;
  s.run = a.run;
  s.friction = ct.friction;
  s.plant = {p.bodies[0].mass, sp.stiffness, dp.damping};
  s.drive.signal = dr.signal;
  switch (dr.kind) {
    case DrivePart::Kind::Displacement: s.drive.kind = Drive::Kind::Displacement; break;
    case DrivePart::Kind::Velocity: s.drive.kind = Drive::Kind::Velocity; break;
    case DrivePart::Kind::Force: s.drive.kind = Drive::Kind::Force; break;
    case DrivePart::Kind::Pull:
      s.drive.kind = Drive::Kind::Pull;
      s.drive.pull_spring = dr.pull_spring;
      s.drive.pull_damper = dr.pull_damper;
      break;
  }
  if (s.drive.kind != Drive::Kind::Pull && (dr.pull_spring != 0.0 || dr.pull_damper != 0.0)) return std::nullopt;
  return s;
}

double stuck_stiffness(const ModelParams& p) {
  double k = 0.0;
  const auto& info = model_info(p.model);
  if (const auto c = info.column_index("k"); c >= 0)
    for (const auto& row : p.elements) k += row[static_cast<std::size_t>(c)];
  if (const auto i = info.scalar_index("sigma0"); i >= 0) k += p.scalars[static_cast<std::size_t>(i)];
  return k;
}

double contact_damping(const ModelParams& p) {
  double c = 0.0;
  const auto& info = model_info(p.model);
  for (const char* key : {"sigma1", "sigma2"})
    if (const auto i = info.scalar_index(key); i >= 0) c += p.scalars[static_cast<std::size_t>(i)];
  if (const auto col = info.column_index("sigma"); col >= 0)
    for (const auto& row : p.elements) c += row[static_cast<std::size_t>(col)];
  return c;
}

std::vector<double> modal_frequencies(const Assembly& a, bool contacts_stuck) {
  const auto pres = prescribed_bodies(a);
  std::vector<int> dof(a.bodies.size(), -1);
  int n = 0;
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (!pres[i]) dof[i] = n++;
  if (n == 0) return {};
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd m(n);
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (dof[i] >= 0) m(dof[i]) = a.bodies[i].mass;
  auto add = [&](int ia, int ib, double k) {
    const int da = ia >= 0 ? dof[ia] : -1, db = ib >= 0 ? dof[ib] : -1;
    if (da >= 0) K(da, da) += k;
    if (db >= 0) K(db, db) += k;
    if (da >= 0 && db >= 0) {
      K(da, db) -= k;
      K(db, da) -= k;
    }
  };
  for (const auto& s : a.springs) add(s.a, s.b, s.stiffness);
  if (contacts_stuck)
    for (const auto& c : a.contacts) add(c.a, c.b, stuck_stiffness(c.friction));
  for (const auto& d : a.drives)
    if (d.kind == DrivePart::Kind::Pull) add(d.body, kGround, d.pull_spring);
  // Symmetric form M^-1/2 K M^-1/2: same eigenvalues, self-adjoint solver.
  const Eigen::VectorXd s = m.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd A = s.asDiagonal() * K * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A, Eigen::EigenvaluesOnly);
  std::vector<double> w(n);
  for (int i = 0; i < n; ++i) w[i] = std::sqrt(std::max(0.0, es.eigenvalues()(i)));
  return w;
}

double stability_limit_dt(const Assembly& a) {
  const auto w = modal_frequencies(a, true);
  if (w.empty() || !(w.back() > 0.0)) return std::numeric_limits<double>::infinity();
  return 2.0 / w.back();
}

std::vector<Channel> output_channels(const Assembly& a) {
  std::vector<Channel> ch;
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    ch.push_back({Channel::Kind::Position, static_cast<int>(i), "x." + a.bodies[i].name, "m"});
    ch.push_back({Channel::Kind::Velocity, static_cast<int>(i), "v." + a.bodies[i].name, "m/s"});
  }
  for (std::size_t i = 0; i < a.contacts.size(); ++i)
    ch.push_back({Channel::Kind::ContactForce, static_cast<int>(i), "F." + a.contacts[i].name, "N"});
  for (std::size_t i = 0; i < a.springs.size(); ++i)
    ch.push_back({Channel::Kind::SpringForce, static_cast<int>(i), "F." + a.springs[i].name, "N"});
  for (std::size_t i = 0; i < a.dampers.size(); ++i)
    ch.push_back({Channel::Kind::DamperForce, static_cast<int>(i), "F." + a.dampers[i].name, "N"});
  for (std::size_t i = 0; i < a.drives.size(); ++i)
    ch.push_back({Channel::Kind::DriveForce, static_cast<int>(i), "F." + a.drives[i].name, "N"});
  return ch;
}

std::ptrdiff_t AssemblyTrace::channel(const std::string& name) const {
  for (std::size_t c = 0; c < channels.size(); ++c)
    if (channels[c].name == name) return static_cast<std::ptrdiff_t>(c);
  return -1;
}

std::vector<double> AssemblyTrace::series(const std::string& name) const {
  const auto c = channel(name);
  if (c < 0) {
    std::string known;
    for (const auto& ch : channels) known += (known.empty() ? "" : ", ") + ch.name;
    throw InputError("output '" + name + "': no such output (available: " + known + ")");
  }
  std::vector<double> y(size());
  for (std::size_t k = 0; k < size(); ++k) y[k] = at(k, static_cast<std::size_t>(c));
  return y;
}

namespace {
void check(const AssemblyScenario& s) {
  std::vector<std::string> bad = validate(s.plant, "plant");
  const auto& r = s.run;
  append_run_problems(r, bad);
  if (bad.empty()) {
    const double lim = stability_limit_dt(s.plant);
    if (r.dt >= lim) {
      std::ostringstream o;
      o << "run.dt: " << r.dt << " s is too large for the stiffest mode of this plant (contacts stuck, "
        << "w_max = " << 2.0 / lim << " rad/s): it must be < 2 / w_max = " << lim
        << " s; about a tenth of that is accurate";
      bad.push_back(o.str());
    }
  }
  throw_if_invalid(s.name, bad);
}
}  // namespace

AssemblySimulation::AssemblySimulation(const AssemblyScenario& s, TraceOptions trace)
    : AssemblySimulation(s, trace, false) {}

AssemblySimulation::AssemblySimulation(const AssemblyScenario& s, TraceOptions trace, bool one_body_layout)
    : sc_(s), trace_opts_(trace) {
  check(sc_);
  as_scenario_ = one_body_scenario(sc_);
  body_layout_ = one_body_layout && as_scenario_;
  body_prescribed_ = body_layout_ && (as_scenario_->drive.kind == Drive::Kind::Displacement ||
                                      as_scenario_->drive.kind == Drive::Kind::Velocity);
  for (const auto& c : sc_.plant.contacts) models_.push_back(build_model(c.friction));
  channels_ = output_channels(sc_.plant);
  reset();
}

void AssemblySimulation::compile() {
  const Assembly& a = sc_.plant;
  const std::size_t nb = a.bodies.size();
  h_over_m_.assign(nb + 1, 0.0);
  for (std::size_t i = 0; i < nb; ++i) h_over_m_[i] = sc_.run.dt / a.bodies[i].mass;
  prescribed_ = prescribed_bodies(a);
  prescribed_.push_back(1);  // ground
  const int g = static_cast<int>(nb);
  auto slot = [g](int i) { return i < 0 ? g : i; };
  springs_c_.clear();
  dampers_c_.clear();
  contacts_c_.clear();
  for (const auto& s : a.springs) springs_c_.push_back({s.a, slot(s.b), s.stiffness});
  for (const auto& s : a.dampers) dampers_c_.push_back({s.a, slot(s.b), s.damping});
  for (const auto& c : a.contacts) {
    CompiledContact cc{c.a, slot(c.b), 0, 0.0, 0.0, 0.0};
    const bool fa = !prescribed_[cc.a], fb = !prescribed_[cc.b];
    cc.mode = (fa ? 1 : 0) | (fb ? 2 : 0);
    if (fa) cc.ma = a.bodies[cc.a].mass;
    if (fb) cc.mb = a.bodies[cc.b].mass;
    cc.m_eff = cc.mode == 3 ? cc.ma * cc.mb / (cc.ma + cc.mb) : cc.mode == 1 ? cc.ma : cc.mode == 2 ? cc.mb : 0.0;
    contacts_c_.push_back(cc);
  }
  has_prescribed_ = false;
  for (const auto& d : a.drives) has_prescribed_ = has_prescribed_ || prescribes(d.kind);
  one_body_ = nb == 1 && !has_prescribed_;
  simple_ = -1;
  const bool single = a.springs.size() <= 1 && a.dampers.size() <= 1 && a.contacts.size() <= 1;
  if (one_body_ && a.drives.size() <= 1 && single) {
    if (a.drives.empty())
      simple_ = 0;
    else if (a.drives[0].kind == DrivePart::Kind::Force)
      simple_ = 1;
    else if (a.drives[0].kind == DrivePart::Kind::Pull && !a.drives[0].point_velocity)
      simple_ = 2;
  }
  if (nb == 1 && has_prescribed_ && a.drives.size() == 1 && single)
    simple_ = a.drives[0].kind == DrivePart::Kind::Displacement ? 3 : 4;
  simple_gms_ = simple_ >= 0 && models_.size() == 1 &&
                dynamic_cast<const GmsModel*>(models_[0].get()) &&
                models_[0]->element_count() <= GmsModel::kScalarElements;
}

void AssemblySimulation::set_history_limit() {
  max_samples_ = 0;
  if (trace_opts_.max_bytes == 0) return;
  if (body_layout_)  // at least 64 samples: a bucket keeps at most 10
    max_samples_ = std::max<std::size_t>(
        64, trace_opts_.max_bytes / trace_sample_bytes(body_trace_.n_elements));
  else  // room for a few buckets of 2 + 2 channels samples
    max_samples_ = std::max<std::size_t>(
        {64, 8 * (2 + 2 * channels_.size()), trace_opts_.max_bytes / trace_.sample_bytes()});
}

void AssemblySimulation::reset() {
  const std::size_t nb = sc_.plant.bodies.size();
  // One extra slot for ground (index nb): x = v = 0, its force is discarded.
  x_.assign(nb + 1, 0.0);
  v_.assign(nb + 1, 0.0);
  cv_.assign(nb + 1, 0.0);
  f_.assign(nb + 1, 0.0);
  compile();
  xp_.assign(sc_.plant.drives.size(), 0.0);
  input_.resize(sc_.plant.drives.size(), 0.0);  // inputs set before a reset stay set
  has_input_.resize(sc_.plant.drives.size(), 0);
  drive_rate_.assign(sc_.plant.drives.size(), 0.0);
  for (std::size_t i = 0; i < sc_.plant.drives.size(); ++i) {
    const auto& d = sc_.plant.drives[i];
    if (d.kind == DrivePart::Kind::Displacement) x_[d.body] = d.signal(0.0);
    if (d.kind == DrivePart::Kind::Velocity) v_[d.body] = d.signal(0.0);
  }
  state_.clear();
  for (const auto& m : models_) {
    state_.emplace_back(m->state_size(), 0.0);
    m->reset(state_.back());
  }
  f_contact_.assign(models_.size(), 0.0);
  v_rel_.assign(models_.size(), 0.0);
  f_spring_.assign(sc_.plant.springs.size(), 0.0);
  f_damper_.assign(sc_.plant.dampers.size(), 0.0);
  f_drive_.assign(sc_.plant.drives.size(), 0.0);
  // Spring and damper forces at the start (the contacts and drives start at rest).
  for (std::size_t i = 0; i < sc_.plant.springs.size(); ++i) {
    const auto& s = sc_.plant.springs[i];
    f_spring_[i] = s.stiffness * (x_[s.a] - (s.b < 0 ? 0.0 : x_[s.b]));
  }
  trace_ = {};
  trace_.channels = channels_;
  for (const auto& m : models_) trace_.n_elements.push_back(std::min(m->element_count(), kMaxRecordedElements));
  trace_.element_force.resize(models_.size());
  trace_.element_slip.resize(models_.size());
  trace_.contact_slip.resize(models_.size());
  body_trace_.clear();
  if (body_layout_) body_trace_.n_elements = trace_.n_elements[0];
  step_ = 0;
  total_steps_ = static_cast<std::uint64_t>(std::llround(sc_.run.duration / sc_.run.dt));
  until_record_ = static_cast<std::uint64_t>(sc_.run.record_every);
  set_history_limit();
  bucket_steps_ = 0;
  // Reserved: the run's samples, at most the options' and the bound's count (4 Mi samples for the
  // assembled trace: more grows as it comes).
  std::size_t expected = static_cast<std::size_t>(total_steps_ / until_record_ + 2);
  expected = std::min(expected, trace_opts_.reserve_samples);
  if (max_samples_ > 0) expected = std::min(expected, max_samples_);
  if (body_layout_) {
    for (auto* vec : {&body_trace_.t, &body_trace_.x, &body_trace_.v, &body_trace_.friction, &body_trace_.applied})
      vec->reserve(expected);
    body_trace_.element_force.reserve(expected * body_trace_.n_elements);
    body_trace_.element_slip.reserve(expected * body_trace_.n_elements);
  } else {
    expected = std::min<std::size_t>(expected, std::size_t{1} << 22);
    trace_.t.reserve(expected);
    trace_.values.reserve(expected * channels_.size());
    for (std::size_t j = 0; j < models_.size(); ++j) {
      trace_.element_force[j].reserve(expected * trace_.n_elements[j]);
      trace_.element_slip[j].reserve(expected * trace_.n_elements[j]);
      trace_.contact_slip[j].reserve(expected);
    }
  }
  // Where each channel's value lives (the output arrays keep their storage until the next reset).
  channel_src_.clear();
  for (const auto& c : channels_) {
    const double* src = nullptr;
    switch (c.kind) {
      case Channel::Kind::Position: src = &x_[c.index]; break;
      case Channel::Kind::Velocity: src = &v_[c.index]; break;
      case Channel::Kind::ContactForce: src = &f_contact_[c.index]; break;
      case Channel::Kind::SpringForce: src = &f_spring_[c.index]; break;
      case Channel::Kind::DamperForce: src = &f_damper_[c.index]; break;
      case Channel::Kind::DriveForce: src = &f_drive_[c.index]; break;
    }
    channel_src_.push_back(src);
  }
  rebase_energy();
  record();
}

namespace {
// "" when b has a's structure (bodies, part names and ends, drive kinds and bodies), else what
// differs.
std::string structure_change(const Assembly& a, const Assembly& b) {
  auto count = [](const char* key, std::size_t n, std::size_t m) {
    return n == m ? std::string()
                  : std::string("plant.") + key + ": " + std::to_string(m) + " instead of " +
                        std::to_string(n);
  };
  for (const std::string& c : {count("bodies", a.bodies.size(), b.bodies.size()),
                               count("springs", a.springs.size(), b.springs.size()),
                               count("dampers", a.dampers.size(), b.dampers.size()),
                               count("contacts", a.contacts.size(), b.contacts.size()),
                               count("drives", a.drives.size(), b.drives.size())})
    if (!c.empty()) return c;
  auto same = [](const auto& x, const auto& y) {
    return x.name == y.name && x.a == y.a && x.b == y.b;
  };
  for (std::size_t i = 0; i < a.bodies.size(); ++i)
    if (a.bodies[i].name != b.bodies[i].name) return "plant.bodies[" + std::to_string(i) + "].name";
  for (std::size_t i = 0; i < a.springs.size(); ++i)
    if (!same(a.springs[i], b.springs[i]))
      return "plant.springs[" + std::to_string(i) + "]: name or ends";
  for (std::size_t i = 0; i < a.dampers.size(); ++i)
    if (!same(a.dampers[i], b.dampers[i]))
      return "plant.dampers[" + std::to_string(i) + "]: name or ends";
  for (std::size_t i = 0; i < a.contacts.size(); ++i)
    if (!same(a.contacts[i], b.contacts[i]))
      return "plant.contacts[" + std::to_string(i) + "]: name or ends";
  for (std::size_t i = 0; i < a.drives.size(); ++i) {
    const auto &x = a.drives[i], &y = b.drives[i];
    if (x.name != y.name || x.kind != y.kind || x.body != y.body ||
        x.point_velocity != y.point_velocity)
      return "plant.drives[" + std::to_string(i) + "]: name, kind, body or point_velocity";
  }
  return {};
}
}  // namespace

void AssemblySimulation::set_plant(const Assembly& a) {
  if (const std::string c = structure_change(sc_.plant, a); !c.empty())
    throw InputError(
        "live edit of '" + sc_.name + "': " + c +
        " - a live edit changes values only; a plant of another structure starts a new run");
  AssemblyScenario next = sc_;
  next.plant = a;
  check(next);
  std::vector<std::unique_ptr<FrictionModel>> models;
  for (const auto& c : a.contacts) models.push_back(build_model(c.friction));
  // Validated: nothing below throws.
  for (std::size_t j = 0; j < models.size(); ++j) {
    const bool keep = a.contacts[j].friction.model == sc_.plant.contacts[j].friction.model &&
                      models[j]->state_size() == state_[j].size();
    models_[j] = std::move(models[j]);
    if (keep) continue;
    state_[j].assign(models_[j]->state_size(), 0.0);
    models_[j]->reset(state_[j]);
    relay_elements(j);
  }
  sc_.plant = a;
  as_scenario_ = one_body_scenario(sc_);
  compile();
  set_history_limit();
  rebase_energy();
  if (max_samples_ > 0 && (body_layout_ ? body_trace_.size() : trace_.size()) >= max_samples_)
    compact_trace();
}

void AssemblySimulation::relay_elements(std::size_t j) {
  // Earlier samples get zeros in the new element columns, so every column stays one per sample.
  const std::size_t ne = std::min(models_[j]->element_count(), kMaxRecordedElements);
  trace_.n_elements[j] = ne;
  trace_.element_force[j].assign(trace_.size() * ne, 0.0);
  trace_.element_slip[j].assign(trace_.size() * ne, 0);
  if (body_layout_ && j == 0) {
    body_trace_.n_elements = ne;
    body_trace_.element_force.assign(body_trace_.size() * ne, 0.0);
    body_trace_.element_slip.assign(body_trace_.size() * ne, 0);
    ++body_trace_.revision;
  }
}

void AssemblySimulation::set_friction(const ModelParams& p, std::size_t contact) {
  if (contact >= sc_.plant.contacts.size())
    throw InputError("live edit: contact " + std::to_string(contact) +
                     " is not a contact of the plant");
  if (as_scenario_) {
    Scenario s = *as_scenario_;
    s.friction = p;
    check_scenario(s);
  }
  Assembly a = sc_.plant;
  a.contacts[contact].friction = p;
  set_plant(a);
}

void AssemblySimulation::set_plant(const Plant& p) {
  if (!as_scenario_)
    throw InputError("live edit of '" + sc_.name +
                     "': not a one-body plant (mass, spring, damper)");
  Scenario s = *as_scenario_;
  s.plant = p;
  check_scenario(s);
  set_plant(assembly_from_scenario(s).plant);
}

void AssemblySimulation::record_one_body() {
  Trace& tr = body_trace_;
  tr.t.push_back(time());
  tr.x.push_back(x_[0]);
  tr.v.push_back(v_[0]);
  tr.friction.push_back(f_contact_[0]);
  tr.applied.push_back(body_prescribed_ ? f_contact_[0] : f_drive_[0]);
  for (std::size_t i = 0; i < tr.n_elements; ++i) {
    const auto e = models_[0]->element(state_[0], i);
    tr.element_force.push_back(e.force);
    tr.element_slip.push_back(e.slipping ? 1 : 0);
  }
  if (max_samples_ > 0 && tr.size() >= max_samples_) compact_trace();
}

void AssemblySimulation::record() {
  if (body_layout_) return record_one_body();
  trace_.t.push_back(time());
  const std::size_t nc = channel_src_.size(), at = trace_.values.size();
  trace_.values.resize(at + nc);
  double* out = trace_.values.data() + at;
  for (std::size_t c = 0; c < nc; ++c) out[c] = *channel_src_[c];
  for (std::size_t j = 0; j < models_.size(); ++j) {
    const std::size_t ne = trace_.n_elements[j];
    bool all_slip = ne > 0;
    for (std::size_t i = 0; i < ne; ++i) {
      const auto e = models_[j]->element(state_[j], i);
      trace_.element_force[j].push_back(e.force);
      trace_.element_slip[j].push_back(e.slipping ? 1 : 0);
      all_slip = all_slip && e.slipping;
    }
    trace_.contact_slip[j].push_back(std::abs(v_rel_[j]) > kSlipVelocity || all_slip ? 1 : 0);
  }
  if (max_samples_ > 0 && trace_.size() >= max_samples_) compact_trace();
}

void AssemblySimulation::compact_trace() {
  // The current width first (the samples since the last compaction are raw), then doubled until
  // half the room is free. One bucket keeps at most 2 + 2 nc samples
  // and max_samples_ >= 8 (2 + 2 nc), so this ends.
  const auto every = static_cast<std::uint64_t>(sc_.run.record_every);
  bucket_steps_ = body_layout_ ? compact_to_half(body_trace_, sc_.run.dt, bucket_steps_, every, max_samples_)
                               : compact_to_half(trace_, sc_.run.dt, bucket_steps_, every, max_samples_);
}

std::size_t AssemblyTrace::sample_bytes() const {
  std::size_t b = sizeof(double) * (1 + channels.size());
  for (std::size_t ne : n_elements) b += ne * (sizeof(double) + 1) + 1;
  return b;
}

void AssemblyTrace::clear() {
  t.clear();
  values.clear();
  for (auto& v : element_force) v.clear();
  for (auto& v : element_slip) v.clear();
  for (auto& v : contact_slip) v.clear();
}

void compact_minmax(AssemblyTrace& tr, double dt, std::uint64_t bucket_steps) {
  const std::size_t n = tr.size(), nc = tr.channels.size();
  auto bucket = [&](std::size_t k) { return static_cast<std::uint64_t>(std::llround(tr.t[k] / dt)) / bucket_steps; };
  std::vector<std::size_t> keep;
  keep.reserve(2 + 2 * nc);
  std::size_t out = 0;
  auto move_sample = [&](std::size_t from, std::size_t to) {
    tr.t[to] = tr.t[from];
    for (std::size_t c = 0; c < nc; ++c) tr.values[to * nc + c] = tr.values[from * nc + c];
    for (std::size_t j = 0; j < tr.n_elements.size(); ++j) {
      const std::size_t ne = tr.n_elements[j];
      for (std::size_t i = 0; i < ne; ++i) {
        tr.element_force[j][to * ne + i] = tr.element_force[j][from * ne + i];
        tr.element_slip[j][to * ne + i] = tr.element_slip[j][from * ne + i];
      }
      tr.contact_slip[j][to] = tr.contact_slip[j][from];
    }
  };
  for (std::size_t i = 0; i < n;) {
    const std::uint64_t b = bucket(i);
    std::size_t j = i + 1;
    while (j < n && bucket(j) == b) ++j;
    keep.clear();
    keep.push_back(i);
    keep.push_back(j - 1);
    for (std::size_t c = 0; c < nc; ++c) {
      std::size_t lo = i, hi = i;
      for (std::size_t k = i + 1; k < j; ++k) {
        const double y = tr.values[k * nc + c];
        if (y < tr.values[lo * nc + c]) lo = k;
        if (y > tr.values[hi * nc + c]) hi = k;
      }
      keep.push_back(lo);
      keep.push_back(hi);
    }
    std::sort(keep.begin(), keep.end());
    keep.erase(std::unique(keep.begin(), keep.end()), keep.end());
    for (std::size_t k : keep) move_sample(k, out++);  // out <= k: moves only backwards
    i = j;
  }
  tr.t.resize(out);
  tr.values.resize(out * nc);
  for (std::size_t j = 0; j < tr.n_elements.size(); ++j) {
    tr.element_force[j].resize(out * tr.n_elements[j]);
    tr.element_slip[j].resize(out * tr.n_elements[j]);
    tr.contact_slip[j].resize(out);
  }
}

std::vector<double> AssemblySimulation::state_vector() const {
  std::vector<double> z;
  state_into(z);
  return z;
}

void AssemblySimulation::state_into(std::vector<double>& z) const {
  const std::size_t nb = sc_.plant.bodies.size();
  z.clear();
  z.insert(z.end(), x_.begin(), x_.begin() + static_cast<std::ptrdiff_t>(nb));
  z.insert(z.end(), v_.begin(), v_.begin() + static_cast<std::ptrdiff_t>(nb));
  z.insert(z.end(), xp_.begin(), xp_.end());
  for (const auto& st : state_) z.insert(z.end(), st.begin(), st.end());
}

std::size_t AssemblySimulation::contact_state_offset(std::size_t j) const {
  std::size_t o = 2 * sc_.plant.bodies.size() + xp_.size();
  for (std::size_t i = 0; i < j && i < state_.size(); ++i) o += state_[i].size();
  return o;
}

void AssemblySimulation::set_state_vector(std::span<const double> z) {
  const std::size_t nb = sc_.plant.bodies.size();
  if (z.size() != contact_state_offset(state_.size()))
    throw InputError("assembly state: expected " +
                     std::to_string(contact_state_offset(state_.size())) + " values, got " +
                     std::to_string(z.size()));
  std::size_t o = 0;
  for (std::size_t i = 0; i < nb; ++i) x_[i] = z[o++];
  for (std::size_t i = 0; i < nb; ++i) v_[i] = z[o++];
  for (double& xp : xp_) xp = z[o++];
  for (auto& st : state_)
    for (double& s : st) s = z[o++];
}

void AssemblySimulation::set_drive_input(std::size_t i, double u) {
  if (i >= sc_.plant.drives.size() || (sc_.plant.drives[i].kind != DrivePart::Kind::Force &&
                                       sc_.plant.drives[i].kind != DrivePart::Kind::Pull))
    throw InputError("drive input: drive " + std::to_string(i) + " is not a force or pull drive of the plant");
  input_[i] = u;
  has_input_[i] = 1;
  any_input_ = true;
  watch_ = false;  // a controller's input is no passive drive
}

double AssemblySimulation::drive_force(std::size_t i, double t, double h, double x, double v) {
  const auto& d = sc_.plant.drives[i];
  if (any_input_ && has_input_[i]) {
    if (d.kind == DrivePart::Kind::Force) return input_[i];
    const double rate = (input_[i] - xp_[i]) / h;  // the point's velocity over the step
    xp_[i] = input_[i];
    return d.pull_spring * (input_[i] - x) + d.pull_damper * (rate - v);
  }
  if (d.kind == DrivePart::Kind::Force) return d.signal(t);
  double xp, rate;  // pull: the drive point's position and rate
  if (d.point_velocity) {
    xp = xp_[i];
    rate = d.signal(t);
    xp_[i] += 0.5 * h * (rate + d.signal(t + h));
  } else {
    xp = d.signal(t);
    rate = d.signal.rate_at(t);
  }
  drive_rate_[i] = rate;
  return d.pull_spring * (xp - x) + d.pull_damper * (rate - v);
}

std::size_t AssemblySimulation::advance_one_body(std::size_t n) {
  const double h = sc_.run.dt;
  const Assembly& p = sc_.plant;
  const auto every = static_cast<std::uint64_t>(sc_.run.record_every);
  const double hm = h_over_m_[0];
  const double m = contacts_c_.empty() ? 0.0 : contacts_c_[0].m_eff;
  double x = x_[0], v = v_[0];
  std::size_t done = 0;
  for (; done < n && step_ < total_steps_; ++done) {
    const double t = time();
    double f = 0.0;
    for (std::size_t i = 0; i < p.drives.size(); ++i) {
      const double fd = drive_force(i, t, h, x, v);  // force or pull (one free body: nothing prescribed)
      f_drive_[i] = fd;
      f += fd;
    }
    for (std::size_t i = 0; i < springs_c_.size(); ++i) {
      const double fs = springs_c_[i].c * (x - 0.0);
      f_spring_[i] = fs;
      f -= fs;
    }
    for (std::size_t i = 0; i < dampers_c_.size(); ++i) {
      const double fd = dampers_c_[i].c * (v - 0.0);
      f_damper_[i] = fd;
      f -= fd;
    }
    for (std::size_t j = 0; j < contacts_c_.size(); ++j) {
      const double F = models_[j]->step(state_[j], {v, h, f, m});
      f_contact_[j] = F;
      v_rel_[j] = v;
      f -= F;
    }
    v += f * hm;
    x += h * v;
    ++step_;
    if (watch_)  // one free body: every drive acts on it
      for (std::size_t i = 0; i < p.drives.size(); ++i)
        drive_work_ += h * f_drive_[i] * (p.drives[i].kind == DrivePart::Kind::Force ? v : drive_rate_[i]);
    if (!std::isfinite(f + x + v)) {
      x_[0] = x;
      v_[0] = v;
      diverged(!std::isfinite(contacts_c_.empty() ? 0.0 : f_contact_[0]));
    }
    if (watch_ && (step_ & (kEnergyCheckEvery - 1)) == 0) {
      x_[0] = x;
      v_[0] = v;
      check_energy();
    }
    if (--until_record_ == 0 || step_ == total_steps_) {
      x_[0] = x;
      v_[0] = v;
      record();
      until_record_ = every;
    }
  }
  x_[0] = x;
  v_[0] = v;
  return done;
}

template <int K, bool Gms>
std::size_t AssemblySimulation::advance_simple(std::size_t n) {
  // Every v1 preset's plant has its spring, damper and contact (zero or not): that case with the
  // three known at compile time keeps fewer values live in the loop.
  if (springs_c_.size() == 1 && dampers_c_.size() == 1 && contacts_c_.size() == 1) {
    if constexpr (Gms && (K == 1 || K == 2)) {  // a force or pull drive: the element count too
      switch (models_[0]->element_count()) {
        case 1:
          return advance_simple_as<K, Gms, true, 1>(n);
        case 2:
          return advance_simple_as<K, Gms, true, 2>(n);
        case 3:
          return advance_simple_as<K, Gms, true, 3>(n);
        case 4:
          return advance_simple_as<K, Gms, true, 4>(n);
        case 5:
          return advance_simple_as<K, Gms, true, 5>(n);
        case 6:
          return advance_simple_as<K, Gms, true, 6>(n);
        case 7:
          return advance_simple_as<K, Gms, true, 7>(n);
        case 8:
          return advance_simple_as<K, Gms, true, 8>(n);
        default:
          break;
      }
    }
    return advance_simple_as<K, Gms, true, 0>(n);
  }
  return advance_simple_as<K, Gms, false, 0>(n);
}

namespace {
// What the one-body loop (advance_simple_as) keeps constant over a call.
struct SimpleParts {
  double h, k, c, hm, m;  // step, spring, damper, h / m, the contact's mass
  const DrivePart* d;
  const FrictionModel* model;
  const GmsModel* gms;  // the model, when it is a GmsModel stepped inline
  GmsModel::StepConstants gc;
  std::span<double> st;  // the contact's state
  bool has_k, has_c, has_f;
};

// What it carries from step to step: the state, the last step's outputs (drive, spring, damper and
// contact force, the contact's velocity), the drive's work and the counters.
struct SimpleVars {
  double x, v, fdrive, fs, fd, F, vr, work;
  std::uint64_t step, left;
};

// The drive's values of steps step .. step + chunk - 1 (they depend on t alone): K 1: F(t) in a;
// 2: x_p(t) in a and its rate in b; 3: x(t + h) in a; 4: v(t) in a and v(t + h) in b.
template <int K>
[[gnu::always_inline]] inline void drive_values(const DrivePart* d, std::uint64_t step,
                                                std::size_t chunk, double h, double* a, double* b) {
  if constexpr (K == 2) {
    if (d->signal.kind == Signal::Kind::Ramp) {  // Signal's ramp and rate, without the calls
      const double value = d->signal.value, slope = d->signal.slope;
      for (std::size_t i = 0; i < chunk; ++i)
        a[i] = value + slope * (static_cast<double>(step + i) * h), b[i] = slope;
      return;
    }
  }
  for (std::size_t i = 0; i < chunk; ++i) {
    const double t = static_cast<double>(step + i) * h;
    if constexpr (K == 1)
      a[i] = d->signal(t);
    else if constexpr (K == 2)
      a[i] = d->signal(t), b[i] = d->signal.rate_at(t);
    else if constexpr (K == 3)
      a[i] = d->signal(t + h);
    else if constexpr (K == 4)
      a[i] = d->signal(t), b[i] = d->signal(t + h);
  }
}

// The contact's force at velocity v (f, m: the model's input besides v and h).
template <bool Gms, std::size_t N>
[[gnu::always_inline]] inline double contact_force(const SimpleParts& P, double v, double f,
                                                   double m) {
  if constexpr (Gms)
    return P.gms->template step_scalar<N>(P.st.data(), v, P.gc);
  else
    return P.model->step(P.st, {v, P.h, f, m});
}

// One step of the free body (K 0 none, 1 force, 2 pull): advance_one_body's sums in its order, f
// starting at the drive's force (0 + F but for a zero's sign). Returns the net force.
template <int K, bool Gms, bool Full, std::size_t N>
[[gnu::always_inline]] inline double free_step(const SimpleParts& P, double a, double b,
                                               SimpleVars& s) {
  double f = 0.0;
  [[maybe_unused]] double rate = 0.0;  // pull: the drive point's velocity [m/s]
  if constexpr (K == 1) {
    s.fdrive = a;
    f = a;
  } else if constexpr (K == 2) {
    rate = b;
    s.fdrive = P.d->pull_spring * (a - s.x) + P.d->pull_damper * (rate - s.v);
    f = s.fdrive;
  }
  if (Full || P.has_k) {
    s.fs = P.k * (s.x - 0.0);
    f -= s.fs;
  }
  if (Full || P.has_c) {
    s.fd = P.c * (s.v - 0.0);
    f -= s.fd;
  }
  if (Full || P.has_f) {
    s.F = contact_force<Gms, N>(P, s.v, f, P.m);
    s.vr = s.v;
    f -= s.F;
  }
  s.v += f * P.hm;
  s.x += P.h * s.v;
  // The energy watch's account: work of the drive this step (force: F dx; pull: F dx_p) [J].
  if constexpr (K == 1)
    s.work += P.h * s.fdrive * s.v;
  else if constexpr (K == 2)
    s.work += P.h * s.fdrive * rate;
  ++s.step;
  return f;
}

// One step of prescribed motion (K 3 displacement, 4 velocity): compute_step's sums for one body,
// the parts at the step's start, the contact at the velocity over the step, the drive supplying
// what holds the motion. Returns the net force of the parts.
template <int K, bool Gms, bool Full, std::size_t N>
[[gnu::always_inline]] inline double prescribed_step(const SimpleParts& P, double a, double b,
                                                     SimpleVars& s) {
  const double cv = K == 3 ? (a - s.x) / P.h : 0.5 * (a + b);
  double f = 0.0;
  if (Full || P.has_k) {
    s.fs = P.k * (s.x - 0.0);
    f -= s.fs;
  }
  if (Full || P.has_c) {
    s.fd = P.c * (s.v - 0.0);
    f -= s.fd;
  }
  if (Full || P.has_f) {
    s.vr = cv - 0.0;
    s.F = contact_force<Gms, N>(P, s.vr, 0.0, 0.0);
    f -= s.F;
  }
  s.fdrive = -f;
  if constexpr (K == 3) {
    s.x = a;
    s.v = cv;
  } else {
    s.x += cv * P.h;
    s.v = b;
  }
  ++s.step;
  return f;
}

// `quiet` free steps before an event (a sample, an energy check, the chunk's end), with a[i], b[i]
// the drive's values of step i: only x, v, the work and the element states carried from step to
// step (the outputs kept are the last step's). A non-finite step calls stop(s).
template <int K, bool Gms, bool Full, std::size_t N, class Stop>
[[gnu::always_inline]] inline void quiet_steps(const SimpleParts& P, const double* a,
                                               const double* b, std::uint64_t quiet, SimpleVars& s,
                                               Stop&& stop) {
  for (std::uint64_t q = 0; q < quiet; ++q) {
    const double f = free_step<K, Gms, Full, N>(P, a[q], b[q], s);
    if (!std::isfinite(f + s.x + s.v)) [[unlikely]] {
      s.left -= q + 1;
      stop(s);
    }
  }
  s.left -= quiet;
}
}  // namespace

template <int K, bool Gms, bool Full, std::size_t N>
std::size_t AssemblySimulation::advance_simple_as(std::size_t n) {
  const double h = sc_.run.dt;
  const bool has_f = Full || !contacts_c_.empty();
  const FrictionModel* model = has_f ? models_[0].get() : nullptr;
  // A GMS contact of few elements steps inline (GmsModel::step_scalar: step()'s operations).
  const GmsModel* gms = Gms ? static_cast<const GmsModel*>(model) : nullptr;
  const SimpleParts P{h,
                      springs_c_.empty() ? 0.0 : springs_c_[0].c,
                      dampers_c_.empty() ? 0.0 : dampers_c_[0].c,
                      h_over_m_[0],
                      has_f ? contacts_c_[0].m_eff : 0.0,
                      sc_.plant.drives.empty() ? nullptr : &sc_.plant.drives[0],
                      model,
                      gms,
                      Gms ? gms->constants(h) : GmsModel::StepConstants{},
                      has_f ? std::span<double>(state_[0]) : std::span<double>(),
                      Full || !springs_c_.empty(),
                      Full || !dampers_c_.empty(),
                      has_f};
  const auto every = static_cast<std::uint64_t>(sc_.run.record_every);
  const std::uint64_t total = total_steps_;
  // The outputs as they stand (the last step's, or the start's).
  SimpleVars s{x_[0],
               v_[0],
               f_drive_.empty() ? 0.0 : f_drive_[0],
               P.has_k ? f_spring_[0] : 0.0,
               P.has_c ? f_damper_[0] : 0.0,
               has_f ? f_contact_[0] : 0.0,
               has_f ? v_rel_[0] : 0.0,
               drive_work_,
               step_,
               until_record_};
  auto store = [ this, &P ](const SimpleVars& s1) __attribute__((always_inline)) {
    x_[0] = s1.x, v_[0] = s1.v, step_ = s1.step, until_record_ = s1.left;
    if (K != 0) f_drive_[0] = s1.fdrive;
    if (P.has_k) f_spring_[0] = s1.fs;
    if (P.has_c) f_damper_[0] = s1.fd;
    if (P.has_f) f_contact_[0] = s1.F, v_rel_[0] = s1.vr;
    drive_work_ = s1.work;
  };
  auto stop = [&](const SimpleVars& s1) {
    store(s1);
    diverged(!std::isfinite(s1.F));
  };
  // The drive's values of a chunk of steps are computed ahead, so the step loop calls nothing
  // between samples and x and v stay in registers.
  constexpr std::size_t kChunk = 64;
  double sa[kChunk], sb[kChunk];
  std::size_t done = 0;
  while (done < n && s.step < total) {
    const auto chunk =
        static_cast<std::size_t>(std::min<std::uint64_t>({kChunk, n - done, total - s.step}));
    drive_values<K>(P.d, s.step, chunk, h, sa, sb);
    for (std::size_t i = 0; i < chunk; ++i, ++done) {
      if constexpr (K < 3) {
        const std::uint64_t quiet =
            std::min<std::uint64_t>(
                {chunk - i, s.left, kEnergyCheckEvery - (s.step & (kEnergyCheckEvery - 1))}) -
            1;
        quiet_steps<K, Gms, Full, N>(P, sa + i, sb + i, quiet, s, stop);
        i += quiet, done += quiet;
        // The event's step: its outputs are kept.
        const double f = free_step<K, Gms, Full, N>(P, sa[i], sb[i], s);
        if (!std::isfinite(f + s.x + s.v)) stop(s);
        if ((s.step & (kEnergyCheckEvery - 1)) == 0) {
          store(s);
          check_energy();
        }
      } else {
        const double f = prescribed_step<K, Gms, Full, N>(P, sa[i], sb[i], s);
        if (!std::isfinite(f + s.x + s.v)) stop(s);
      }
      if (--s.left == 0 || s.step == total) {
        s.left = every;
        store(s);
        record();
      }
    }
  }
  store(s);
  return done;
}

double AssemblySimulation::compute_step() {
  const double h = sc_.run.dt, t = time();
  const Assembly& p = sc_.plant;
  const std::size_t nb = p.bodies.size();
  double* __restrict x = x_.data();
  double* __restrict v = v_.data();
  double* __restrict cv = cv_.data();
  double* __restrict f = f_.data();
  // 1. prescribed motion: contact velocity over the step; x and v at t + h are set in 4.
  for (std::size_t i = 0; i <= nb; ++i) {
    f[i] = 0.0;
    cv[i] = v[i];
  }
  if (has_prescribed_)
    for (const auto& d : p.drives) {
      if (d.kind == DrivePart::Kind::Displacement) cv[d.body] = (d.signal(t + h) - x[d.body]) / h;
      else if (d.kind == DrivePart::Kind::Velocity) cv[d.body] = 0.5 * (d.signal(t) + d.signal(t + h));
    }
  // 2. non-friction forces: drives, springs, dampers (in this order; the one-body loop's sum).
  for (std::size_t i = 0; i < p.drives.size(); ++i) {
    const auto& d = p.drives[i];
    if (d.kind == DrivePart::Kind::Force || d.kind == DrivePart::Kind::Pull) {
      f_drive_[i] = drive_force(i, t, h, x[d.body], v[d.body]);
      f[d.body] += f_drive_[i];
    }
  }
  double* __restrict fs_out = f_spring_.data();
  for (std::size_t i = 0; i < springs_c_.size(); ++i) {
    const Link& s = springs_c_[i];
    const double fs = s.c * (x[s.a] - x[s.b]);
    fs_out[i] = fs;
    f[s.a] -= fs;
    f[s.b] += fs;
  }
  double* __restrict fd_out = f_damper_.data();
  for (std::size_t i = 0; i < dampers_c_.size(); ++i) {
    const Link& s = dampers_c_[i];
    const double fd = s.c * (v[s.a] - v[s.b]);
    fd_out[i] = fd;
    f[s.a] -= fd;
    f[s.b] += fd;
  }
  // 3. contacts, each with its relative velocity frozen over the step.
  for (std::size_t j = 0; j < contacts_c_.size(); ++j) {
    const CompiledContact& c = contacts_c_[j];
    const double vr = cv[c.a] - cv[c.b];
    double f_other = 0.0;
    if (c.mode == 3) f_other = c.m_eff * (f[c.a] / c.ma - f[c.b] / c.mb);
    else if (c.mode == 1) f_other = f[c.a];
    else if (c.mode == 2) f_other = -f[c.b];
    const double F = models_[j]->step(state_[j], {vr, h, f_other, c.m_eff});
    f_contact_[j] = F;
    v_rel_[j] = vr;
    f[c.a] -= F;
    f[c.b] += F;
  }
  // 4. bodies.
  const double* __restrict hm = h_over_m_.data();
  double probe = 0.0;
  for (std::size_t i = 0; i < nb; ++i) {
    if (!prescribed_[i]) {
      v[i] += f[i] * hm[i];
      x[i] += h * v[i];
    }
    probe += f[i];
  }
  if (!has_prescribed_) return probe + x[0] + v[0];
  for (std::size_t i = 0; i < p.drives.size(); ++i) {
    const auto& d = p.drives[i];
    if (!prescribes(d.kind)) continue;
    // The force the drive must supply to hold the motion against the parts (inertia left out).
    f_drive_[i] = -f[d.body];
    if (d.kind == DrivePart::Kind::Displacement) {
      x[d.body] = d.signal(t + h);
      v[d.body] = cv[d.body];
    } else {
      x[d.body] += cv[d.body] * h;
      v[d.body] = d.signal(t + h);
    }
  }
  for (std::size_t i = 0; i < nb; ++i) probe += x[i] + v[i];
  return probe;
}

std::string AssemblySimulation::divergence_cause() const {
  if (as_scenario_) return gmslab::divergence_cause(*as_scenario_);
  std::ostringstream o;
  o << "The step limit of this plant with contacts stuck is dt < " << stability_limit_dt(sc_.plant)
    << " s (run.dt = " << sc_.run.dt << " s); lower run.dt or soften the stiffest part, or lower the "
    << "dampers (explicit damping needs dt < 2 m / sum c).";
  return o.str();
}

void AssemblySimulation::diverged(bool friction) const {
  std::ostringstream o;
  o << "simulation diverged at t = " << time() << " s (non-finite ";
  // A one-body scenario's plant names what turned non-finite, as its one-body form does.
  o << (as_scenario_ && friction ? "friction force" : "state") << "). " << divergence_cause();
  throw SimulationError(o.str());
}

void AssemblySimulation::rebase_energy() {
  watch_ = one_body_ && !any_input_;
  drive_work_ = 0.0;
  energy0_ = kinetic_energy() + spring_energy();
  storage_ = 0.0;
  for (std::size_t j = 0; j < models_.size(); ++j)
    storage_ += friction_storage(*models_[j], sc_.plant.contacts[j].friction);
  dt_limit_ = as_scenario_ ? stability_limit_dt(*as_scenario_) : stability_limit_dt(sc_.plant);
}

void AssemblySimulation::check_energy() const {
  const double e = kinetic_energy() + spring_energy();
  const double budget = energy0_ + std::abs(drive_work_) + storage_;
  if (!(e - energy0_ - drive_work_ - storage_ > energy_margin(budget, sc_.run.dt, dt_limit_))) return;
  throw SimulationError(energy_growth_message(time(), e, energy0_, drive_work_, storage_) + divergence_cause());
}

std::size_t AssemblySimulation::advance(std::size_t n) {
  // The dedicated one-body loop drives from the signal; a controller's input (set_drive_input)
  // goes through the general path.
  switch (any_input_ ? -1 : simple_) {
    case 0:
      return advance_simple<0, false>(n);
    case 1:
      return simple_gms_ ? advance_simple<1, true>(n) : advance_simple<1, false>(n);
    case 2:
      return simple_gms_ ? advance_simple<2, true>(n) : advance_simple<2, false>(n);
    case 3:
      return simple_gms_ ? advance_simple<3, true>(n) : advance_simple<3, false>(n);
    case 4:
      return simple_gms_ ? advance_simple<4, true>(n) : advance_simple<4, false>(n);
    default: break;
  }
  if (one_body_) return advance_one_body(n);
  const auto every = static_cast<std::uint64_t>(sc_.run.record_every);
  std::size_t done = 0;
  for (; done < n && step_ < total_steps_; ++done) {
    const double probe = compute_step();
    ++step_;
    if (!std::isfinite(probe)) diverged(false);
    if (--until_record_ == 0 || step_ == total_steps_) {
      record();
      until_record_ = every;
    }
  }
  return done;
}

void AssemblySimulation::run_to_end() {
  while (!finished()) advance(1u << 20);
}

double AssemblySimulation::momentum() const {
  double p = 0.0;
  for (std::size_t i = 0; i < sc_.plant.bodies.size(); ++i)
    if (!prescribed_[i]) p += sc_.plant.bodies[i].mass * v_[i];
  return p;
}

double AssemblySimulation::kinetic_energy() const {
  double e = 0.0;
  for (std::size_t i = 0; i < sc_.plant.bodies.size(); ++i) e += 0.5 * sc_.plant.bodies[i].mass * v_[i] * v_[i];
  return e;
}

double AssemblySimulation::spring_energy() const {
  double e = 0.0;
  for (const auto& s : sc_.plant.springs) {
    const double d = x_[s.a] - (s.b < 0 ? 0.0 : x_[s.b]);
    e += 0.5 * s.stiffness * d * d;
  }
  for (std::size_t i = 0; i < sc_.plant.drives.size(); ++i) {
    const auto& d = sc_.plant.drives[i];
    if (d.kind != DrivePart::Kind::Pull) continue;
    const double xp = d.point_velocity ? xp_[i] : d.signal(time());
    e += 0.5 * d.pull_spring * (xp - x_[d.body]) * (xp - x_[d.body]);
  }
  return e;
}

AssemblyTrace simulate(const AssemblyScenario& s) {
  AssemblySimulation sim(s);
  sim.run_to_end();
  return sim.take_trace();
}

AssemblySimulation one_body_simulation(const Scenario& s, TraceOptions trace) {
  check_scenario(s);
  return AssemblySimulation(assembly_from_scenario(s), trace, true);
}

Trace simulate(const Scenario& scenario) {
  AssemblySimulation sim = one_body_simulation(scenario);
  sim.run_to_end();
  return sim.take_one_body_trace();
}

}  // namespace gmslab

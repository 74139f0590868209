#include "core/control/hunting.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"

namespace gmslab::control {

namespace {
constexpr double kPi = std::numbers::pi;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

// First harmonic of the unit-peak wave (its phasor is -j this).
double first_harmonic_of(DriveWave w) { return w == DriveWave::Sine ? 1.0 : 8.0 / (kPi * kPi); }
// The unit-peak wave at phase th (sin th, or the triangle through the same peaks).
double wave_at(DriveWave w, double sin_th) {
  return w == DriveWave::Sine ? sin_th : (2.0 / kPi) * std::asin(std::clamp(sin_th, -1.0, 1.0));
}

// First and third harmonic phasors of x (samples at phase th0 + 2 pi (k + 1) / n, k < n) after the linear
// drift over the period is removed; the detrended samples are written back.
struct Harmonics {
  cplx X1, X3;
  double half_pp = 0.0;
};
Harmonics harmonics(double* x, int n, double x_before, double th0) {
  const double slope = (x[n - 1] - x_before) / n;  // per sample
  Harmonics r;
  double lo = 1e300, hi = -1e300;
  cplx s1, s3;
  for (int k = 0; k < n; ++k) {
    x[k] -= slope * (k + 1 - 0.5 * n);
    const double th = th0 + 2.0 * kPi * (k + 1) / n;
    s1 += x[k] * cplx(std::cos(th), -std::sin(th));
    s3 += x[k] * cplx(std::cos(3 * th), -std::sin(3 * th));
    lo = std::min(lo, x[k]), hi = std::max(hi, x[k]);
  }
  r.X1 = s1 * (2.0 / n);
  r.X3 = s3 * (2.0 / n);
  r.half_pp = 0.5 * (hi - lo);
  return r;
}

double wrap(double a) {  // to (-pi, pi]
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}
}  // namespace

const char* to_string(DriveWave w) { return w == DriveWave::Sine ? "sine" : "triangle"; }

std::optional<IntegralSplit> integral_split(const LeadCompensator& c) {
  int integrators = 0;
  for (int i = 0; i < c.sections(); ++i) integrators += c.section(i).p == 0.0;
  if (integrators != 1) return std::nullopt;
  const Poly N = c.num_poly(), Dp = c.den_poly().shift_down(1);  // den = s Dp
  IntegralSplit s;
  s.R = c.Kc * N(0.0) / Dp(0.0);
  // C_f = Kc N' / Dp, N' = (N - (R / Kc) Dp) / s.
  const Poly Np = (N - Dp * (s.R / c.Kc)).shift_down(1);
  if (Dp.degree() == 0) {
    s.fast.d = c.Kc * Np.coeff(0) / Dp.coeff(0);
  } else {  // Dp = s + a (monic), N' = n1 s + n0
    s.fast.a = Dp.coeff(0);
    s.fast.d = c.Kc * Np.coeff(1);
    s.fast.cst = c.Kc * (Np.coeff(0) - Np.coeff(1) * s.fast.a);
  }
  return s;
}

PlantHarmonics plant_harmonics(const Plant& pl, const FrictionModel& f, const FastPart& fp, double A, double w,
                               const HuntingOptions& o, bool keep_x) {
  if (!(A > 0.0) || !(w > 0.0) || !std::isfinite(A + w))
    throw InputError("hunting describing function: need force amplitude A > 0 N and frequency w > 0 rad/s");
  if (!(pl.mass > 0.0)) throw InputError("hunting describing function: need m > 0 kg");
  if (o.steps < 16 || o.periods < 1)
    throw InputError("hunting describing function: need >= 16 steps per period and >= 1 period");
  const double T = 2.0 * kPi / w;
  int n = o.steps;
  if (o.max_step > 0.0) {
    const double need = std::ceil(T / o.max_step);
    if (need > 2e6)
      throw InputError("hunting describing function: w = " + std::to_string(w) +
                       " rad/s is too slow for the plant's stiffest mode (more than 2e6 steps per period)");
    n = std::max(n, static_cast<int>(need));
  }
  const double h = T / n, m = pl.mass, k = pl.spring, c = pl.damper;
  const double decay = std::exp(-fp.a * h), gain = fp.a > 0.0 ? (1.0 - decay) / fp.a : h;
  std::vector<double> st(f.state_size());
  f.reset(st);
  // Start where a stick-slip cycle starts its rise: the drive at its trough (phase -90 deg), the
  // mass at rest at the low stick level of the ideal cycle, (C_f(0) + k) x0 = -(Fs - F_slide)
  // (F_slide: the lowest steady sliding force; the offset a symmetric Coulomb slip leaves). A
  // drive too weak to break away from there ends stuck (P = 0).
  const cplx jw(0.0, w), U1(0.0, -A * first_harmonic_of(o.wave));
  const double k0 = fp.d + (fp.a > 0.0 ? fp.cst / fp.a : 0.0) + k;
  double f_slide = f.break_away();
  for (int i = 0; i <= 24; ++i) f_slide = std::min(f_slide, f.steady_state(std::pow(10.0, -6.0 + 0.25 * i)));
  double x = k0 > 0.0 ? -(f.break_away() - f_slide) / k0 : 0.0, v = 0.0;
  double ws = fp.a > 0.0 ? -x / fp.a : 0.0;  // e = -x held: w_s at rest = e / a
  const double th0 = -0.5 * kPi;
  const cplx rot(std::cos(w * h), std::sin(w * h)), half(std::cos(0.5 * w * h), std::sin(0.5 * w * h));
  std::vector<double> xs(static_cast<std::size_t>(2 * n));
  double before_prev = x, before_last = x;
  for (int p = 0; p < o.periods; ++p) {
    cplx e(std::cos(th0), std::sin(th0));  // e^{j w t} at the step's start (restarted each period)
    if (p == o.periods - 2) before_prev = x;
    if (p == o.periods - 1) before_last = x;
    double* rec = p == o.periods - 1 ? xs.data() + n : p == o.periods - 2 ? xs.data() : nullptr;
    for (int j = 0; j < n; ++j) {
      const double uI = A * wave_at(o.wave, (e * half).imag());  // at mid-step
      const double err = -x;
      const double uf = fp.d * err + fp.cst * ws;
      ws = decay * ws + gain * err;
      const double f_other = uI + uf - k * x - c * v;
      const double F = f.step(st, {v, h, f_other, m});
      v += h * (f_other - F) / m;
      x += h * v;
      e *= rot;
      if (rec) rec[j] = x;
    }
    if (!std::isfinite(x) || !std::isfinite(v))
      throw SimulationError("hunting describing function: the driven plant diverged (step too large)");
  }
  Harmonics last = harmonics(xs.data() + n, n, before_last, th0);
  if (last.half_pp < 1e-12) last = Harmonics{};  // stuck: roundoff only (P = 0)
  PlantHarmonics r;
  r.X1 = last.X1;
  r.X3 = last.X3;
  r.half_pp = last.half_pp;
  r.P = last.X1 / U1;
  if (o.periods >= 2) {
    const Harmonics prev = harmonics(xs.data(), n, before_prev, th0);
    r.settle = std::abs(last.X1) > 0.0 ? std::abs(last.X1 - prev.X1) / std::abs(last.X1) : 0.0;
  }
  if (keep_x) r.x.assign(xs.begin() + n, xs.end());
  return r;
}

const HuntingCycle* HuntingReport::hunting() const {
  for (const HuntingCycle& c : cycles)
    if (c.stable && c.valid) return &c;
  for (const HuntingCycle& c : cycles)
    if (c.stable) return &c;
  return nullptr;
}

HuntingReport predict_hunting(const Plant& pl, const ModelParams& friction, const LeadCompensator& comp,
                              const HuntingOptions& opt_in) {
  if (!(pl.mass > 0.0)) throw InputError("hunting prediction: need m > 0 kg");
  check_compensator(comp, "hunting prediction");
  if (opt_in.amplitudes < 4) throw InputError("hunting prediction: need >= 4 amplitudes in the grid");
  HuntingReport r;
  r.wave = opt_in.wave;
  const auto split = integral_split(comp);
  if (!split) {
    r.note = "no hunting predicted: the compensator has no integrator (hunting is the integral action's; a "
             "loop without one comes to rest inside the stiction band)";
    for (int i = 0; i < comp.sections(); ++i)
      if (comp.section(i).p == 0.0) r.note = "not predicted for a double integrator";
    return r;
  }
  const auto model = build_model(friction);
  r.break_away = model->break_away();
  r.integral_gain = split->R;
  if (!(r.break_away > 0.0)) {
    r.note = "the friction has no break-away force: nothing sticks, no hunting";
    return r;
  }
  const FastPart& fp = split->fast;
  const double R = split->R;
  HuntingOptions opt = opt_in;
  if (opt.max_step == 0.0) {
    Scenario s;
    s.plant = pl;
    s.friction = friction;
    s.drive.kind = Drive::Kind::Force;
    const double lim = stability_limit_dt(s);
    // The fast part's high-frequency gain acts as one more spring (as in the loop simulation's check).
    const double k_eq = (std::isfinite(lim) ? 4.0 / (lim * lim) * pl.mass : 0.0) + std::max(0.0, fp.d);
    if (k_eq > 0.0) opt.max_step = 0.5 * 2.0 / std::sqrt(k_eq / pl.mass);
    if (pl.damper > 0.0) opt.max_step = std::min(opt.max_step > 0.0 ? opt.max_step : 1e300, 0.2 * pl.mass / pl.damper);
  }
  const auto eval = [&](double lA, double lw) {
    ++r.evaluations;
    return plant_harmonics(pl, *model, fp, std::exp(lA), std::exp(lw), opt);
  };
  const auto phase_err = [](const PlantHarmonics& ph) { return wrap(std::arg(ph.P) + 0.5 * kPi); };
  const auto gain_err = [&](const PlantHarmonics& ph, double lw) { return std::log(R * std::abs(ph.P)) - lw; };
  const double la0 = std::log(0.2 * r.break_away), la1 = std::log(100.0 * r.break_away);
  const int na = opt.amplitudes;
  struct Root {
    double lA = kNaN;
    PlantHarmonics ph;
  };
  // Bisection of the phase error on [lo, hi] (a sign change with |error| < 90 deg at both ends).
  const auto bisect = [&](double lo, double hi, double flo, double lw) {
    Root rt;
    for (int it = 0; it < 14; ++it) {
      const double mid = 0.5 * (lo + hi);
      const PlantHarmonics ph = eval(mid, lw);
      const double fm = std::abs(ph.P) > 0.0 ? phase_err(ph) : kNaN;
      rt.lA = mid, rt.ph = ph;
      if (!std::isfinite(fm)) {  // stuck (below break-away): a larger A
        lo = mid;
        continue;
      }
      if (std::abs(fm) < 1e-4) break;
      if ((fm > 0) == (flo > 0)) lo = mid, flo = fm;
      else hi = mid;
    }
    return rt;
  };
  const auto usable = [&](const PlantHarmonics& ph) {
    return std::abs(ph.P) > 0.0 && std::abs(phase_err(ph)) < 0.5 * kPi;
  };
  // Every phase root at frequency lw over the A grid.
  const auto scan = [&](double lw) {
    std::vector<Root> roots;
    double prev_la = la0;
    PlantHarmonics prev = eval(la0, lw);
    for (int i = 1; i < na; ++i) {
      const double la = la0 + (la1 - la0) * i / (na - 1);
      PlantHarmonics cur = eval(la, lw);
      if (usable(prev) && usable(cur) && (phase_err(prev) > 0) != (phase_err(cur) > 0))
        roots.push_back(bisect(prev_la, la, phase_err(prev), lw));
      prev = std::move(cur), prev_la = la;
    }
    return roots;
  };
  // The phase root nearest lA0 at frequency lw: a bracket grown around lA0, else the full scan.
  const auto root_near = [&](double lA0, double lw) {
    for (double span : {0.15, 0.4, 1.0}) {
      const double lo = lA0 - span, hi = lA0 + span;
      const PlantHarmonics a = eval(lo, lw), b = eval(hi, lw);
      if (usable(a) && usable(b) && (phase_err(a) > 0) != (phase_err(b) > 0))
        return bisect(lo, hi, phase_err(a), lw);
    }
    Root best;
    for (Root& rt : scan(lw))
      if (!std::isfinite(best.lA) || std::abs(rt.lA - lA0) < std::abs(best.lA - lA0)) best = std::move(rt);
    return best;
  };
  // Seed frequency: where the integral's gain R / w equals the fast part's DC gain.
  const double cf0 = fp.d + (fp.a > 0.0 ? fp.cst / fp.a : 0.0);
  const double w_seed = cf0 > 0.0 ? R / cf0 : R / std::max(fp.d, 1e-300);
  std::vector<Root> seeds;
  double lw_seed = std::log(w_seed);
  for (double f : {1.0, 0.25, 4.0, 1.0 / 16, 16.0}) {
    seeds = scan(std::log(w_seed * f));
    if (!seeds.empty()) {
      lw_seed = std::log(w_seed * f);
      break;
    }
  }
  for (Root seed : seeds) {
    // Secant on the gain error in ln w, following this phase root.
    double lw0 = lw_seed, h0 = gain_err(seed.ph, lw0);
    Root cur = seed;
    double lw1 = lw0, h1 = h0;
    bool conv = std::abs(h0) < 1e-3;
    double step = std::clamp(h0, -1.5, 1.5);  // the fixed point w = R |P|
    for (int it = 0; it < 14 && !conv; ++it) {
      Root nx = root_near(cur.lA, lw1 + step);
      int tries = 0;
      while (!std::isfinite(nx.lA) && tries++ < 3) {  // lost the root: a shorter step
        step *= 0.5;
        nx = root_near(cur.lA, lw1 + step);
      }
      if (!std::isfinite(nx.lA)) break;
      lw0 = lw1, h0 = h1;
      lw1 = lw1 + step, cur = nx, h1 = gain_err(nx.ph, lw1);
      if (std::abs(h1) < 1e-3) {
        conv = true;
        break;
      }
      step = h1 != h0 ? -h1 * (lw1 - lw0) / (h1 - h0) : h1;
      if (!std::isfinite(step)) break;
      step = std::clamp(step, -1.5, 1.5);
    }
    HuntingCycle hc;
    hc.force_amplitude = std::exp(cur.lA);
    hc.frequency = std::exp(lw1);
    hc.period = 2.0 * kPi / hc.frequency;
    hc.converged = conv && std::abs(phase_err(cur.ph)) < 0.1 * kPi / 180.0;
    bool dup = false;
    for (const HuntingCycle& o : r.cycles)
      dup |= std::abs(std::log(o.force_amplitude) - cur.lA) < 0.01 && std::abs(std::log(o.frequency) - lw1) < 0.01;
    if (dup) continue;
    const PlantHarmonics full = plant_harmonics(pl, *model, fp, hc.force_amplitude, hc.frequency, opt, true);
    ++r.evaluations;
    hc.plant_gain = full.P;
    hc.amplitude = full.half_pp;
    hc.first_harmonic = std::abs(full.X1);
    // Stability (Loeb): g = ln(R |P| / w) + j (arg P + 90 deg); stable when Im(g_A / g_w) < 0.
    const double d = 0.02;
    const auto g = [&](const PlantHarmonics& ph, double lw) { return cplx(gain_err(ph, lw), phase_err(ph)); };
    const cplx g0 = g(full, lw1);
    const PlantHarmonics pa = eval(cur.lA + d, lw1), pw = eval(cur.lA, lw1 + d);
    if (std::abs(pa.P) > 0.0 && std::abs(pw.P) > 0.0) {
      const cplx gA = (g(pa, lw1) - g0) / d, gw = (g(pw, lw1 + d) - g0) / d;
      hc.stable = (gA / gw).imag() < 0.0;
    }
    // Waveform the loop feeds back, -R int x dt, against the assumed wave (same first harmonic).
    const int n = static_cast<int>(full.x.size());
    const double h = hc.period / n;
    std::vector<double> ui(static_cast<std::size_t>(n)), ua(static_cast<std::size_t>(n));
    double acc = 0.0, mean = 0.0;
    for (int k = 0; k < n; ++k) acc += -R * full.x[k] * h, ui[k] = acc, mean += acc / n;
    cplx Ui;
    for (int k = 0; k < n; ++k) {
      ui[k] -= mean;
      const double th = -0.5 * kPi + 2.0 * kPi * (k + 1) / n;  // the block's sample phases
      ua[k] = hc.force_amplitude * wave_at(opt.wave, std::sin(th));
      Ui += ui[k] * cplx(std::cos(th), -std::sin(th));
    }
    const double scale = hc.force_amplitude * first_harmonic_of(opt.wave) / (std::abs(Ui) * 2.0 / n);
    double se = 0.0, sa = 0.0;
    for (int k = 0; k < n; ++k) se += std::pow(ui[k] * scale - ua[k], 2), sa += ua[k] * ua[k];
    hc.waveform_error = sa > 0.0 ? std::sqrt(se / sa) : kNaN;
    hc.valid = hc.converged && hc.waveform_error <= kHuntingWaveformLimit;
    r.cycles.push_back(hc);
  }
  std::sort(r.cycles.begin(), r.cycles.end(),
            [](const HuntingCycle& a, const HuntingCycle& b) { return a.force_amplitude < b.force_amplitude; });
  if (r.cycles.empty())
    r.note = "no hunting predicted: arg P(A, w) never reaches -90 deg for A in [0.2, 100] x break-away";
  return r;
}

}  // namespace gmslab::control

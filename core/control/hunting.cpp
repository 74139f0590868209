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

double wrap(double a) {  // to (-pi, pi]
  while (a > kPi) a -= 2 * kPi;
  while (a <= -kPi) a += 2 * kPi;
  return a;
}
}  // namespace

const char* to_string(DriveWave w) { return w == DriveWave::Sine ? "sine" : "triangle"; }

HuntingOptions view_rate_hunting_options() {
  HuntingOptions ho;
  ho.steps = 200;
  ho.amplitudes = 8;
  ho.max_steps = 4000;
  ho.shooting = 6;
  ho.limit_fraction = 0.9;
  return ho;
}

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
    if (need > o.max_steps)
      throw InputError("hunting describing function: w = " + std::to_string(w) +
                       " rad/s is too slow for the plant's stiffest mode (more than " + std::to_string(o.max_steps) +
                       " steps per period)");
    n = std::max(n, static_cast<int>(need));
  }
  n += n % 2;
  const int nh = n / 2;
  const double h = T / n, m = pl.mass, k = pl.spring, c = pl.damper;
  const double decay = std::exp(-fp.a * h), gain = fp.a > 0.0 ? (1.0 - decay) / fp.a : h;
  std::vector<double> st(f.state_size());
  const cplx rot(std::cos(w * h), std::sin(w * h)), half(std::cos(0.5 * w * h), std::sin(0.5 * w * h));
  // From rest at x = -X0 (friction virgin, C_f's state at rest) with the drive rising through 0,
  // `halves` half periods; x of the last half period into rec (nh samples) when given.
  struct End {
    double x, v;
  };
  const auto run = [&](double X0, int halves, double* rec) {
    f.reset(st);
    double x = -X0, v = 0.0, ws = fp.a > 0.0 ? X0 / fp.a : 0.0;
    cplx e(1.0, 0.0);
    for (int p = 0; p < halves; ++p) {
      if (p % 2 == 0) e = cplx(1.0, 0.0);  // restart the rotation every period (no drift)
      for (int j = 0; j < nh; ++j) {
        const double uI = A * wave_at(o.wave, (e * half).imag());  // at mid-step
        const double err = -x;
        const double uf = fp.d * err + fp.cst * ws;
        ws = decay * ws + gain * err;
        const double f_other = uI + uf - k * x - c * v;
        const double F = f.step(st, {v, h, f_other, m});
        v += h * (f_other - F) / m;
        x += h * v;
        e *= rot;
        if (rec && p == halves - 1) rec[j] = x;
      }
      if (!std::isfinite(x) || !std::isfinite(v))
        throw SimulationError("hunting describing function: the driven plant diverged (step too large)");
    }
    return End{x, v};
  };
  // The symmetric stick-slip cycle: stuck at -X0 as the drive rises through 0, stuck at +X0 half a
  // period later (odd symmetry). g(X0) = x(T/2) - X0: below the break-away offset the mass never
  // moves (g = -2 X0), just above it one slip overshoots (g > 0), far above it the slip cannot reach
  // +X0 (g < 0): the largest + to - change of g is the cycle (an attracting fixed point of the
  // half-period map). X0 on a grid up to the stick band's edge (C_f(0) + k) X0 = Fs.
  const double k0 = fp.d + (fp.a > 0.0 ? fp.cst / fp.a : 0.0) + k;
  const double Xmax = k0 > 0.0 ? f.break_away() / k0 : 0.0;
  std::vector<double> xs(static_cast<std::size_t>(n));
  PlantHarmonics r;
  bool cycle = false, moves = false;
  double X_star = 0.0;
  if (Xmax > 0.0) {
    // Below X_b = (Fs - A) / k0 the peak drive cannot break the mass away: the grid starts there,
    // denser near it (the + region of g is narrow when the cycle is near its threshold).
    const int grid = std::max(4, o.shooting);
    const double Xb = std::clamp((f.break_away() - A) / k0, 0.0, Xmax);
    int found = -1;
    std::vector<double> gx(grid + 1), gg(grid + 1);
    for (int j = 1; j <= grid; ++j) {
      const double q = static_cast<double>(j) / grid;
      gx[j] = Xb + (Xmax - Xb) * q * q + 1e-9 * Xmax;
      const End e = run(gx[j], 1, nullptr);
      gg[j] = e.x - gx[j];
      moves |= std::abs(e.x + gx[j]) > 1e-12;
    }
    for (int j = grid - 1; j >= 1 && found < 0; --j)
      if (gg[j] > 0.0 && gg[j + 1] <= 0.0) found = j;
    if (found >= 0) {
      double lo = gx[found], hi = gx[found + 1];
      for (int it = 0; it < std::max(4, o.shooting); ++it) {
        const double mid = 0.5 * (lo + hi);
        const double g = run(mid, 1, nullptr).x - mid;
        if (g > 0.0) lo = mid;
        else hi = mid;
      }
      X_star = 0.5 * (lo + hi);
      const End e = run(X_star, 1, xs.data());
      r.settle = std::abs(e.x - X_star) / X_star;
      cycle = true;
    }
  }
  if (cycle) {
    for (int j = 0; j < nh; ++j) xs[nh + j] = -xs[j];  // odd symmetry
  } else if (moves || Xmax == 0.0) {
    // No stick-to-stick cycle (e.g. the mass keeps sliding): the response after `periods` periods
    // from X0 = Xmax / 2, linear drift over the last period removed.
    const End e1 = run(0.5 * Xmax, 2 * o.periods - 1, xs.data());
    const End e2 = run(0.5 * Xmax, 2 * o.periods, xs.data() + nh);  // (the same run, one half longer)
    (void)e1;
    const double slope = (e2.x - xs[0]) / (n - 1);
    for (int j = 0; j < n; ++j) xs[j] -= slope * (j - 0.5 * n);
    r.settle = kNaN;
  } else {
    return r;  // stuck at any offset: P = 0
  }
  cplx s1, s3;
  double lo = 1e300, hi = -1e300;
  for (int j = 0; j < n; ++j) {
    const double th = 2.0 * kPi * (j + 1) / n;
    s1 += xs[j] * cplx(std::cos(th), -std::sin(th));
    s3 += xs[j] * cplx(std::cos(3 * th), -std::sin(3 * th));
    lo = std::min(lo, xs[j]), hi = std::max(hi, xs[j]);
  }
  r.X1 = s1 * (2.0 / n);
  r.X3 = s3 * (2.0 / n);
  r.half_pp = 0.5 * (hi - lo);
  if (r.half_pp < 1e-12) return PlantHarmonics{};
  r.P = r.X1 / cplx(0.0, -A * first_harmonic_of(o.wave));
  if (keep_x) r.x = xs;
  return r;
}

const HuntingCycle* HuntingReport::hunting() const {
  for (const HuntingCycle& c : cycles)
    if (c.stable && c.valid) return &c;
  for (const HuntingCycle& c : cycles)
    if (c.stable) return &c;
  return nullptr;
}

namespace {
// The block's integration step bound the options leave at 0: limit_fraction x the stability limit
// of the block with the fast part's high-frequency gain as one more spring (as in the loop
// simulation's check), and at most 0.2 m / c with a damper.
double default_max_step(const Plant& pl, const ModelParams& friction, const FastPart& fp, double limit_fraction) {
  Scenario s;
  s.plant = pl;
  s.friction = friction;
  s.drive.kind = Drive::Kind::Force;
  const double lim = stability_limit_dt(s);
  const double k_eq = (std::isfinite(lim) ? 4.0 / (lim * lim) * pl.mass : 0.0) + std::max(0.0, fp.d);
  double max_step = 0.0;
  if (k_eq > 0.0) max_step = limit_fraction * 2.0 / std::sqrt(k_eq / pl.mass);
  if (pl.damper > 0.0) max_step = std::min(max_step > 0.0 ? max_step : 1e300, 0.2 * pl.mass / pl.damper);
  return max_step;
}

// Relative waveform error of the force the loop feeds back in the cycle, -R int x dt over the
// period (x: the block's motion over it), against the assumed wave with the same first harmonic.
double waveform_error(std::vector<double> x, double R, const HuntingCycle& hc, DriveWave wave) {
  const int n = std::max(1, static_cast<int>(x.size()));
  x.resize(static_cast<std::size_t>(n));
  const double h = hc.period / n;
  std::vector<double> ui(static_cast<std::size_t>(n)), ua(static_cast<std::size_t>(n));
  double acc = 0.0, mean = 0.0;
  for (int k = 0; k < n; ++k) acc += -R * x[k] * h, ui[k] = acc, mean += acc / n;
  cplx Ui;
  for (int k = 0; k < n; ++k) {
    ui[k] -= mean;
    const double th = 2.0 * kPi * (k + 1) / n;
    ua[k] = hc.force_amplitude * wave_at(wave, std::sin(th));
    Ui += ui[k] * cplx(std::cos(th), -std::sin(th));
  }
  const double scale = hc.force_amplitude * first_harmonic_of(wave) / (std::abs(Ui) * 2.0 / n);
  double se = 0.0, sa = 0.0;
  for (int k = 0; k < n; ++k) se += std::pow(ui[k] * scale - ua[k], 2), sa += ua[k] * ua[k];
  return sa > 0.0 ? std::sqrt(se / sa) : kNaN;
}

// The harmonic balance of the integral force u_I (amplitude A, frequency w) and the block, in
// log coordinates lA = ln A, lw = ln w; every block run counts in the report's evaluations.
class HuntingSearch {
 public:
  // At frequency lw: the A of the phase balance arg P = -90 deg (exact), or the sustain threshold.
  struct Balance {
    double lA = kNaN;
    PlantHarmonics ph;
    bool exact = false;
  };
  // The gain balance R |P| / w = 1 along the phase balance.
  struct Solution {
    Balance b;
    double lw = 0.0;
    bool converged = false;
  };

  HuntingSearch(const Plant& pl, const FrictionModel& model, const IntegralSplit& split, const HuntingOptions& opt,
                HuntingReport& r)
      : pl_(pl), model_(model), fp_(split.fast), R_(split.R), opt_(opt), r_(r),
        // A stick-slip motion, not the creep of a stick band or a presliding model's elastic motion.
        x_scale_(r.break_away / std::max(1e-300, fp_.d + (fp_.a > 0.0 ? fp_.cst / fp_.a : 0.0) + pl.spring)),
        la0_(std::log(0.2 * r.break_away)), la1_(std::log(100.0 * r.break_away)) {}

  Solution solve();
  HuntingCycle cycle(const Solution& s);
  bool moving(const PlantHarmonics& ph) const { return ph.half_pp > 1e-3 * x_scale_; }

 private:
  PlantHarmonics eval(double lA, double lw);
  static double phase_err(const PlantHarmonics& ph) { return wrap(std::arg(ph.P) + 0.5 * kPi); }
  Balance balance(double lw, double lA0);
  Balance scan(const std::vector<double>& las, double lw);
  Balance bisect_phase(double lo, double hi, double flo, double lw);
  Balance bisect_threshold(double lo, double hi, const PlantHarmonics& p1, double lw);
  bool stable(const Balance& b, double lw, const PlantHarmonics& full);

  const Plant& pl_;
  const FrictionModel& model_;
  const FastPart& fp_;
  const double R_;
  const HuntingOptions& opt_;
  HuntingReport& r_;
  const double x_scale_, la0_, la1_;
};

PlantHarmonics HuntingSearch::eval(double lA, double lw) {
  ++r_.evaluations;
  try {
    return plant_harmonics(pl_, model_, fp_, std::exp(lA), std::exp(lw), opt_);
  } catch (const Error&) {  // a frequency too slow for the step bound, a diverging block: no motion
    return PlantHarmonics{};
  }
}

// At frequency lw: the A of the phase balance (bisection on a sign change of the phase error), or,
// when the sustained cycles of the block never lag the drive by 90 deg, the A closest to it: the
// sustain threshold (bisection between stuck and moving). `lA0`: where to look first (a bracket of
// +-0.15 around it), NaN: the whole grid of opt.amplitudes in [0.2, 100] x break-away.
HuntingSearch::Balance HuntingSearch::balance(double lw, double lA0) {
  Balance out;
  std::vector<double> las;
  if (std::isfinite(lA0)) las = {lA0 - 0.15, lA0 + 0.15};
  for (int pass = 0; pass < 2 && !std::isfinite(out.lA); ++pass) {
    if (pass == 1) {
      if (!std::isfinite(lA0)) break;
      las.clear();
    }
    const int na = opt_.amplitudes;
    if (las.empty())
      for (int i = 0; i < na; ++i) las.push_back(la0_ + (la1_ - la0_) * i / (na - 1));
    out = scan(las, lw);
  }
  return out;
}

// The first interval of `las` (ascending lA) that brackets the phase balance or the threshold.
HuntingSearch::Balance HuntingSearch::scan(const std::vector<double>& las, double lw) {
  Balance out;
  std::vector<PlantHarmonics> phs;
  for (double la : las) phs.push_back(eval(la, lw));
  for (std::size_t i = 0; i + 1 < las.size() && !std::isfinite(out.lA); ++i) {
    const PlantHarmonics &p0 = phs[i], &p1 = phs[i + 1];
    if (moving(p0) && moving(p1) && (phase_err(p0) > 0) != (phase_err(p1) > 0) &&
        std::abs(phase_err(p0)) < 0.5 * kPi && std::abs(phase_err(p1)) < 0.5 * kPi)
      out = bisect_phase(las[i], las[i + 1], phase_err(p0), lw);
    else if (!moving(p0) && moving(p1) && phase_err(p1) > 0.0)
      out = bisect_threshold(las[i], las[i + 1], p1, lw);  // lags less than 90 deg above it, stuck below
  }
  return out;
}

// Bisection on the sign of the phase error between lo and hi (phase error flo at lo).
HuntingSearch::Balance HuntingSearch::bisect_phase(double lo, double hi, double flo, double lw) {
  Balance out;
  out.exact = true;
  for (int it = 0; it < (opt_.shooting >= 12 ? 10 : 7); ++it) {
    const double mid = 0.5 * (lo + hi);
    out.ph = eval(mid, lw), out.lA = mid;
    const double fm = moving(out.ph) ? phase_err(out.ph) : -1.0;
    if ((fm > 0) == (flo > 0)) lo = mid, flo = fm;
    else hi = mid;
  }
  return out;
}

// Bisection between stuck (lo) and moving (hi, with harmonics p1): the lowest moving A found.
HuntingSearch::Balance HuntingSearch::bisect_threshold(double lo, double hi, const PlantHarmonics& p1, double lw) {
  Balance out;
  out.ph = p1, out.lA = hi;
  for (int it = 0; it < (opt_.shooting >= 12 ? 8 : 5); ++it) {
    const double mid = 0.5 * (lo + hi);
    const PlantHarmonics pm = eval(mid, lw);
    if (moving(pm)) hi = mid, out.ph = pm, out.lA = mid;
    else lo = mid;
  }
  return out;
}

// The gain balance R |P| / w = 1 by the fixed point w <- R |P(A(w), w)| (P depends little on w for
// stick-slip: a square wave of x whose level the slips set), damped when it oscillates; from the
// fast part's corner (R / its low-frequency gain), at most 100x away from it.
HuntingSearch::Solution HuntingSearch::solve() {
  const double cf0 = fp_.d + (fp_.a > 0.0 ? fp_.cst / fp_.a : 0.0);
  const double lw_seed = std::log(cf0 > 0.0 ? R_ / cf0 : R_ / std::max(fp_.d, 1e-300));
  Solution s;
  s.lw = lw_seed;
  s.b = balance(s.lw, kNaN);
  double prev_step = 0.0;
  for (int it = 0; it < 24 && std::isfinite(s.b.lA); ++it) {
    double step = std::log(R_ * std::abs(s.b.ph.P)) - s.lw;
    if (std::abs(step) < 5e-3) {
      s.converged = true;
      break;
    }
    if (prev_step != 0.0 && step * prev_step < 0.0) step *= 0.5;
    prev_step = step;
    s.lw += std::clamp(step, -1.5, 1.5);
    if (std::abs(s.lw - lw_seed) > 4.6) break;  // beyond 100x the seed: outside the prediction's range
    Balance nb = balance(s.lw, s.b.lA);
    if (!std::isfinite(nb.lA)) nb = balance(s.lw, kNaN);
    s.b = nb;
  }
  return s;
}

// Stability: stick-slip cycles of the block exist only above the threshold and lag less there as
// A grows (Loeb with g = ln(R |P| / w) + j (arg P + 90 deg): Im(g_A / g_w) < 0); a cycle at the
// threshold is the attracting one the integrator winds up to.
bool HuntingSearch::stable(const Balance& b, double lw, const PlantHarmonics& full) {
  const double d = 0.02;
  const auto g = [&](const PlantHarmonics& ph, double l) { return cplx(std::log(R_ * std::abs(ph.P)) - l, phase_err(ph)); };
  const PlantHarmonics pa = eval(b.lA + d, lw), pw = eval(b.lA, lw + d);
  if (!b.exact) return true;  // at the sustain threshold (see the header)
  if (!moving(pa) || !moving(pw)) return false;
  const cplx g0 = g(full, lw), gA = (g(pa, lw) - g0) / d, gw = (g(pw, lw + d) - g0) / d;
  return (gA / gw).imag() < 0.0;
}

// The predicted cycle at a solution: the block's motion in it, its stability and how well the
// assumed wave matches the force the loop feeds back.
HuntingCycle HuntingSearch::cycle(const Solution& s) {
  HuntingCycle hc;
  hc.force_amplitude = std::exp(s.b.lA);
  hc.frequency = std::exp(s.lw);
  hc.period = 2.0 * kPi / hc.frequency;
  hc.converged = s.converged;
  hc.phase_residual = phase_err(s.b.ph);
  PlantHarmonics full;
  try {
    full = plant_harmonics(pl_, model_, fp_, hc.force_amplitude, hc.frequency, opt_, true);
  } catch (const Error&) {
  }
  ++r_.evaluations;
  hc.plant_gain = full.P;
  hc.amplitude = full.half_pp;
  hc.first_harmonic = std::abs(full.X1);
  hc.stable = stable(s.b, s.lw, full);
  hc.waveform_error = waveform_error(full.x, R_, hc, opt_.wave);
  hc.valid = hc.converged && std::abs(hc.phase_residual) <= kHuntingPhaseLimit &&
             hc.waveform_error <= kHuntingWaveformLimit;
  return hc;
}
}  // namespace

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
  HuntingOptions opt = opt_in;
  if (opt.max_step == 0.0) opt.max_step = default_max_step(pl, friction, split->fast, opt.limit_fraction);
  HuntingSearch search(pl, *model, *split, opt, r);
  const HuntingSearch::Solution s = search.solve();
  if (std::isfinite(s.b.lA) && search.moving(s.b.ph)) r.cycles.push_back(search.cycle(s));
  std::sort(r.cycles.begin(), r.cycles.end(),
            [](const HuntingCycle& a, const HuntingCycle& b) { return a.force_amplitude < b.force_amplitude; });
  if (r.cycles.empty())
    r.note = "no hunting predicted: the block sticks or never lags 90 deg for A in [0.2, 100] x break-away";
  return r;
}

}  // namespace gmslab::control

#include "core/ident/structure.hpp"
#include "core/simd_path.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

namespace gmslab::ident {

namespace {

double sgn(double v) { return static_cast<double>((v > 0.0) - (v < 0.0)); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto m = static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), v.begin() + m, v.end());
  return v[static_cast<std::size_t>(m)];
}

// Regularised upper incomplete gamma Q(a, x) (series / continued fraction).
double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double gln = std::lgamma(a);
  if (x < a + 1) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 500; ++n) {
      ap += 1;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-14) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(-x + a * std::log(x) - gln));
  }
  double b = x + 1 - a, c = 1e300, dd = 1 / b, h = dd;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2;
    dd = an * dd + b;
    if (std::abs(dd) < 1e-300) dd = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    dd = 1 / dd;
    const double del = dd * c;
    h *= del;
    if (std::abs(del - 1) < 1e-14) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

// Chance that chi^2 with `dof` degrees of freedom exceeds x.
double chi2_tail(double x, double dof) { return gamma_q(0.5 * dof, 0.5 * x); }

// 1 - (1 - p)^m without cancellation.
double family(double p, double m) {
  if (p >= 1) return 1.0;
  return -std::expm1(std::max(1.0, m) * std::log1p(-p));
}

double round3(double x) {
  if (x == 0.0 || !std::isfinite(x)) return 0.0;
  const double s = std::pow(10.0, 3 - std::ceil(std::log10(std::abs(x))));
  return std::round(x * s) / s;
}

std::string num(double x, int prec = 3) {
  std::ostringstream o;
  o.precision(prec);
  o << x;
  return o.str();
}

// Length with a unit a person reads: um or mm.
std::string length(double m) {
  if (std::abs(m) < 1e-3) return num(m * 1e6) + " um";
  return num(m * 1e3) + " mm";
}

// Least-squares fit of the four ripple columns at wavelength L on (x, g, r): SSR reduction and
// coefficients {a_sin, a_cos, b_sin, b_cos}.
struct Fit4 {
  double delta = 0;
  Eigen::Vector4d coef = Eigen::Vector4d::Zero();
};

Fit4 fit4(const std::vector<double>& x, const std::vector<double>& g, const std::vector<double>& r,
          double L) {
  const double w = 2 * std::numbers::pi / L;
  Eigen::Matrix4d G = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double s = std::sin(w * x[i]), c = std::cos(w * x[i]);
    const Eigen::Vector4d p(s, c, g[i] * s, g[i] * c);
    G.selfadjointView<Eigen::Lower>().rankUpdate(p);
    b += r[i] * p;
  }
  G = G.selfadjointView<Eigen::Lower>();
  G.diagonal().array() += 1e-9 * G.diagonal().maxCoeff() + 1e-300;
  Fit4 f;
  f.coef = G.ldlt().solve(b);
  f.delta = std::max(0.0, b.dot(f.coef));
  return f;
}

}  // namespace

NoiseEstimate noise_level(const Dataset& d, const EffectContext& c) {
  NoiseEstimate e;
  std::vector<double> rest, all;
  for (std::size_t k = 1; k + 1 < d.size(); ++k) {
    if (!d.use[k - 1] || !d.use[k] || !d.use[k + 1]) continue;
    const double d2 = d.F[k + 1] - 2 * d.F[k] + d.F[k - 1];
    all.push_back(d2);
    if (std::abs(d.v[k - 1]) < c.v_rest && std::abs(d.v[k]) < c.v_rest &&
        std::abs(d.v[k + 1]) < c.v_rest && d.x[k - 1] == d.x[k + 1])
      rest.push_back(d2);
  }
  const bool rests = rest.size() >= 50;
  auto& v = rests ? rest : all;
  if (v.empty()) return e;
  const double m = median(v);
  for (auto& x : v) x = std::abs(x - m);
  e.sigma = 1.4826 * median(v) / std::sqrt(6.0);
  e.samples = v.size();
  e.from_rests = rests;
  return e;
}

void add_quantisation(NoiseEstimate& e, const Dataset& d, const EffectContext& c, const std::vector<double>& f) {
  double q = 0;
  for (std::size_t k = 1; k < d.size(); ++k) {
    const double dx = std::abs(d.x[k] - d.x[k - 1]);
    if (dx > 0 && (q == 0 || dx < q)) q = dx;
  }
  e.quantum = q;
  double s = 0, n = 0;
  for (std::size_t k = 1; k + 1 < d.size(); ++k) {
    if (!d.use[k]) continue;
    n += 1;
    if (std::abs(d.v[k]) < c.v_rest) continue;
    const double dfdx = (f[k + 1] - f[k - 1]) / (d.t[k + 1] - d.t[k - 1]) / d.v[k];
    s += dfdx * dfdx;
  }
  e.quantisation = n > 0 ? std::sqrt(s / n) * q / std::sqrt(12.0) : 0.0;
}

void add_sampling(NoiseEstimate& e, const Dataset& d, const std::vector<double>& f,
                  const std::vector<double>& f_straight) {
  double s = 0, n = 0;
  for (std::size_t k = 0; k < d.size() && k < f.size() && k < f_straight.size(); ++k) {
    if (!d.use[k]) continue;
    s += (f[k] - f_straight[k]) * (f[k] - f_straight[k]);
    n += 1;
  }
  // The path is somewhere between the two (uniformly, for want of better): the straight line's
  // expected error is then the RMS difference over sqrt(3).
  e.sampling = n > 0 ? std::sqrt(s / n / 3.0) : 0.0;
}

void add_sampling_halving(NoiseEstimate& e, const Dataset& d, const std::vector<double>& f,
                          const std::vector<double>& f_half) {
  double s = 0, n = 0;
  for (std::size_t k = 0; k < d.size() && k < f.size() && k / 2 < f_half.size(); k += 2) {
    if (!d.use[k]) continue;
    s += (f[k] - f_half[k / 2]) * (f[k] - f_half[k / 2]);
    n += 1;
  }
  e.sampling_halving = n > 0 ? std::sqrt(s / n) / 2.0 : -1.0;
}

namespace {
struct PeriodogramSums {
  double v[10];  // C0 S0 C1 S1 C2 S2 bs bc bgs bgc
};
// One frequency's sums over the scan samples, and the phase recurrence to the next frequency.
// Compiled for AVX2 and the baseline, chosen per call (core/simd_path.hpp; the reduction order
// depends on the vector width, as in the GMS element step).
[[gnu::always_inline]] inline PeriodogramSums periodogram_body(
    std::size_t ns, double* __restrict pc, double* __restrict ps, const double* __restrict pcr,
    const double* __restrict psr, const double* __restrict pg, const double* __restrict pr) {
  double C0 = 0, S0 = 0, C1 = 0, S1 = 0, C2 = 0, S2 = 0, bs = 0, bc = 0, bgs = 0, bgc = 0;
#pragma omp simd reduction(+ : C0, S0, C1, S1, C2, S2, bs, bc, bgs, bgc)
  for (std::size_t q = 0; q < ns; ++q) {
    const double cc = pc[q], ss = ps[q], gg = pg[q], rr = pr[q];
    const double c2 = cc * cc - ss * ss, s2 = 2 * cc * ss;
    C0 += c2, S0 += s2, C1 += gg * c2, S1 += gg * s2, C2 += gg * gg * c2, S2 += gg * gg * s2;
    bs += rr * ss, bc += rr * cc, bgs += rr * gg * ss, bgc += rr * gg * cc;
    pc[q] = cc * pcr[q] - ss * psr[q];  // (exact again at the next multiple of 128)
    ps[q] = ss * pcr[q] + cc * psr[q];
  }
  return {{C0, S0, C1, S1, C2, S2, bs, bc, bgs, bgc}};
}
__attribute__((target("avx2"))) PeriodogramSums periodogram_avx2(
    std::size_t ns, double* __restrict pc, double* __restrict ps, const double* __restrict pcr,
    const double* __restrict psr, const double* __restrict pg, const double* __restrict pr) {
  return periodogram_body(ns, pc, ps, pcr, psr, pg, pr);
}
PeriodogramSums periodogram_baseline(
    std::size_t ns, double* __restrict pc, double* __restrict ps, const double* __restrict pcr,
    const double* __restrict psr, const double* __restrict pg, const double* __restrict pr) {
  return periodogram_body(ns, pc, ps, pcr, psr, pg, pr);
}
PeriodogramSums periodogram_sums(
    std::size_t ns, double* __restrict pc, double* __restrict ps, const double* __restrict pcr,
    const double* __restrict psr, const double* __restrict pg, const double* __restrict pr) {
  return use_avx2() ? periodogram_avx2(ns, pc, ps, pcr, psr, pg, pr)
                    : periodogram_baseline(ns, pc, ps, pcr, psr, pg, pr);
}
}  // namespace

RippleSearch ripple_search(const Dataset& d, const EffectContext& c, const std::vector<double>& r,
                           const std::vector<double>& g_in, double fap, int max_peaks) {
  RippleSearch out;
  const auto travel = travel_since_reversal(d, c);
  std::vector<double> xs, gs, rs, vs, steps;
  for (std::size_t k = 1; k < d.size(); ++k) {
    if (!d.use[k] || std::abs(d.v[k]) <= 5 * c.v_rest || travel[k] < 4 * c.x_ba) continue;
    xs.push_back(d.x[k] - c.x_mid);
    gs.push_back(g_in.size() == d.size() ? g_in[k] : sgn(d.v[k]));
    rs.push_back(r[k]);
    vs.push_back(d.v[k]);
    steps.push_back(std::abs(d.x[k] - d.x[k - 1]));
  }
  const std::size_t n = xs.size();
  out.samples = n;
  if (n < 60) return out;
  // Remove the static-curve trend and a cubic in x.
  {
    const int p = 8;
    Eigen::MatrixXd A(static_cast<Eigen::Index>(n), p);
    Eigen::VectorXd y(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const double u = vs[i] / c.v_ref, xi = xs[i] / c.x_half;
      A.row(static_cast<Eigen::Index>(i)) << 1.0, sgn(u), u, u * std::abs(u),
          sgn(u) * std::exp(-std::abs(u) / 0.2), xi, xi * xi, xi * xi * xi;
      y(static_cast<Eigen::Index>(i)) = rs[i];
    }
    const Eigen::VectorXd th = A.colPivHouseholderQr().solve(y);
    const Eigen::VectorXd e = y - A * th;
    for (std::size_t i = 0; i < n; ++i) rs[i] = e(static_cast<Eigen::Index>(i));
  }
  const auto [xl, xh] = std::minmax_element(xs.begin(), xs.end());
  const double span = *xh - *xl;
  std::vector<double> st = steps;
  std::nth_element(st.begin(), st.begin() + static_cast<std::ptrdiff_t>(0.9 * (n - 1)), st.end());
  const double step90 = st[static_cast<std::size_t>(0.9 * (n - 1))];
  double lmin = std::max(3.0 * step90, 1e-7), lmax = 0.5 * span;
  if (!(lmax > 2 * lmin)) return out;
  double fmin = 1 / lmax, fmax = 1 / lmin;
  // Grid: oversampled 4x in spatial frequency, at most 6000 frequencies (then the shortest
  // wavelengths are left out and lmin says so).
  const double over = 4.0;
  if ((fmax - fmin) * span * over > 6000) fmax = fmin + 6000 / (span * over), lmin = 1 / fmax;
  out.lmin = lmin, out.lmax = lmax;
  out.independent = std::max(1.0, (fmax - fmin) * span);
  const double df = 1 / (span * over);
  const int M = static_cast<int>(std::floor((fmax - fmin) / df)) + 1;
  // Scan samples: all, or a fixed pseudo-random subset of kRippleScan of them (an even stride would
  // alias a ripple whose period is near the stride's travel); the peak's refinement, amplitude and
  // false-alarm probability use all.
  std::vector<std::size_t> sidx;
  if (n <= kRippleScan) {
    for (std::size_t i = 0; i < n; ++i) sidx.push_back(i);
  } else {
    std::mt19937 rng(20261126u);  // raw outputs only: the same subset on every platform
    std::size_t need = kRippleScan;
    for (std::size_t i = 0; i < n && need > 0; ++i)  // selection sampling (Knuth's algorithm S)
      if (static_cast<double>(rng()) / 4294967296.0 * static_cast<double>(n - i) < static_cast<double>(need)) sidx.push_back(i), --need;
  }
  const std::size_t ns = sidx.size();
  double W1 = 0, W2 = 0;
  for (std::size_t i : sidx) W1 += gs[i], W2 += gs[i] * gs[i];
  const double W0 = static_cast<double>(ns);
  double ssr = 0;
  for (double e : rs) ssr += e * e;
  std::vector<double> P(static_cast<std::size_t>(M));
  for (int round = 0; round < max_peaks; ++round) {
    // Periodogram by phase recurrence (exact every 128 steps), over the scan samples packed
    // contiguously; the recurrence step is fused into the sums' pass.
    std::vector<double> cs(ns), sn(ns), cr(ns), sr(ns), gq(ns), rq(ns), xq(ns);
    for (std::size_t q = 0; q < ns; ++q) gq[q] = gs[sidx[q]], rq[q] = rs[sidx[q]], xq[q] = xs[sidx[q]];
    for (int j = 0; j < M; ++j) {
      const double f = fmin + j * df;
      if (j % 128 == 0) {
        for (std::size_t q = 0; q < ns; ++q) {
          const double ph = 2 * std::numbers::pi * f * xq[q];
          cs[q] = std::cos(ph), sn[q] = std::sin(ph);
          if (j == 0) {
            const double pd = 2 * std::numbers::pi * df * xq[q];
            cr[q] = std::cos(pd), sr[q] = std::sin(pd);
          }
        }
      }
      const PeriodogramSums ps = periodogram_sums(ns, cs.data(), sn.data(), cr.data(), sr.data(), gq.data(), rq.data());
      const double C0 = ps.v[0], S0 = ps.v[1], C1 = ps.v[2], S1 = ps.v[3], C2 = ps.v[4], S2 = ps.v[5];
      const double bs = ps.v[6], bc = ps.v[7], bgs = ps.v[8], bgc = ps.v[9];
      Eigen::Matrix4d G;
      G << (W0 - C0) / 2, S0 / 2, (W1 - C1) / 2, S1 / 2,  //
          S0 / 2, (W0 + C0) / 2, S1 / 2, (W1 + C1) / 2,     //
          (W1 - C1) / 2, S1 / 2, (W2 - C2) / 2, S2 / 2,     //
          S1 / 2, (W1 + C1) / 2, S2 / 2, (W2 + C2) / 2;
      G.diagonal().array() += 1e-9 * G.diagonal().maxCoeff() + 1e-300;
      const Eigen::Vector4d b(bs, bc, bgs, bgc);
      P[static_cast<std::size_t>(j)] = std::max(0.0, b.dot(G.ldlt().solve(b))) * (static_cast<double>(n) / W0);
    }
    if (round == 0) {
      for (int j = M; j-- > 0;) {
        out.wavelength.push_back(1 / (fmin + j * df));
        out.power.push_back(P[static_cast<std::size_t>(j)]);
      }
    }
    const int jp = static_cast<int>(std::max_element(P.begin(), P.end()) - P.begin());
    // Refine on the scan samples (golden section over +-1 grid step); the peak's fit on all.
    double a = fmin + std::max(0, jp - 1) * df, bnd = fmin + std::min(M - 1, jp + 1) * df;
    const double gr = 0.5 * (std::sqrt(5.0) - 1);
    for (int it = 0; it < 30; ++it) {
      const double c1 = bnd - gr * (bnd - a), c2 = a + gr * (bnd - a);
      if (fit4(xq, gq, rq, 1 / c1).delta > fit4(xq, gq, rq, 1 / c2).delta) bnd = c2;
      else a = c1;
    }
    const double fpk = 0.5 * (a + bnd);
    const Fit4 f = fit4(xs, gs, rs, 1 / fpk);
    // Noise power: the residual variance without the peak, or the local periodogram level
    // (median power within a factor 1.5 in frequency, the peak's own lobe left out; the median
    // of chi^2 with 4 degrees of freedom is 3.357), whichever is larger.
    std::vector<double> loc;
    for (int j = 0; j < M; ++j) {
      const double fj = fmin + j * df;
      if (fj > fpk / 1.5 && fj < fpk * 1.5 && std::abs(j - jp) > 2 * over) loc.push_back(P[static_cast<std::size_t>(j)]);
    }
    const double s2_res = (ssr - f.delta) / std::max(1.0, static_cast<double>(n) - 12.0);
    const double s2_loc = loc.size() >= 8 ? median(loc) / 3.357 : 0.0;
    const double s2 = std::max(s2_res, s2_loc);
    RipplePeak pk;
    pk.wavelength = 1 / fpk;
    pk.amplitude = std::sqrt(2 * f.delta / static_cast<double>(n));
    pk.additive = std::hypot(f.coef(0), f.coef(1));
    pk.modulation = std::hypot(f.coef(2), f.coef(3));
    pk.f_statistic = s2 > 0 ? f.delta / (4 * s2) : 0.0;
    pk.false_alarm = family(chi2_tail(4 * pk.f_statistic, 4), out.independent);
    if (pk.false_alarm > fap) break;
    for (std::size_t i = 0; i < out.peaks.size(); ++i) {
      const double ratio = out.peaks[i].wavelength / pk.wavelength;
      if (ratio > 1.5 && std::abs(ratio - std::round(ratio)) < 0.02 * ratio) {
        pk.harmonic_of = static_cast<int>(i);
        break;
      }
    }
    out.peaks.push_back(pk);
    // Prewhiten: remove this ripple and look again.
    const double w = 2 * std::numbers::pi * fpk;
    for (std::size_t i = 0; i < n; ++i) {
      const double s = std::sin(w * xs[i]), cc = std::cos(w * xs[i]);
      rs[i] -= f.coef(0) * s + f.coef(1) * cc + gs[i] * (f.coef(2) * s + f.coef(3) * cc);
    }
    ssr = 0;
    for (double e : rs) ssr += e * e;
  }
  return out;
}

nlohmann::json to_json(const RippleSearch& s) {
  nlohmann::json j;
  j["sliding_samples"] = s.samples;
  j["wavelength_range_m"] = {round3(s.lmin), round3(s.lmax)};
  j["independent_wavelengths"] = round3(s.independent);
  nlohmann::json pk = nlohmann::json::array();
  for (const auto& p : s.peaks) {
    nlohmann::json o = {{"wavelength_m", round3(p.wavelength)},
                        {"amplitude_N", round3(p.amplitude)},
                        {"additive_amplitude_N", round3(p.additive)},
                        {"friction_modulation", round3(p.modulation)},
                        {"f_statistic", round3(p.f_statistic)},
                        {"false_alarm_probability", p.false_alarm}};
    if (p.harmonic_of >= 0) o["harmonic_of_peak"] = p.harmonic_of;
    pk.push_back(o);
  }
  j["peaks"] = pk;
  return j;
}

// ------------------------------------------------------------------------------------------------
// Remaining structure
// ------------------------------------------------------------------------------------------------

namespace {

// Bin means of y over the bins b[k] (-1: not counted); chi^2 of the means against sigma, the
// structure's RMS with the noise share removed.
struct BinTest {
  double chi2 = 0, size = 0, p = 1;
  int bins = 0, worst = -1;
};

BinTest bin_test(const std::vector<int>& bin, const std::vector<double>& y, int nb, double sigma) {
  std::vector<double> s(static_cast<std::size_t>(nb), 0.0), m(static_cast<std::size_t>(nb), 0.0);
  double total = 0;
  for (std::size_t k = 0; k < bin.size(); ++k)
    if (bin[k] >= 0) s[static_cast<std::size_t>(bin[k])] += y[k], m[static_cast<std::size_t>(bin[k])] += 1, total += 1;
  BinTest t;
  double ss = 0, worst = 0;
  for (int b = 0; b < nb; ++b) {
    const auto i = static_cast<std::size_t>(b);
    if (m[i] < 5) continue;
    ++t.bins;
    const double mean = s[i] / m[i];
    ss += m[i] * mean * mean;
    if (m[i] * mean * mean > worst) worst = m[i] * mean * mean, t.worst = b;
  }
  if (t.bins == 0 || sigma <= 0 || total <= 0) return t;
  t.chi2 = ss / (sigma * sigma);
  t.p = chi2_tail(t.chi2, t.bins);
  t.size = std::sqrt(std::max(0.0, ss - t.bins * sigma * sigma) / total);
  return t;
}

}  // namespace

ResidualStructure residual_structure(const Dataset& d, const EffectContext& c,
                                     const std::vector<double>& r, const std::vector<double>& g,
                                     const NoiseEstimate& noise) {
  ResidualStructure out;
  out.noise = noise;
  double ss = 0, nu = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) ss += r[k] * r[k], nu += 1;
  out.rms = nu > 0 ? std::sqrt(ss / nu) : 0.0;
  const double sigma = noise.floor();
  out.rms_to_noise = sigma > 0 ? out.rms / sigma : 0.0;
  const double alpha = 1e-4 / 5;  // five families of tests
  auto add = [&](std::string where, std::string detail, const BinTest& t) {
    if (t.p > alpha || sigma <= 0 || t.size < 0.2 * sigma) return;
    out.findings.push_back({std::move(where), std::move(detail), t.size, t.size / sigma, t.p});
  };
  const std::size_t n = d.size();
  std::vector<double> rd(n);  // residual along the direction of friction
  for (std::size_t k = 0; k < n; ++k) rd[k] = r[k] * (g.size() == n ? sgn(g[k]) : sgn(d.v[k]));
  // By velocity: 16 bins of signed v over [-1.2, 1.2] v_ref plus rest.
  {
    const int nb = 17;
    std::vector<int> b(n, -1);
    for (std::size_t k = 0; k < n; ++k) {
      if (!d.use[k]) continue;
      if (std::abs(d.v[k]) < c.v_rest) { b[k] = 16; continue; }
      b[k] = std::clamp(static_cast<int>((d.v[k] / c.v_ref + 1.2) / 2.4 * 16), 0, 15);
    }
    const auto t = bin_test(b, r, nb, sigma);
    std::string det = "rest";
    if (t.worst >= 0 && t.worst < 16) {
      const double v0 = (t.worst / 16.0 * 2.4 - 1.2) * c.v_ref, v1 = v0 + 2.4 / 16 * c.v_ref;
      det = "v " + num(v0 * 1e3) + " to " + num(v1 * 1e3) + " mm/s";
    }
    add("velocity", "largest mean at " + det, t);
  }
  // By position and over time: 20 bins each, additive and along the friction direction.
  auto along = [&](const std::vector<double>& q, double mid, double half, const char* where,
                   const std::function<std::string(double)>& at) {
    const int nb = 20;
    std::vector<int> b(n, -1);
    for (std::size_t k = 0; k < n; ++k)
      if (d.use[k]) b[k] = std::clamp(static_cast<int>(((q[k] - mid) / half + 1.0) * 0.5 * nb), 0, nb - 1);
    const auto t1 = bin_test(b, r, nb, sigma), t2 = bin_test(b, rd, nb, sigma);
    const auto& t = t1.p <= t2.p ? t1 : t2;
    const double q0 = mid - half + t.worst * 2 * half / nb;
    add(where, std::string(&t == &t1 ? "additive" : "along the friction direction") +
                   ", largest mean near " + at(q0 + half / nb),
        t);
  };
  along(d.x, c.x_mid, c.x_half, "position", [&](double x) { return "x = " + length(x); });
  along(d.t, c.t_mid, c.t_half, "time", [&](double t) { return "t = " + num(t) + " s"; });
  // After reversals: travel since the reversal in bins of x_ba / 8 .. 16 x_ba (log), residual
  // along the new direction of motion.
  {
    const auto travel = travel_since_reversal(d, c);
    const int nb = 8;
    std::vector<int> b(n, -1);
    std::vector<double> rm(n);
    for (std::size_t k = 0; k < n; ++k) {
      rm[k] = r[k] * sgn(d.v[k]);
      if (!d.use[k] || std::abs(d.v[k]) < c.v_rest || travel[k] > 16 * c.x_ba) continue;
      const double q = std::log2(std::max(travel[k], c.x_ba / 8) / (c.x_ba / 8));  // 0 .. 7
      b[k] = std::clamp(static_cast<int>(q), 0, nb - 1);
    }
    const auto t = bin_test(b, rm, nb, sigma);
    const double lo = c.x_ba / 8 * std::pow(2.0, std::max(0, t.worst));
    add("after_reversal", "largest mean at " + length(t.worst <= 0 ? 0.0 : lo) + " to " +
                              length(lo * 2) + " of travel after a reversal",
        t);
  }
  // Position spectrum.
  {
    const auto rs = ripple_search(d, c, r, g, 1e-3, 2);
    for (const auto& p : rs.peaks)
      if (sigma > 0 && p.amplitude >= 0.2 * sigma)
        out.findings.push_back({"position_spectrum", "ripple with wavelength " + length(p.wavelength),
                                p.amplitude / std::sqrt(2.0), p.amplitude / std::sqrt(2.0) / sigma,
                                p.false_alarm});
  }
  std::sort(out.findings.begin(), out.findings.end(),
            [](const auto& a, const auto& b) { return a.size > b.size; });
  std::ostringstream s;
  s << "residual RMS " << num(out.rms) << " N = " << num(out.rms_to_noise) << "x the noise floor ("
    << num(sigma) << " N: noise " << num(noise.sigma) << " N "
    << (noise.from_rests ? "from rests" : "(upper bound: no rests)") << ", encoder quantisation "
    << num(noise.quantisation) << " N, sampling " << num(noise.sampling) << " N)";
  if (out.findings.empty()) {
    s << "; no structure above the noise";
  } else {
    s << "; remaining:";
    for (std::size_t i = 0; i < out.findings.size(); ++i) {
      const auto& f = out.findings[i];
      s << (i ? ";" : "") << ' ' << f.where << " (" << f.detail << ") " << num(f.size) << " N RMS = "
        << num(f.size_to_noise) << "x the floor";
    }
  }
  out.summary = s.str();
  return out;
}

nlohmann::json to_json(const ResidualStructure& s) {
  nlohmann::json j;
  j["noise_sigma_N"] = s.noise.sigma;
  j["noise_from_rests"] = s.noise.from_rests;
  j["noise_samples"] = s.noise.samples;
  j["encoder_step_m"] = s.noise.quantum;
  j["quantisation_N"] = s.noise.quantisation;
  j["sampling_N"] = s.noise.sampling;
  j["floor_N"] = s.noise.floor();
  j["rms_N"] = s.rms;
  j["rms_to_noise"] = s.rms_to_noise;
  nlohmann::json f = nlohmann::json::array();
  for (const auto& x : s.findings)
    f.push_back({{"where", x.where},
                 {"detail", x.detail},
                 {"rms_N", x.size},
                 {"to_noise", x.size_to_noise},
                 {"p_value", x.p_value}});
  j["findings"] = f;
  j["summary"] = s.summary;
  return j;
}

}  // namespace gmslab::ident

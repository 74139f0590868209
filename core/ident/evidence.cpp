#include "core/ident/evidence.hpp"

#include "core/ident/structure.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gmslab::ident {

namespace {

double sgn(double v) { return static_cast<double>((v > 0.0) - (v < 0.0)); }

double corr(const Dataset& d, const std::vector<double>& r, const std::vector<double>& z) {
  double mr = 0, mz = 0, n = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) mr += r[k], mz += z[k], n += 1;
  if (n < 2) return 0.0;
  mr /= n, mz /= n;
  double srr = 0, szz = 0, srz = 0;
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.use[k]) {
      srr += (r[k] - mr) * (r[k] - mr);
      szz += (z[k] - mz) * (z[k] - mz);
      srz += (r[k] - mr) * (z[k] - mz);
    }
  return srr > 0 && szz > 0 ? srz / std::sqrt(srr * szz) : 0.0;
}

template <class F>
std::vector<double> make(const Dataset& d, F f) {
  std::vector<double> z(d.size());
  for (std::size_t k = 0; k < d.size(); ++k) z[k] = f(k);
  return z;
}

double round3(double x) {
  if (x == 0.0 || !std::isfinite(x)) return 0.0;
  const double s = std::pow(10.0, 3 - std::ceil(std::log10(std::abs(x))));
  return std::round(x * s) / s;
}

// Amplitude of the best sine of wavelength L through (x_i, r_i).
double sine_amplitude(const std::vector<double>& x, const std::vector<double>& r, double L) {
  const double w = 2 * std::numbers::pi / L;
  double ss = 0, cc = 0, sc = 0, rs = 0, rc = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double s = std::sin(w * x[i]), c = std::cos(w * x[i]);
    ss += s * s, cc += c * c, sc += s * c, rs += r[i] * s, rc += r[i] * c;
  }
  const double det = ss * cc - sc * sc;
  if (det <= 0) return 0.0;
  const double a = (rs * cc - rc * sc) / det, b = (rc * ss - rs * sc) / det;
  return std::hypot(a, b);
}

}  // namespace

Spectrum position_spectrum(const Dataset& d, const EffectContext& c, const std::vector<double>& r) {
  Spectrum s;
  // Moving samples, residual detrended by a cubic in xi.
  std::vector<double> xs, rs;
  double max_dx = 0;
  for (std::size_t k = 1; k < d.size(); ++k)
    if (d.use[k] && std::abs(d.v[k]) > 5 * c.v_rest) {
      xs.push_back(d.x[k]);
      rs.push_back(r[k]);
      max_dx = std::max(max_dx, std::abs(d.x[k] - d.x[k - 1]));
    }
  if (xs.size() < 50) return s;
  {
    double m[4][5] = {};
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double xi = (xs[i] - c.x_mid) / c.x_half;
      const double p[4] = {1, xi, xi * xi, xi * xi * xi};
      for (int a = 0; a < 4; ++a) {
        for (int b = 0; b < 4; ++b) m[a][b] += p[a] * p[b];
        m[a][4] += p[a] * rs[i];
      }
    }
    for (int a = 0; a < 4; ++a)  // Gauss-Jordan on the 4x4 normal equations
      for (int b = 0; b < 4; ++b)
        if (b != a && m[a][a] != 0) {
          const double f = m[b][a] / m[a][a];
          for (int q = 0; q < 5; ++q) m[b][q] -= f * m[a][q];
        }
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const double xi = (xs[i] - c.x_mid) / c.x_half;
      const double p[4] = {1, xi, xi * xi, xi * xi * xi};
      for (int a = 0; a < 4; ++a)
        if (m[a][a] != 0) rs[i] -= m[a][4] / m[a][a] * p[a];
    }
  }
  // Decimate for the scan; refine on all samples.
  std::vector<double> xd, rd;
  const std::size_t stride = std::max<std::size_t>(1, xs.size() / 4000);
  for (std::size_t i = 0; i < xs.size(); i += stride) xd.push_back(xs[i]), rd.push_back(rs[i]);
  const double lmin = std::max(4.0 * max_dx, 1e-7);
  const double lmax = 0.5 * c.x_half;
  if (!(lmax > 2 * lmin)) return s;
  const int n = 240;
  for (int i = 0; i < n; ++i) {
    const double L = lmin * std::pow(lmax / lmin, i / (n - 1.0));
    s.wavelength.push_back(L);
    s.amplitude.push_back(sine_amplitude(xd, rd, L));
  }
  const auto it = std::max_element(s.amplitude.begin(), s.amplitude.end());
  const auto i0 = static_cast<std::size_t>(it - s.amplitude.begin());
  std::vector<double> sorted = s.amplitude;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const double med = sorted[n / 2];
  // Golden-section refinement between the neighbours of the peak.
  double a = s.wavelength[i0 > 0 ? i0 - 1 : 0], b = s.wavelength[std::min<std::size_t>(i0 + 1, n - 1)];
  const double gr = 0.5 * (std::sqrt(5.0) - 1);
  for (int it2 = 0; it2 < 30; ++it2) {
    const double c1 = b - gr * (b - a), c2 = a + gr * (b - a);
    if (sine_amplitude(xs, rs, c1) > sine_amplitude(xs, rs, c2)) b = c2;
    else a = c1;
  }
  s.peak_wavelength = 0.5 * (a + b);
  s.peak_amplitude = sine_amplitude(xs, rs, s.peak_wavelength);
  s.peak_to_median = med > 0 ? *it / med : 0.0;
  return s;
}

nlohmann::json effect_evidence(Effect e, const Dataset& d, const EffectContext& c,
                               const std::vector<double>& r, const std::vector<double>& g,
                               const RippleSearch& ripples, const std::vector<double>* g_contact) {
  nlohmann::json j = nlohmann::json::object();
  switch (e) {
    case Effect::Inertia:
      j["corr_acceleration"] = round3(corr(d, r, d.a));
      break;
    case Effect::Offset: {
      double s = 0, n = 0;
      for (std::size_t k = 0; k < d.size(); ++k)
        if (d.use[k]) s += r[k], n += 1;
      j["mean_residual_N"] = round3(n ? s / n : 0.0);
      break;
    }
    case Effect::DirectionAsymmetry: {
      double sp_ = 0, np = 0, sn = 0, nn = 0;
      for (std::size_t k = 0; k < d.size(); ++k)
        if (d.use[k] && std::abs(d.v[k]) > 0.2 * c.v_ref) {
          if (d.v[k] > 0) sp_ += r[k], np += 1;
          else sn += r[k], nn += 1;
        }
      j["mean_residual_sliding_positive_N"] = round3(np ? sp_ / np : 0.0);
      j["mean_residual_sliding_negative_N"] = round3(nn ? sn / nn : 0.0);
      j["corr_abs_velocity"] = round3(corr(d, r, make(d, [&](auto k) { return std::abs(d.v[k]); })));
      j["corr_abs_friction"] = round3(corr(d, r, make(d, [&](auto k) { return std::abs(g[k]); })));
      break;
    }
    case Effect::PositionPeriodic:
      j["ripple_search"] = to_json(ripples);
      break;
    case Effect::PositionDependent:
      j["corr_position"] = round3(corr(d, r, d.x));
      j["corr_friction_times_position"] =
          round3(corr(d, r, make(d, [&](auto k) { return g[k] * (d.x[k] - c.x_mid); })));
      break;
    case Effect::TimeDrift:
      j["corr_time"] = round3(corr(d, r, d.t));
      j["corr_friction_times_time"] =
          round3(corr(d, r, make(d, [&](auto k) { return g[k] * (d.t[k] - c.t_mid); })));
      break;
    case Effect::VelocityExtra: {
      const int nb = 8;
      std::vector<double> s(nb, 0.0), n(nb, 0.0);
      for (std::size_t k = 0; k < d.size(); ++k) {
        if (!d.use[k]) continue;
        const double q = std::abs(d.v[k]) / (1.2 * c.v_ref);
        const int b = std::min(nb - 1, static_cast<int>(q * nb));
        s[b] += r[k] * sgn(d.v[k]), n[b] += 1;
      }
      nlohmann::json tab = nlohmann::json::array();
      for (int b = 0; b < nb; ++b)
        tab.push_back({{"abs_v_mps", round3((b + 0.5) / nb * 1.2 * c.v_ref)},
                       {"mean_residual_along_v_N", round3(n[b] ? s[b] / n[b] : 0.0)},
                       {"samples", static_cast<int>(n[b])}});
      j["by_velocity_bin"] = tab;
      break;
    }
    case Effect::DwellStiction: {
      nlohmann::json tab = nlohmann::json::array();
      std::vector<double> phi, peak;
      for (const auto& m : motion_starts(d, c)) {
        double pk = 0;
        for (std::size_t k = m.k; k < d.size() && std::abs(d.x[k] - d.x[m.k]) < c.dwell_s0; ++k)
          if (d.use[k]) pk = std::max(pk, m.dir * r[k]);
        phi.push_back(std::log(1 + m.dwell / c.dwell_tau));
        peak.push_back(pk);
        if (tab.size() < 40)
          tab.push_back({{"t_s", round3(d.t[m.k])}, {"dwell_s", round3(m.dwell)}, {"residual_peak_N", round3(pk)}});
      }
      double c_ = 0;
      if (phi.size() >= 3) {
        Dataset tmp;
        tmp.t = phi;
        tmp.use.assign(phi.size(), 1);
        c_ = corr(tmp, peak, phi);
      }
      j["breakaways"] = tab;
      j["corr_log_dwell_peak"] = round3(c_);
      j["decay_length_m"] = round3(c.dwell_s0);
      break;
    }
    case Effect::NormalLoad:
      if (d.has_Fn && c.Fn0 != 0)
        j["corr_friction_times_normal"] =
            round3(corr(d, r, make(d, [&](auto k) { return g[k] * (d.Fn[k] / c.Fn0 - 1); })));
      break;
    case Effect::TimeShift: {
      std::vector<double> z(d.size());
      shifted(d, g, c.time_shift, z);
      for (std::size_t k = 0; k < d.size(); ++k) z[k] -= g[k];
      j["time_shift_s"] = round3(c.time_shift);
      j["time_shift_samples"] = round3(c.time_shift / c.h_med);
      j["corr_shifted_model"] = round3(corr(d, r, z));
      j["corr_acceleration"] = round3(corr(d, r, d.a));
      break;
    }
    case Effect::SensorFilter: {
      std::vector<double> z(d.size());
      lowpass(d, g, c.filter_T, z);
      for (std::size_t k = 0; k < d.size(); ++k) z[k] -= g[k];
      j["time_constant_s"] = round3(c.filter_T);
      j["time_constant_samples"] = round3(c.filter_T / c.h_med);
      j["corr_filtered_model"] = round3(corr(d, r, z));
      break;
    }
    case Effect::Backlash: {
      j["lost_motion_m"] = round3(c.backlash);
      if (g_contact && g_contact->size() == d.size()) {
        std::vector<double> z(d.size());
        for (std::size_t k = 0; k < d.size(); ++k) z[k] = (*g_contact)[k] - g[k];
        j["corr_model_through_backlash"] = round3(corr(d, r, z));
      }
      // Mean residual along the new direction over the first 2 b after reversals.
      const auto travel = travel_since_reversal(d, c);
      double s = 0, n = 0;
      for (std::size_t k = 0; k < d.size(); ++k)
        if (d.use[k] && travel[k] < 2 * c.backlash && std::abs(d.v[k]) > c.v_rest)
          s += r[k] * sgn(d.v[k]), n += 1;
      j["mean_residual_after_reversal_N"] = round3(n ? s / n : 0.0);
      break;
    }
    case Effect::Discovered:
      j["terms"] = c.discovered.size();
      break;
  }
  return j;
}

}  // namespace gmslab::ident

// The figure set: every figure is drawable (labelled axes with units, non-empty series), and each
// figure's CSV (write_figure_csv) carries the reference numbers of docs/references.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "core/figures/figure_set.hpp"

namespace gmslab {
namespace {

const std::string kPresets = std::string(GMSLAB_SOURCE_DIR) + "/presets";

// One series read back from the CSV.
struct Xy {
  std::vector<double> x, y;
};
using Csv = std::map<std::string, std::map<std::string, Xy>>;  // panel -> series -> points

// Returns the cached parse (a reference: callers keep references into it).
const Csv& csv_of(const std::string& id) {
  static std::map<std::string, Csv> cache;
  if (auto it = cache.find(id); it != cache.end()) return it->second;
  std::stringstream ss;
  write_figure_csv(make_figure(id, kPresets), ss);
  Csv out;
  std::string line;
  std::getline(ss, line);
  EXPECT_EQ(line, "panel,series,x,y,x_label,y_label");
  while (std::getline(ss, line)) {
    // One header, then rows only: a plain pandas.read_csv / MATLAB readtable reads the file.
    EXPECT_NE(line.rfind("#", 0), 0u) << id << ": comment line " << line;
    std::stringstream ls(line);
    std::string panel, series, x, y, x_label, y_label;
    std::getline(ls, panel, ',');
    std::getline(ls, series, ',');
    std::getline(ls, x, ',');
    std::getline(ls, y, ',');
    std::getline(ls, x_label, ',');
    std::getline(ls, y_label);
    // Every row carries its panel's axis labels with units.
    if (x_label.find('[') == std::string::npos || y_label.find('[') == std::string::npos)
      ADD_FAILURE() << id << ": row without labels and units: " << line;
    auto& s = out[panel][series];
    s.x.push_back(std::stod(x));
    s.y.push_back(std::stod(y));
  }
  return cache[id] = out;
}

const Xy& series(const Csv& c, const std::string& panel, const std::string& name) {
  static const Xy empty;
  const auto p = c.find(panel);
  if (p == c.end()) return ADD_FAILURE() << "no panel " << panel, empty;
  const auto s = p->second.find(name);
  if (s == p->second.end()) return ADD_FAILURE() << "no series " << name, empty;
  return s->second;
}

// y where x first crosses x0 in `direction` (+1 up, -1 down) at or after index `from`.
double crossing(const Xy& s, double x0, int direction, std::size_t from = 0) {
  for (std::size_t k = std::max<std::size_t>(from, 1); k < s.x.size(); ++k) {
    const double a = direction * (s.x[k - 1] - x0), b = direction * (s.x[k] - x0);
    if (a < 0 && b >= 0) return s.y[k - 1] + (s.y[k] - s.y[k - 1]) * (x0 - s.x[k - 1]) / (s.x[k] - s.x[k - 1]);
  }
  return NAN;
}

double y_at(const Xy& s, double x0) {  // nearest sample (x = time)
  std::size_t best = 0;
  for (std::size_t k = 0; k < s.x.size(); ++k)
    if (std::abs(s.x[k] - x0) < std::abs(s.x[best] - x0)) best = k;
  return s.y[best];
}

TEST(FigureSet, EveryFigureHasLabelledAxesWithUnitsAndData) {
  for (const auto& id : figure_ids()) {
    const Figure f = make_figure(id, kPresets);
    EXPECT_EQ(f.id, id);
    EXPECT_FALSE(f.title.empty());
    EXPECT_FALSE(f.caption.empty());
    ASSERT_FALSE(f.panels.empty()) << id;
    for (const auto& p : f.panels) {
      EXPECT_FALSE(p.letter.empty()) << id;
      EXPECT_NE(p.x_label.find('['), std::string::npos) << id << ": unit in " << p.x_label;
      EXPECT_NE(p.y_label.find('['), std::string::npos) << id << ": unit in " << p.y_label;
      ASSERT_FALSE(p.series.empty()) << id << " " << p.letter;
      for (const auto& s : p.series) {
        EXPECT_EQ(s.label.find(','), std::string::npos) << "CSV-safe label: " << s.label;
        EXPECT_GE(s.x.size(), 20u) << id << " " << s.label;
        EXPECT_EQ(s.x.size(), s.y.size());
        EXPECT_LE(s.x.size(), 20000u) << id << " " << s.label;
        for (std::size_t k = 0; k < s.x.size(); ++k)
          ASSERT_TRUE(std::isfinite(s.x[k]) && std::isfinite(s.y[k])) << id << " " << s.label;
      }
    }
  }
  EXPECT_THROW(make_figure("fig9_nonsense", kPresets), InputError);
}

TEST(FigureCsv, Fig2aTurningPointsAndVirginCurve) {
  const Xy& s = series(csv_of("fig2a_presliding"), "A", "GMS");
  std::vector<double> turning;  // forces where x reverses: 15, -15, 8, -3, 15 um, then the end
  std::size_t after_inner = 0;  // index of the -3 um reversal
  for (std::size_t k = 1; k + 1 < s.x.size(); ++k)
    if ((s.x[k] - s.x[k - 1]) * (s.x[k + 1] - s.x[k]) < 0) {
      turning.push_back(s.y[k]);
      if (turning.size() == 4) after_inner = k;
    }
  turning.push_back(s.y.back());
  const std::vector<double> ref = {1.35, -1.35, 1.14, -0.585, 1.35, -1.35};
  ASSERT_EQ(turning.size(), ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_NEAR(turning[i], ref[i], 5e-3) << i;
  // Back at 8 um after the inner loop: the loop closes at 1.14 N.
  EXPECT_NEAR(crossing(s, 8.0, +1, after_inner), 1.14, 5e-3);
  const double virgin[][2] = {{1, 0.21}, {2, 0.42}, {5, 0.825}, {10, 1.20}};
  for (const auto& v : virgin) EXPECT_NEAR(crossing(s, v[0], +1), v[1], 5e-3) << v[0] << " um";
}

TEST(FigureCsv, Fig2bLagLoopsAtOneMillimetrePerSecond) {
  const Csv c = csv_of("fig2b_frictional_lag");
  const struct {
    const char* name;
    double up, down;
  } ref[] = {{"a0 = 1 mm/s^2 (reference)", 1.186, 1.182}, {"16 a0", 1.222, 1.154},
             {"100 a0", 1.320, 1.079}};
  for (const auto& r : ref) {
    const Xy& s = series(c, "B", r.name);
    EXPECT_NEAR(crossing(s, 1.0, +1), r.up, 2e-3) << r.name;
    EXPECT_NEAR(crossing(s, 1.0, -1), r.down, 2e-3) << r.name;
  }
}

TEST(FigureCsv, Fig2cMidStrokeForcesAndEqualPresliding) {
  const Csv c = csv_of("fig2c_periodic_sliding");
  const Xy& slow = series(c, "C", "0.1 Hz");
  const Xy& fast = series(c, "C", "1 Hz");
  EXPECT_NEAR(crossing(slow, 0.0, +1), 1.45, 0.02);
  EXPECT_NEAR(crossing(fast, 0.0, +1), 1.00, 0.02);
  // After the reversal at x = +0.5 mm every element sticks: over the first 2 um the force drops by
  // sum k_i * 2 um = 0.42 N at both frequencies.
  for (const Xy* s : {&slow, &fast}) {
    const std::size_t top = std::max_element(s->x.begin(), s->x.end()) - s->x.begin();
    const double drop = s->y[top] - crossing(*s, s->x[top] - 2e-3, -1, top);
    EXPECT_NEAR(drop, 0.42, 0.01);
  }
}

TEST(FigureCsv, Fig2dStopsAfterAbout30cmAndStaysPut) {
  const Csv c = csv_of("fig2d_nondrifting");
  const Xy& x = series(c, "D", "position x");
  EXPECT_NEAR(y_at(x, 2.0), 300.0, 10.0);  // mm
  double t_stop = 0.0;  // the end of the slide: x stops increasing
  for (std::size_t k = 1; k < x.x.size() && t_stop == 0.0; ++k)
    if (x.x[k] > 0.6 && x.y[k] < x.y[k - 1]) t_stop = x.x[k - 1];
  EXPECT_NEAR(t_stop, 1.31, 0.02);
  // After the stop the body vibrates elastically (a few um) with the force; at the same phase of
  // the force (t = 2 s and 12 s) it is back within 0.03 um: no drift.
  const Xy& d = series(c, "D''", "GMS");
  EXPECT_LT(std::abs(d.y.back() - d.y.front()), 0.035);  // um
  EXPECT_LT(*std::max_element(d.y.begin(), d.y.end()), 5.0);
  for (double y : series(c, "D''", "same phase of each force period").y) EXPECT_LT(std::abs(y), 0.035);
}

TEST(FigureCsv, Fig4SlipOnsetsSpikeAndSlidingForce) {
  const Csv c = csv_of("fig4_stick_slip");
  const Xy& v = series(c, "a", "velocity v");
  const Xy& ff = series(c, "b", "friction force");
  const Xy& fs = series(c, "b", "spring force");
  std::vector<double> on, stick;  // slip onsets (v up through 1 mm/s), sticks (v down through 0)
  for (std::size_t k = 1; k < v.x.size(); ++k) {
    if (v.y[k - 1] <= 1e-3 && v.y[k] > 1e-3) on.push_back(v.x[k]);
    if (v.y[k - 1] > 0.0 && v.y[k] <= 0.0 && on.size() > stick.size()) stick.push_back(v.x[k]);
  }
  ASSERT_EQ(on.size(), 3u);
  const double ref[] = {7.55, 14.08, 20.61};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(on[i], ref[i], 0.02);
    EXPECT_NEAR(y_at(fs, on[i]), 1.5, 0.02) << "slip starts at Fs";
  }
  ASSERT_GE(stick.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    double spike = 0.0;
    for (std::size_t k = 0; k < ff.x.size(); ++k)
      if (ff.x[k] > stick[i] - 0.005 && ff.x[k] <= stick[i]) spike = std::max(spike, ff.y[k]);
    EXPECT_NEAR(spike, 1.19, 0.02) << "spike in the last ms before stick " << i;
    const double tm = 0.5 * (on[i] + stick[i]);  // mid-slip: non-viscous part near Fc
    const double sliding = y_at(ff, tm) - 0.4 * y_at(v, tm);
    EXPECT_GT(sliding, 0.99);
    EXPECT_LT(sliding, 1.04);
  }
}

TEST(FigureCsv, CompareFig2dLuGreDriftsGmsDoesNot) {
  const Csv c = csv_of("compare_fig2d_drift");
  const Xy& lugre = series(c, "A", "LuGre");
  EXPECT_NEAR(lugre.y.back() - y_at(lugre, 6.0), 81.0, 2.0);
  for (const char* m : {"GMS", "elasto-plastic", "Maxwell-slip"}) {
    const Xy& s = series(c, "B", m);
    EXPECT_LT(std::abs(s.y.back() - y_at(s, 6.0)), 0.1) << m;
  }
}

TEST(FigureCsv, CompareFig4PeriodsGmsAndLuGre) {
  const Csv c = csv_of("compare_fig4_stick_slip");
  auto period = [&](const char* m) {
    const Xy& v = series(c, "a", m);
    std::vector<double> on;
    for (std::size_t k = 1; k < v.x.size(); ++k)
      if (v.y[k - 1] <= 1e-3 && v.y[k] > 1e-3) on.push_back(v.x[k]);
    return on.size() >= 3 ? on[2] - on[1] : NAN;
  };
  EXPECT_NEAR(period("GMS"), 6.53, 0.02);
  EXPECT_NEAR(period("LuGre"), 6.36, 0.03);
}

}  // namespace
}  // namespace gmslab

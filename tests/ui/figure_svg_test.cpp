// Vector figures: ui::figure_svg over random figures (panels, series, ranges, styles; fixed seed)
// is well-formed XML whose text is text (titles, axis labels with units, legend labels, tick
// labels) and whose polylines, mapped back through each panel's recorded ranges, give every data
// point of every series to within the 0.01 px the coordinates are written with. The commands
// `figures --format both` and `render --format svg` write such files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/figures/figure_set.hpp"
#include "ui/figures/figure_svg.hpp"

using namespace gmslab;
namespace fs = std::filesystem;

namespace {
struct Element {
  std::string name, text;
  std::map<std::string, std::string> attr;
  std::vector<Element> children;
};

std::string unescape(std::string s) {
  const std::pair<const char*, const char*> m[] = {{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}};
  for (auto [from, to] : m)
    for (std::size_t i = 0; (i = s.find(from, i)) != std::string::npos; i += std::string(to).size())
      s.replace(i, std::string(from).size(), to);
  return s;
}

// A strict little XML parser (elements, attributes, text; the prolog skipped). Throws on any
// malformation: unbalanced or mismatched tags, unquoted attributes, stray '<' or '&'.
struct Parser {
  const std::string& s;
  std::size_t i = 0;
  void ws() { while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i; }
  std::string name() {
    const std::size_t a = i;
    while (i < s.size() && (std::isalnum(static_cast<unsigned char>(s[i])) || s[i] == '-' || s[i] == '_' || s[i] == ':')) ++i;
    if (a == i) throw std::runtime_error("name expected at " + std::to_string(a));
    return s.substr(a, i - a);
  }
  Element element() {
    if (s[i] != '<') throw std::runtime_error("'<' expected at " + std::to_string(i));
    ++i;
    Element e;
    e.name = name();
    for (;;) {
      ws();
      if (s.compare(i, 2, "/>") == 0) return i += 2, e;
      if (s[i] == '>') break;
      const std::string k = name();
      ws();
      if (s[i] != '=') throw std::runtime_error("'=' expected after " + k);
      ++i;
      ws();
      if (s[i] != '"') throw std::runtime_error("quoted value expected for " + k);
      const std::size_t end = s.find('"', i + 1);
      const std::string v = s.substr(i + 1, end - i - 1);
      if (v.find('<') != std::string::npos) throw std::runtime_error("'<' in attribute " + k);
      e.attr[k] = unescape(v);
      i = end + 1;
    }
    ++i;
    for (;;) {
      const std::size_t lt = s.find('<', i);
      if (lt == std::string::npos) throw std::runtime_error("unclosed <" + e.name + ">");
      const std::string t = s.substr(i, lt - i);
      for (std::size_t a = t.find('&'); a != std::string::npos; a = t.find('&', a + 1))
        if (t.compare(a, 4, "&lt;") && t.compare(a, 4, "&gt;") && t.compare(a, 5, "&amp;") && t.compare(a, 6, "&quot;"))
          throw std::runtime_error("stray '&' in text");
      e.text += unescape(t);
      i = lt;
      if (s.compare(i, 2, "</") == 0) {
        i += 2;
        if (name() != e.name) throw std::runtime_error("mismatched </...> for <" + e.name + ">");
        ws();
        if (s[i] != '>') throw std::runtime_error("'>' expected");
        return ++i, e;
      }
      e.children.push_back(element());
    }
  }
  Element document() {
    if (s.compare(0, 5, "<?xml") == 0) i = s.find("?>") + 2;
    ws();
    Element root = element();
    ws();
    if (i != s.size()) throw std::runtime_error("content after the root element");
    return root;
  }
};

void collect(const Element& e, const std::string& name, std::vector<const Element*>& out) {
  if (e.name == name) out.push_back(&e);
  for (const auto& c : e.children) collect(c, name, out);
}

std::vector<const Element*> all(const Element& e, const std::string& name) {
  std::vector<const Element*> out;
  collect(e, name, out);
  return out;
}

bool has_text(const Element& root, const std::string& want) {
  for (const Element* t : all(root, "text"))
    if (t->text == want) return true;
  return false;
}

Figure random_figure(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  Figure f;
  f.id = "random";
  f.title = "Random <figure> & \"quotes\"";
  const int panels = 1 + static_cast<int>(rng() % 3);
  for (int k = 0; k < panels; ++k) {
    Panel p;
    p.letter = std::string(1, static_cast<char>('A' + k));
    p.title = "panel " + p.letter;
    p.x_label = "x [um]";
    p.y_label = "F_f [N]";
    const double sx = std::pow(10.0, -6 + 12 * u(rng)), sy = std::pow(10.0, -6 + 12 * u(rng));
    const int ns = 1 + static_cast<int>(rng() % 4);
    for (int j = 0; j < ns; ++j) {
      Series s;
      s.label = "series " + std::to_string(j);
      s.style = static_cast<Series::Style>(rng() % 3);
      const int n = 2 + static_cast<int>(rng() % 300);
      for (int i = 0; i < n; ++i) {
        s.x.push_back(sx * (i + u(rng)));
        s.y.push_back(sy * (u(rng) - 0.5) * (j + 1));
      }
      p.series.push_back(std::move(s));
    }
    f.panels.push_back(std::move(p));
  }
  return f;
}

double attr(const Element& e, const char* k) { return std::stod(e.attr.at(k)); }
}  // namespace

TEST(FigureSvg, IsValidXmlWithTextAsTextAndPolylinesThatGiveBackTheData) {
  std::mt19937 rng(4242);
  for (int trial = 0; trial < 25; ++trial) {
    const Figure f = random_figure(rng);
    const int w = 640 + static_cast<int>(rng() % 1200), h = 400 + static_cast<int>(rng() % 800);
    const std::string svg = ui::figure_svg(f, w, h);
    Element root;
    ASSERT_NO_THROW(root = Parser{svg}.document()) << svg.substr(0, 400);
    EXPECT_EQ(root.name, "svg");
    EXPECT_EQ(root.attr.at("width"), std::to_string(w));
    EXPECT_TRUE(has_text(root, f.title));
    EXPECT_TRUE(has_text(root, "x [\xC2\xB5m]")) << "um written as µm, as in the window";
    EXPECT_TRUE(has_text(root, "F_f [N]"));
    std::vector<const Element*> groups;
    for (const Element* g : all(root, "g"))
      if (g->attr.count("class") && g->attr.at("class") == "panel") groups.push_back(g);
    ASSERT_EQ(groups.size(), f.panels.size());
    for (std::size_t k = 0; k < f.panels.size(); ++k) {
      const Element& g = *groups[k];
      const double x0 = attr(g, "data-x0"), x1 = attr(g, "data-x1"), y0 = attr(g, "data-y0"), y1 = attr(g, "data-y1");
      const double px0 = attr(g, "data-px0"), px1 = attr(g, "data-px1"), py0 = attr(g, "data-py0"), py1 = attr(g, "data-py1");
      ASSERT_GT(px1, px0);
      ASSERT_GT(py1, py0);
      EXPECT_LE(px1, w);
      EXPECT_LE(py1, h);
      const auto lines = all(g, "polyline");
      ASSERT_EQ(lines.size(), f.panels[k].series.size());
      for (std::size_t j = 0; j < lines.size(); ++j) {
        const Series& s = f.panels[k].series[j];
        EXPECT_EQ(lines[j]->attr.at("data-series"), s.label);
        EXPECT_TRUE(has_text(g, s.label)) << "legend label as text";
        std::istringstream pts(lines[j]->attr.at("points"));
        std::string pair;
        std::size_t i = 0;
        while (pts >> pair) {
          ASSERT_LT(i, s.x.size());
          const double px = std::stod(pair.substr(0, pair.find(','))), py = std::stod(pair.substr(pair.find(',') + 1));
          // Inverse of the panel's map, within the 0.01 px (+ rounding) of the written coordinates.
          const double tol_x = 0.006 * (x1 - x0) / (px1 - px0), tol_y = 0.006 * (y1 - y0) / (py1 - py0);
          EXPECT_NEAR(x0 + (px - px0) / (px1 - px0) * (x1 - x0), s.x[i], tol_x);
          EXPECT_NEAR(y0 + (py1 - py) / (py1 - py0) * (y1 - y0), s.y[i], tol_y);
          // Every point inside the plot box (the ranges cover the data).
          EXPECT_GE(px, px0 - 1e-9);
          EXPECT_LE(px, px1 + 1e-9);
          ++i;
        }
        EXPECT_EQ(i, s.x.size()) << "one unbroken polyline with every point";
        const std::string dash = lines[j]->attr.count("stroke-dasharray") ? "dashed" : "solid";
        EXPECT_EQ(dash == "solid", s.style == Series::Style::Solid);
      }
    }
  }
}

#ifdef GMSLAB_HEADLESS_EXE
TEST(FigureSvg, FiguresAndRenderCommandsWriteSvgFromTheFigureData) {
  const fs::path dir = fs::temp_directory_path() / ("gmslab_svg_" + std::to_string(getpid()));
  fs::remove_all(dir);
  const std::string cmd = std::string(GMSLAB_HEADLESS_EXE) + " figures --only fig2a_presliding --format both --size 800x500 --out " +
                          dir.string() + " >" + (dir.string() + ".out") + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  ASSERT_TRUE(fs::exists(dir / "fig2a_presliding.png"));
  ASSERT_TRUE(fs::exists(dir / "fig2a_presliding.svg"));
  std::ifstream in(dir / "fig2a_presliding.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)), {});
  const Element root = Parser{svg}.document();
  const Figure f = make_figure("fig2a_presliding", std::string(GMSLAB_SOURCE_DIR) + "/presets");
  EXPECT_EQ(svg, ui::figure_svg(f, 800, 500)) << "the command writes the figure's own SVG";
  EXPECT_TRUE(has_text(root, f.title));
  std::ifstream out(dir.string() + ".out");
  const std::string listed((std::istreambuf_iterator<char>(out)), {});
  EXPECT_NE(listed.find("fig2a_presliding.svg"), std::string::npos) << "results on stdout: " << listed;
  // render --format svg: the simulation's four plots.
  const std::string r = (dir / "sim.svg").string();
  const std::string cmd2 = std::string(GMSLAB_HEADLESS_EXE) + " render " + GMSLAB_SOURCE_DIR +
                           "/presets/fig4_stick_slip.json --format svg --size 1280x720 --out " + r + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd2.c_str()), 0) << cmd2;
  std::ifstream in2(r);
  const std::string svg2((std::istreambuf_iterator<char>(in2)), {});
  const Element root2 = Parser{svg2}.document();
  EXPECT_EQ(all(root2, "polyline").size(), 4u);
  EXPECT_TRUE(has_text(root2, "v [mm/s]"));
  fs::remove_all(dir);
  fs::remove(dir.string() + ".out");
}
#endif

// Comparison figures share one y scale: every panel of a shared_y figure (random data, fixed seed)
// gets the same y range, covering all panels' data; the model comparisons of the figure set are
// such figures.
TEST(FigureSvg, SharedYScaleGivesEveryPanelTheSameRange) {
  std::mt19937 rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    Figure f = random_figure(rng);
    if (f.panels.size() < 2) f.panels.push_back(f.panels[0]), f.panels.back().series[0].y[0] *= 7.0;
    f.shared_y = true;
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : f.panels)
      for (const auto& s : p.series)
        for (double v : s.y) lo = std::min(lo, v), hi = std::max(hi, v);
    const Element root = Parser{ui::figure_svg(f, 1200, 700)}.document();
    std::vector<const Element*> groups;
    for (const Element* g : all(root, "g"))
      if (g->attr.count("class") && g->attr.at("class") == "panel") groups.push_back(g);
    ASSERT_EQ(groups.size(), f.panels.size());
    for (const Element* g : groups) {
      EXPECT_DOUBLE_EQ(attr(*g, "data-y0"), attr(*groups[0], "data-y0"));
      EXPECT_DOUBLE_EQ(attr(*g, "data-y1"), attr(*groups[0], "data-y1"));
      EXPECT_LE(attr(*g, "data-y0"), lo);
      EXPECT_GE(attr(*g, "data-y1"), hi);
    }
  }
  for (const char* id : {"compare_fig2a_presliding", "compare_fig2b_frictional_lag", "compare_fig2c_periodic_sliding"})
    EXPECT_TRUE(make_figure(id, std::string(GMSLAB_SOURCE_DIR) + "/presets").shared_y) << id;
}

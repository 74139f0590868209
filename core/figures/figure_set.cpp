#include "core/figures/figure_set.hpp"

#include <iomanip>

#include "core/error.hpp"
#include "core/io/scenario_io.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {

std::vector<std::string> figure_ids() { return {"fig2a_presliding", "fig4_stick_slip"}; }

namespace {
Figure fig2a(const std::string& dir) {
  const Trace tr = simulate(load_scenario(dir + "/fig2a_presliding.json"));
  Series s{"GMS", {}, {}, Series::Style::Solid, 0};
  for (std::size_t k = 0; k < tr.size(); ++k) {
    s.x.push_back(tr.x[k] * 1e6);
    s.y.push_back(tr.friction[k]);
  }
  return {"fig2a_presliding", "Seed Fig. 2A - presliding hysteresis with nonlocal memory",
          "Imposed displacement 0 -> 15 -> -15 -> 8 -> -3 -> 8 -> 15 -> -15 um at 10 um/s. The "
          "inner loop closes at 8 um and the curve rejoins the outer branch.",
          {{"A", "Presliding hysteresis", "x [um]", "F_f [N]", {s}}}};
}

Figure fig4(const std::string& dir) {
  const Trace tr = simulate(load_scenario(dir + "/fig4_stick_slip.json"));
  Series x{"position x", {}, {}, Series::Style::Solid, 0};
  Series v{"velocity v", {}, {}, Series::Style::Dashed, 1};
  Series ff{"friction force", {}, {}, Series::Style::Solid, 0};
  Series fs{"spring force", {}, {}, Series::Style::Dashed, 1};
  for (std::size_t k = 0; k < tr.size(); ++k) {
    x.x.push_back(tr.t[k]);
    x.y.push_back(tr.x[k]);
    v.x.push_back(tr.t[k]);
    v.y.push_back(tr.v[k]);
    ff.x.push_back(tr.t[k]);
    ff.y.push_back(tr.friction[k]);
    fs.x.push_back(tr.t[k]);
    fs.y.push_back(tr.applied[k]);
  }
  return {"fig4_stick_slip", "Seed Fig. 4 - stick-slip",
          "A 1 kg mass pulled through a 2 N/m spring at 0.1 m/s. Each stick is preceded by a force "
          "spike and followed by a damped high-frequency vibration.",
          {{"a", "Position [m] and velocity [m/s]", "t [s]", "x [m], v [m/s]", {x, v}},
           {"b", "Friction and spring force", "t [s]", "F [N]", {ff, fs}}}};
}
}  // namespace

Figure make_figure(const std::string& id, const std::string& preset_dir) {
  if (id == "fig2a_presliding") return fig2a(preset_dir);
  if (id == "fig4_stick_slip") return fig4(preset_dir);
  std::string known;
  for (const auto& i : figure_ids()) known += (known.empty() ? "" : ", ") + i;
  throw InputError("unknown figure '" + id + "' (known: " + known + ")");
}

void write_figure_csv(const Figure& f, std::ostream& out) {
  out << "panel,series,x,y\n";
  out << std::setprecision(10);
  for (const auto& p : f.panels) {
    out << "# panel " << p.letter << ": x = " << p.x_label << ", y = " << p.y_label << '\n';
    for (const auto& s : p.series)
      for (std::size_t k = 0; k < s.x.size(); ++k)
        out << p.letter << ',' << s.label << ',' << s.x[k] << ',' << s.y[k] << '\n';
  }
}

}  // namespace gmslab

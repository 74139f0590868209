// gmslab core: a paper-style figure as data (no drawing). core/figures builds them by running
// scenarios; ui/ draws them (the same widget as the live plots); `gmslab figures` writes each as PNG
// plus its series as CSV, so a figure can be re-plotted elsewhere.
#pragma once

#include <string>
#include <vector>

namespace gmslab {

struct Series {
  enum class Style { Solid, Dashed, Dotted };
  std::string label;          // legend text, e.g. "x16 a0"
  std::vector<double> x, y;   // data in the units of the panel's axis labels
  Style style = Style::Solid;
  int color = -1;             // palette index; -1 = by position
};

struct Panel {
  std::string letter;    // panel letter as in the paper, e.g. "A"
  std::string title;     // e.g. "Presliding hysteresis (nonlocal memory)"
  std::string x_label;   // with unit, e.g. "x [um]"
  std::string y_label;   // with unit, e.g. "F_f [N]"
  std::vector<Series> series;
};

struct Figure {
  std::string id;       // file stem, e.g. "fig2a_presliding"
  std::string title;    // e.g. "Seed Fig. 2A - GMS presliding hysteresis"
  std::string caption;  // what it shows and what to look for
  std::vector<Panel> panels;  // laid out left to right
  bool shared_y = false;      // every panel on one y scale (comparisons where magnitudes matter)
};

}  // namespace gmslab

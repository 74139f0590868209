// gmslab core: the figure set that `gmslab figures` renders. Each figure is built by running its
// preset(s) (presets/*.json) and extracting the series the paper plots. Comparison figures run the
// same presets with the friction replaced by another model's defaults (model_info(tag).defaults():
// LuGre Table I, the Maxwell-slip / Leuven sets built on the GMS reference elements, ...).
//
// Seed figures (Al-Bender, Lampaert, Swevers 2005), GMS reference set:
//   fig2a_presliding       A  F_f [N] vs x [um]: hysteresis with nonlocal memory
//   fig2b_frictional_lag   B  F_f [N] vs v [mm/s]: dashed a0, solid x16, dotted x100 (last cycle)
//   fig2c_periodic_sliding C  F_f [N] vs x [mm] and vs v [mm/s]: 0.1 Hz solid, 1 Hz dotted
//   fig2d_nondrifting      D  x [mm] vs t [s] and the drift x - x(2 s) [um] after the mass stopped
//   fig2_gms               the four panels A-D together, as the seed's Fig. 2
//   fig4_stick_slip        a  x, v with the desired x_p, v_p dotted; b  friction and spring force
// Comparisons (same protocols, other models):
//   compare_fig2a_presliding, compare_fig2b_frictional_lag, compare_fig2c_periodic_sliding,
//   compare_fig2d_drift, compare_fig4_stick_slip
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "core/figures/figure.hpp"

namespace gmslab {

// Ids of every figure, in display order (e.g. "fig2a_presliding").
std::vector<std::string> figure_ids();
// Builds one figure; presets are read from `preset_dir`. Throws InputError for an unknown id or a
// bad preset (naming the file and key).
Figure make_figure(const std::string& id, const std::string& preset_dir);
// All series of a figure in long form, one header line and no comment lines (a plain
// pandas.read_csv or MATLAB readtable reads it): "panel,series,x,y,x_label,y_label", one row per
// point, each with its panel's axis labels and units ("t [s]", "x [um]": the micro prefix as u). A
// field with a comma or quote is quoted (RFC 4180). 10 significant digits.
void write_figure_csv(const Figure& f, std::ostream& out);

}  // namespace gmslab

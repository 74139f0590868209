// gmslab Python module: the paper's figures as data (figure_ids, figure).
#include "app/python/bindings.hpp"
#include "core/figures/figure_set.hpp"

namespace gmslab::py_bindings {

using namespace pybind11::literals;
void bind_figures(py::module_& m) {
  m.def("figure_ids", &figure_ids, "Ids of the paper's figures, e.g. 'fig2a_presliding'");
  m.def(
      "figure",
      [](const std::string& id) {
        Figure f;
        const std::string presets = preset_dir();
        {
          py::gil_scoped_release nogil;
          f = make_figure(id, presets);
        }
        py::list panels;
        for (const auto& p : f.panels) {
          py::list series;
          for (const auto& s : p.series) {
            py::dict sd;
            sd["label"] = s.label;
            sd["x"] = arr(s.x);
            sd["y"] = arr(s.y);
            sd["style"] = s.style == Series::Style::Solid    ? "solid"
                          : s.style == Series::Style::Dashed ? "dashed"
                                                             : "dotted";
            series.append(sd);
          }
          py::dict pd;
          pd["letter"] = p.letter, pd["title"] = p.title, pd["x_label"] = p.x_label,
          pd["y_label"] = p.y_label;
          pd["series"] = series;
          panels.append(pd);
        }
        py::dict d;
        d["id"] = f.id, d["title"] = f.title, d["caption"] = f.caption, d["panels"] = panels;
        return d;
      },
      py::arg("id"),
      "One of the paper's figures as data: id, title, caption, panels [{letter, title, x_label, "
      "y_label "
      "(with units), series [{label, x, y, style}]}]");
}

}  // namespace gmslab::py_bindings

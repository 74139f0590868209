// gmslab identification: a Figure (core/figures/figure.hpp) as JSON, so a process without GL can
// hand a figure to the headless renderer (gmslab identify --plot). Generic: any Figure.
//   {"id", "title", "caption", "panels": [{"letter", "title", "x_label", "y_label",
//     "series": [{"label", "style": "solid|dashed|dotted", "color", "x": [...], "y": [...]}]}]}
// Reading is strict (JsonReader): unknown keys, wrong types, x/y of different lengths are
// InputErrors naming the file and key.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/figures/figure.hpp"

namespace gmslab {

nlohmann::json figure_to_json(const Figure& f);
Figure figure_from_json(const nlohmann::json& j, const std::string& file);
void save_figure_json(const Figure& f, const std::string& path);  // atomic
Figure load_figure_json(const std::string& path);

}  // namespace gmslab

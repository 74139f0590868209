#include "core/ident/figure_json.hpp"

#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"

namespace gmslab {

namespace {
const char* style_name(Series::Style s) {
  switch (s) {
    case Series::Style::Dashed: return "dashed";
    case Series::Style::Dotted: return "dotted";
    default: return "solid";
  }
}
}  // namespace

nlohmann::json figure_to_json(const Figure& f) {
  nlohmann::json j{{"id", f.id}, {"title", f.title}, {"caption", f.caption}};
  nlohmann::json panels = nlohmann::json::array();
  for (const auto& p : f.panels) {
    nlohmann::json series = nlohmann::json::array();
    for (const auto& s : p.series)
      series.push_back({{"label", s.label}, {"style", style_name(s.style)}, {"color", s.color},
                        {"x", s.x}, {"y", s.y}});
    panels.push_back({{"letter", p.letter}, {"title", p.title}, {"x_label", p.x_label},
                      {"y_label", p.y_label}, {"series", series}});
  }
  j["panels"] = panels;
  return j;
}

Figure figure_from_json(const nlohmann::json& j, const std::string& file) {
  JsonReader r(j, file);
  Figure f;
  f.id = r.string("id");
  f.title = r.string("title");
  f.caption = r.opt_string("caption", "");
  for (auto& pr : r.array_of_objects("panels", 1, 16)) {
    Panel p;
    p.letter = pr.opt_string("letter", "");
    p.title = pr.opt_string("title", "");
    p.x_label = pr.string("x_label");
    p.y_label = pr.string("y_label");
    for (auto& sr : pr.array_of_objects("series", 0, 64)) {
      Series s;
      s.label = sr.opt_string("label", "");
      if (sr.has("style")) {
        const auto st = sr.choice("style", {"solid", "dashed", "dotted"});
        s.style = st == "dashed" ? Series::Style::Dashed
                  : st == "dotted" ? Series::Style::Dotted
                                   : Series::Style::Solid;
      }
      if (sr.has("color")) s.color = static_cast<int>(sr.integer("color", -1, 255));
      s.x = sr.numbers("x", 0, 10'000'000);
      s.y = sr.numbers("y", 0, 10'000'000);
      if (s.x.size() != s.y.size())
        sr.fail("y", "has " + std::to_string(s.y.size()) + " values but x has " +
                         std::to_string(s.x.size()) + "; they must match");
      sr.finish();
      p.series.push_back(std::move(s));
    }
    pr.finish();
    f.panels.push_back(std::move(p));
  }
  r.finish();
  return f;
}

void save_figure_json(const Figure& f, const std::string& path) {
  write_file_atomic(path, figure_to_json(f).dump() + "\n");
}

Figure load_figure_json(const std::string& path) {
  return figure_from_json(parse_json(read_file(path), path), path);
}

}  // namespace gmslab

#include "ui/figures/figure_export.hpp"

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/figures/figure_set.hpp"
#include "core/io/atomic_file.hpp"
#include "ui/figures/figure_svg.hpp"

namespace gmslab::ui {

namespace fs = std::filesystem;

std::string export_dir() {
  if (const char* d = std::getenv("GMSLAB_EXPORT_DIR"); d && *d) return d;
  const char* home = std::getenv("HOME");
  return std::string(home && *home ? home : ".") + "/gmslab-exports";
}

std::string fresh_export_path(const std::string& name, const std::string& extension) {
  std::string stem;
  for (char c : name) stem += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  while (stem.find("__") != std::string::npos) stem.erase(stem.find("__"), 1);
  if (stem.empty()) stem = "plot";
  const fs::path dir = export_dir();
  fs::path p = dir / (stem + extension);
  for (int k = 2; fs::exists(p); ++k) p = dir / (stem + "-" + std::to_string(k) + extension);
  return p.string();
}

std::string export_figure(const Figure& f, ExportFormat format, const PngWriter& png) {
  constexpr int kW = 1600, kH = 1000;
  try {
    fs::create_directories(export_dir());
    const std::string name = f.id.empty() ? f.title : f.id;
    std::string path;
    switch (format) {
      case ExportFormat::Svg:
        path = fresh_export_path(name, ".svg");
        write_figure_svg(f, kW, kH, path);
        break;
      case ExportFormat::Csv: {
        path = fresh_export_path(name, ".csv");
        std::ostringstream csv;
        write_figure_csv(f, csv);
        write_file_atomic(path, csv.str());
        break;
      }
      case ExportFormat::Png:
        if (!png) return "export failed: PNG export is not available here (use SVG)";
        path = fresh_export_path(name, ".png");
        png(f, path);
        break;
    }
    return "wrote " + path;
  } catch (const std::exception& e) {
    return std::string("export failed: ") + e.what();
  }
}

}  // namespace gmslab::ui

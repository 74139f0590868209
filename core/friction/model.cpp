#include "core/friction/model.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"

namespace gmslab {

namespace {
std::string fmt(double x) {
  std::ostringstream o;
  o << x;
  return o.str();
}
}  // namespace

bool ParamSpec::allowed(double x) const {
  if (!std::isfinite(x)) return false;
  if (lo_open ? !(x > lo) : !(x >= lo)) return false;
  return x <= hi;
}

std::string ParamSpec::range_text() const {
  std::string r = (lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
  if (unit != "-") r += " " + std::string(unit);
  return r;
}

std::ptrdiff_t ModelInfo::scalar_index(std::string_view key) const {
  for (std::size_t i = 0; i < scalars.size(); ++i)
    if (scalars[i].key == key) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

std::ptrdiff_t ModelInfo::column_index(std::string_view key) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i].key == key) return static_cast<std::ptrdiff_t>(i);
  return -1;
}

namespace {
// "model 'gms' has no scalar parameter 'X' (its scalars: Fs, Fc, ...)".
[[noreturn]] void no_key(const std::string& model, const char* what, std::string_view key) {
  std::string known;
  const ModelInfo& info = model_info(model);
  if (std::string_view(what) == "scalar parameter")
    for (const auto& s : info.scalars) known += (known.empty() ? "" : ", ") + std::string(s.key);
  else
    for (const auto& c : info.columns) known += (known.empty() ? "" : ", ") + std::string(c.key);
  throw InputError("model '" + model + "' has no " + what + " '" + std::string(key) + "' (its keys: " + known + ")");
}
}  // namespace

double ModelParams::scalar(std::string_view key) const {
  const auto i = model_info(model).scalar_index(key);
  if (i < 0 || static_cast<std::size_t>(i) >= scalars.size()) no_key(model, "scalar parameter", key);
  return scalars[static_cast<std::size_t>(i)];
}

void ModelParams::set_scalar(std::string_view key, double value) {
  const auto i = model_info(model).scalar_index(key);
  if (i < 0 || static_cast<std::size_t>(i) >= scalars.size()) no_key(model, "scalar parameter", key);
  scalars[static_cast<std::size_t>(i)] = value;
}

std::vector<double> ModelParams::column(std::string_view key) const {
  const auto c = model_info(model).column_index(key);
  if (c < 0) no_key(model, "element column", key);
  std::vector<double> out;
  out.reserve(elements.size());
  for (const auto& row : elements) {
    if (static_cast<std::size_t>(c) >= row.size())
      throw InputError("model '" + model + "': an element row has " + std::to_string(row.size()) +
                       " values, fewer than its columns");
    out.push_back(row[static_cast<std::size_t>(c)]);
  }
  return out;
}

const ModelInfo& model_info(std::string_view tag) {
  for (const auto& m : model_registry())
    if (m.tag == tag) return m;
  std::string known;
  for (const auto& m : model_registry()) known += (known.empty() ? "" : ", ") + std::string(m.tag);
  throw InputError("unknown friction model '" + std::string(tag) + "' (known models: " + known +
                   ")");
}

std::vector<std::string> validate(const ModelParams& p, std::string_view where) {
  std::vector<std::string> out;
  const ModelInfo* info = nullptr;
  for (const auto& m : model_registry())
    if (m.tag == p.model) info = &m;
  if (!info) {
    try {
      model_info(p.model);
    } catch (const InputError& e) {
      out.push_back(std::string(where) + ".model: " + e.what());
    }
    return out;
  }
  const std::string w(where);
  if (p.scalars.size() != info->scalars.size()) {
    out.push_back(w + ": expected " + std::to_string(info->scalars.size()) +
                  " scalar parameters, got " + std::to_string(p.scalars.size()));
    return out;
  }
  for (std::size_t i = 0; i < p.scalars.size(); ++i) {
    const auto& s = info->scalars[i];
    if (!s.allowed(p.scalars[i]))
      out.push_back(w + "." + std::string(s.key) + ": " + fmt(p.scalars[i]) +
                    " is outside the allowed range " + s.range_text() + " (" +
                    std::string(s.help) + ")");
  }
  const std::size_t n = p.elements.size();
  if (!info->columns.empty() || n > 0) {
    if (n < info->min_elements || n > info->max_elements)
      out.push_back(w + ".elements: " + std::to_string(n) + " elements; model '" + p.model +
                    "' takes " + std::to_string(info->min_elements) + " to " +
                    std::to_string(info->max_elements));
    for (std::size_t r = 0; r < n; ++r) {
      if (p.elements[r].size() != info->columns.size()) {
        out.push_back(w + ".elements[" + std::to_string(r) + "]: expected " +
                      std::to_string(info->columns.size()) + " values");
        continue;
      }
      for (std::size_t c = 0; c < info->columns.size(); ++c) {
        const auto& s = info->columns[c];
        if (!s.allowed(p.elements[r][c]))
          out.push_back(w + ".elements[" + std::to_string(r) + "]." + std::string(s.key) + ": " +
                        fmt(p.elements[r][c]) + " is outside the allowed range " +
                        s.range_text() + " (" + std::string(s.help) + ")");
      }
    }
  }
  if (out.empty() && info->check) {
    std::vector<std::string> cross;
    info->check(p, cross);
    for (auto& c : cross) out.push_back(w + ": " + c);
  }
  return out;
}

std::unique_ptr<FrictionModel> build_model(const ModelParams& p) {
  const auto problems = validate(p);
  if (!problems.empty()) {
    std::string msg = "invalid friction parameters:";
    for (const auto& m : problems) msg += "\n  " + m;
    throw InputError(msg);
  }
  return model_info(p.model).build(p);
}

}  // namespace gmslab

#include "core/io/measured_file.hpp"

#include <matio.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <memory>

#include "core/error.hpp"
#include "core/io/trace_file.hpp"

namespace gmslab {

namespace {

// matio reports problems through a log function; the loader reports them as InputError instead.
void quiet_log(int, char*) {}

struct MatCloser {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
struct VarFree {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};

template <typename T>
void copy_values(const matvar_t* v, std::size_t n, std::vector<double>& out) {
  const T* p = static_cast<const T*>(v->data);
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(p[i]);
}

// All values of a real numeric variable as doubles (column-major); false for other classes.
bool numeric_values(const matvar_t* v, std::size_t n, std::vector<double>& out) {
  if (!v->data) return false;
  switch (v->class_type) {
    case MAT_C_DOUBLE: copy_values<double>(v, n, out); return true;
    case MAT_C_SINGLE: copy_values<float>(v, n, out); return true;
    case MAT_C_INT8: copy_values<std::int8_t>(v, n, out); return true;
    case MAT_C_UINT8: copy_values<std::uint8_t>(v, n, out); return true;
    case MAT_C_INT16: copy_values<std::int16_t>(v, n, out); return true;
    case MAT_C_UINT16: copy_values<std::uint16_t>(v, n, out); return true;
    case MAT_C_INT32: copy_values<std::int32_t>(v, n, out); return true;
    case MAT_C_UINT32: copy_values<std::uint32_t>(v, n, out); return true;
    case MAT_C_INT64: copy_values<std::int64_t>(v, n, out); return true;
    case MAT_C_UINT64: copy_values<std::uint64_t>(v, n, out); return true;
    default: return false;
  }
}

const char* class_name(matio_classes c) {
  switch (c) {
    case MAT_C_CELL: return "cell";
    case MAT_C_STRUCT: return "struct";
    case MAT_C_OBJECT: return "object";
    case MAT_C_CHAR: return "char";
    case MAT_C_SPARSE: return "sparse";
    case MAT_C_FUNCTION: return "function";
    case MAT_C_OPAQUE: return "opaque";
    default: return "numeric";
  }
}

}  // namespace

bool is_mat_file(const std::string& path) {
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".mat") return true;
  std::ifstream f(path, std::ios::binary);
  char head[6] = {};
  return f.read(head, 6) && std::string(head, 6) == "MATLAB";
}

namespace {
// The numeric columns of a MATLAB file, and what it holds that is not one ("s (struct)").
std::vector<NamedColumn> mat_columns(const std::string& path, std::string& unusable);
}  // namespace

std::vector<NamedColumn> load_mat_columns(const std::string& path) {
  std::string unusable;
  auto cols = mat_columns(path, unusable);
  if (cols.empty())
    throw InputError(path + ": no numeric vector or matrix variable" +
                     (unusable.empty() ? std::string() : " (not usable: " + unusable + ")"));
  return cols;
}

MeasuredRecord load_measured_mat(const std::string& path, const CsvColumns& columns) {
  std::string unusable;
  const auto cols = mat_columns(path, unusable);
  return record_from_columns(cols, columns, path, unusable);
}

namespace {
std::vector<NamedColumn> mat_columns(const std::string& path, std::string& unusable) {
  static const int log_init = Mat_LogInitFunc("gmslab", quiet_log);
  (void)log_init;
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw InputError(path + ": cannot open the file (does it exist, is it readable?)");
  }
  std::unique_ptr<mat_t, MatCloser> mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!mat)
    throw InputError(path + ": not a MATLAB file that can be read; accepted: MAT-files version 4, "
                            "5/7 and 7.3 (HDF5) holding numeric vectors or matrices");
  std::vector<NamedColumn> cols;
  std::vector<double> all;
  for (;;) {
    std::unique_ptr<matvar_t, VarFree> v(Mat_VarReadNext(mat.get()));
    if (!v) break;
    const std::string name = v->name ? v->name : "?";
    const bool numeric = v->rank == 2 && !v->isComplex && v->class_type != MAT_C_SPARSE;
    const std::size_t rows = v->rank >= 1 ? v->dims[0] : 0, cols_n = v->rank >= 2 ? v->dims[1] : 0;
    const std::size_t n = rows * cols_n;
    if (!numeric || n == 0 || !numeric_values(v.get(), n, all)) {
      std::string why = v->isComplex ? "complex"
                        : v->rank != 2 ? std::to_string(v->rank) + "-D"
                        : n == 0       ? "empty"
                                       : class_name(v->class_type);
      unusable += (unusable.empty() ? "" : ", ") + name + " (" + why + ")";
      continue;
    }
    if (rows == 1 || cols_n == 1) {
      cols.push_back({name, all});
    } else {
      for (std::size_t c = 0; c < cols_n; ++c)
        cols.push_back({name + ":" + std::to_string(c + 1),
                        std::vector<double>(all.begin() + static_cast<std::ptrdiff_t>(c * rows),
                                            all.begin() + static_cast<std::ptrdiff_t>((c + 1) * rows))});
    }
  }
  return cols;
}
}  // namespace

MeasuredRecord load_measured(const std::string& path, const CsvColumns& columns) {
  if (is_mat_file(path)) return load_measured_mat(path, columns);
  if (is_hdf5_file(path)) return record_from_columns(load_hdf5_columns(path), columns, path);
  return load_measured_csv(path, columns);
}

}  // namespace gmslab

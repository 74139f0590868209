#include "core/io/trace_csv.hpp"

#include <cstdio>
#include <sstream>

#include "core/io/atomic_file.hpp"

namespace gmslab {

void write_trace_csv(const Trace& tr, std::ostream& out) {
  const std::size_t ne = tr.element_force.size() == tr.size() * tr.n_elements ? tr.n_elements : 0;
  out << "t_s,x_m,v_mps,F_friction_N,F_applied_N";
  for (std::size_t i = 0; i < ne; ++i) out << ",F" << i + 1 << "_N";
  for (std::size_t i = 0; i < ne; ++i) out << ",slip" << i + 1;
  out << '\n';
  char buf[64];
  auto put = [&](double x) {
    const int n = std::snprintf(buf, sizeof buf, "%.10g", x);
    out.write(buf, n);
  };
  for (std::size_t k = 0; k < tr.size(); ++k) {
    put(tr.t[k]);
    for (double x : {tr.x[k], tr.v[k], tr.friction[k], tr.applied[k]}) {
      out << ',';
      put(x);
    }
    for (std::size_t i = 0; i < ne; ++i) {
      out << ',';
      put(tr.element_force[k * ne + i]);
    }
    for (std::size_t i = 0; i < ne; ++i) out << ',' << int(tr.element_slip[k * ne + i]);
    out << '\n';
  }
}

void save_trace_csv(const Trace& tr, const std::string& path) {
  std::ostringstream ss;
  write_trace_csv(tr, ss);
  write_file_atomic(path, ss.str());
}

}  // namespace gmslab

// gmslab core: a simulation trace as CSV, header with units:
//   t_s,x_m,v_mps,F_friction_N,F_applied_N[,F1_N,...,FN_N,slip1,...,slipN]
#pragma once

#include <ostream>
#include <string>

#include "core/sim/simulation.hpp"

namespace gmslab {

void write_trace_csv(const Trace& tr, std::ostream& out);
void save_trace_csv(const Trace& tr, const std::string& path);  // atomic

}  // namespace gmslab

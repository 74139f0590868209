// gmslab core: a simulation trace as CSV, header with units:
//   t_s,x_m,v_mps,F_friction_N,F_applied_N[,F1_N,...,FN_N,slip1,...,slipN]
// Numbers are written as printf's %.10g writes them (core/text/format_g10.hpp, byte for byte).
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <string_view>

#include "core/sim/simulation.hpp"

namespace gmslab {

void write_trace_csv(const Trace& tr, std::ostream& out);
void save_trace_csv(const Trace& tr, const std::string& path);  // atomic

// The element columns a trace's CSV has: n_elements when every sample has them, else 0.
std::size_t trace_csv_elements(const Trace& tr);
// Appends the header line for `n_elements` element columns, and the rows of every sample of `tr`
// (with `n_elements` element columns, which must be trace_csv_elements(tr) or 0).
void append_trace_csv_header(std::size_t n_elements, std::string& out);
void append_trace_csv_rows(const Trace& tr, std::size_t n_elements, std::string& out);

// Simulates `scenario` and streams its trace as CSV into `sink` as it goes, a chunk of 16384
// samples at a time: memory stays constant (the chunk being simulated, and three chunks of samples
// with room for their text: one being formatted here, one waiting, one being formatted and written
// by the second thread) whatever the length of the run. Both threads format: this one the rows of
// its newest chunk while the second thread still has an earlier chunk waiting, the second thread
// the rest, and it passes the text to `sink` (the header on the calling thread first; one call at a
// time, in order; the text is that of doing it all in turn). Returns the number of samples
// written. Throws what the simulation throws (InputError, SimulationError); the samples of the
// chunks before a divergence have been passed to the sink by then, and what `sink` throws.
std::size_t stream_trace_csv(const Scenario& scenario, const std::function<void(std::string_view)>& sink);
// The same into a file, atomically: the text streams to a temporary file beside `path`, renamed
// over it once the run is complete (a failed run leaves `path` as it was).
std::size_t save_trace_csv_streamed(const Scenario& scenario, const std::string& path);

}  // namespace gmslab

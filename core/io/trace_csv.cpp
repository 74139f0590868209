#include "core/io/trace_csv.hpp"

#include <charconv>

#include "core/io/atomic_file.hpp"
#include "core/sim/assembly.hpp"

namespace gmslab {

namespace {
// %.10g (std::to_chars in general format with a precision is specified as printf's %.*g).
inline void put(double x, std::string& out) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, 10);
  out.append(buf, r.ptr);
}
}  // namespace

std::size_t trace_csv_elements(const Trace& tr) {
  return tr.element_force.size() == tr.size() * tr.n_elements && tr.element_slip.size() == tr.size() * tr.n_elements
             ? tr.n_elements
             : 0;
}

void append_trace_csv_header(std::size_t ne, std::string& out) {
  out += "t_s,x_m,v_mps,F_friction_N,F_applied_N";
  for (std::size_t i = 0; i < ne; ++i) out += ",F" + std::to_string(i + 1) + "_N";
  for (std::size_t i = 0; i < ne; ++i) out += ",slip" + std::to_string(i + 1);
  out += '\n';
}

void append_trace_csv_rows(const Trace& tr, std::size_t ne, std::string& out) {
  for (std::size_t k = 0; k < tr.size(); ++k) {
    put(tr.t[k], out);
    for (double x : {tr.x[k], tr.v[k], tr.friction[k], tr.applied[k]}) {
      out += ',';
      put(x, out);
    }
    for (std::size_t i = 0; i < ne; ++i) {
      out += ',';
      put(tr.element_force[k * ne + i], out);
    }
    for (std::size_t i = 0; i < ne; ++i) {
      out += ',';
      out += static_cast<char>('0' + tr.element_slip[k * ne + i]);
    }
    out += '\n';
  }
}

void write_trace_csv(const Trace& tr, std::ostream& out) {
  const std::size_t ne = trace_csv_elements(tr);
  std::string text;
  append_trace_csv_header(ne, text);
  append_trace_csv_rows(tr, ne, text);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

void save_trace_csv(const Trace& tr, const std::string& path) {
  const std::size_t ne = trace_csv_elements(tr);
  std::string text;
  append_trace_csv_header(ne, text);
  append_trace_csv_rows(tr, ne, text);
  write_file_atomic(path, text);
}

std::size_t stream_trace_csv(const Scenario& scenario, const std::function<void(std::string_view)>& sink) {
  constexpr std::size_t kChunkSamples = 1u << 14;
  AssemblySimulation sim = one_body_simulation(scenario, TraceOptions{.max_bytes = 0, .reserve_samples = kChunkSamples + 2});
  // Every sample has its element columns (the run has no live edits), so the header is known now.
  const std::size_t ne = sim.one_body_trace().n_elements;
  std::string text;
  append_trace_csv_header(ne, text);
  std::size_t written = 0;
  const auto chunk_steps = kChunkSamples * static_cast<std::size_t>(scenario.run.record_every);
  auto drain = [&] {
    append_trace_csv_rows(sim.one_body_trace(), ne, text);
    written += sim.one_body_trace().size();
    sim.clear_trace();
    sink(text);
    text.clear();
  };
  while (!sim.finished()) {
    sim.advance(chunk_steps);
    drain();
  }
  if (sim.one_body_trace().size() > 0 || !text.empty()) drain();  // a run of zero steps: its first sample
  return written;
}

std::size_t save_trace_csv_streamed(const Scenario& scenario, const std::string& path) {
  AtomicFileWriter file(path);
  const std::size_t n = stream_trace_csv(scenario, [&](std::string_view s) { file.write(s); });
  file.commit();
  return n;
}

}  // namespace gmslab

#include "core/io/trace_csv.hpp"

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "core/io/atomic_file.hpp"
#include "core/io/handoff.hpp"
#include "core/sim/assembly.hpp"
#include "core/text/format_g10.hpp"

namespace gmslab {

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

namespace {

// Longest text of one row with `ne` element columns.
std::size_t row_room(std::size_t ne) { return (5 + ne) * (kFormatG10MaxChars + 1) + 2 * ne + 1; }

// The last value written in each number column (t, x, v, F_friction, F_applied, then the element
// forces): a value whose text is that of the value above it (it lies in that value's interval,
// format_g10_cached) is copied from the row above, not formatted. The row above is still in the
// buffer: a chunk's text is kept whole, and a block appended to the string is not cleared.
struct RowTexts {
  std::vector<G10Last> column;
  explicit RowTexts(std::size_t ne) : column(5 + ne) {}
};

// Writes row k of `tr` at `o` (room for row_room(ne) characters) and returns its end.
char* format_row(const Trace& tr, std::size_t k, std::size_t ne, RowTexts& texts, char* o) {
  G10Last* last = texts.column.data();
  o = format_g10_cached(tr.t[k], o, last[0]);
  for (double x : {tr.x[k], tr.v[k], tr.friction[k], tr.applied[k]}) {
    *o++ = ',';
    o = format_g10_cached(x, o, *++last);
  }
  for (std::size_t i = 0; i < ne; ++i) {
    *o++ = ',';
    o = format_g10_cached(tr.element_force[k * ne + i], o, *++last);
  }
  for (std::size_t i = 0; i < ne; ++i) {
    o[0] = ',';
    o[1] = static_cast<char>('0' + tr.element_slip[k * ne + i]);
    o += 2;
  }
  *o++ = '\n';
  return o;
}

}  // namespace

void append_trace_csv_rows(const Trace& tr, std::size_t ne, std::string& out) {
  // Rows are written in place into a block with room for 256 of their longest text (format_g10:
  // printf's %.10g), appended to `out` a block at a time.
  const std::size_t room = row_room(ne);
  std::vector<char> block(256 * room);
  char* const end = block.data() + block.size();
  char* o = block.data();
  out.reserve(out.size() + tr.size() * (6 + ne) * 12);
  RowTexts texts(ne);
  for (std::size_t k = 0; k < tr.size(); ++k) {
    if (static_cast<std::size_t>(end - o) < room) {
      out.append(block.data(), o);
      o = block.data();
    }
    o = format_row(tr, k, ne, texts, o);
  }
  out.append(block.data(), o);
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

namespace {

// A chunk of samples on its way to the sink, with the text of its first `formatted` rows.
struct CsvChunk {
  Trace samples;
  std::unique_ptr<char[]> text;  // room for every row; its first `used` characters are written
  std::size_t room = 0, used = 0, formatted = 0;
  RowTexts texts{0};  // of the rows formatted so far (by whichever thread)

  // Takes the samples `sim` recorded (exchanged with this chunk's former ones, whose memory the
  // simulation records into next: nothing is copied), none formatted yet.
  void take(AssemblySimulation& sim, std::size_t ne) {
    sim.hand_over_one_body_trace(samples);
    used = formatted = 0;
    texts = RowTexts(ne);
    const std::size_t need = samples.size() * row_room(ne);
    if (room < need) {  // uninitialised: only the pages written are ever touched
      text.reset(new char[need]);
      room = need;
    }
  }
  void format_until(std::size_t to, std::size_t ne) {
    char* const start = text.get();
    char* o = start + used;
    for (; formatted < to; ++formatted) o = format_row(samples, formatted, ne, texts, o);
    used = static_cast<std::size_t>(o - start);
  }
};

}  // namespace

std::size_t stream_trace_csv(const Scenario& scenario, const std::function<void(std::string_view)>& sink) {
  constexpr std::size_t kChunkSamples = 1u << 14;
  AssemblySimulation sim = one_body_simulation(scenario, TraceOptions{.max_bytes = 0, .reserve_samples = kChunkSamples + 2});
  // Every sample has its element columns (the run has no live edits), so the header is known now.
  const std::size_t ne = sim.one_body_trace().n_elements;
  std::string header;
  append_trace_csv_header(ne, header);
  sink(header);
  // The text is passed to the sink on a second thread (Handoff) while the next chunk is
  // simulated. Both threads format: the second one whatever the first has not, the first the rows
  // of its newest chunk while the second still has an earlier chunk waiting, so neither waits
  // while the other works. The sink sees the same text in the same order as without it.
  Handoff<CsvChunk> writer([&](CsvChunk& c) {
    c.format_until(c.samples.size(), ne);
    sink(std::string_view(c.text.get(), c.used));
  });
  std::size_t written = 0;
  CsvChunk next;
  auto hand_over = [&] {
    next.take(sim, ne);
    written += next.samples.size();
    const auto fill = [&](CsvChunk& slot) { std::swap(slot, next); };
    constexpr std::size_t kRowsPerTry = 256;  // rows formatted here between looks at the slot
    while (!writer.try_put(fill)) {
      if (next.formatted == next.samples.size()) {
        writer.put(fill);
        break;
      }
      next.format_until(std::min(next.samples.size(), next.formatted + kRowsPerTry), ne);
    }
  };
  try {
    const auto chunk_steps = kChunkSamples * static_cast<std::size_t>(scenario.run.record_every);
    while (!sim.finished()) {
      sim.advance(chunk_steps);
      hand_over();
    }
    if (sim.one_body_trace().size() > 0) hand_over();  // a run of zero steps: its first sample
  } catch (...) {  // a divergence: the chunks before it still reach the sink
    try {
      writer.drain();
    } catch (...) {
    }
    throw;
  }
  writer.drain();
  return written;
}

std::size_t save_trace_csv_streamed(const Scenario& scenario, const std::string& path) {
  AtomicFileWriter file(path);
  const std::size_t n = stream_trace_csv(scenario, [&](std::string_view s) { file.write(s); });
  file.commit();
  return n;
}

}  // namespace gmslab

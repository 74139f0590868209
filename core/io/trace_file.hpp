// gmslab core: a simulation trace in the format analysis tools read, chosen by the file extension:
//   .csv         text, the header t_s,x_m,v_mps,F_friction_N,F_applied_N,... (trace_csv.hpp)
//   .h5, .hdf5   HDF5: one 1-D dataset per CSV column, with the CSV header's name ("t_s",
//                "F_friction_N", "slip1"), an attribute "unit" ("s", "m", "m/s", "N", "" for a slip
//                flag); doubles, slip flags as uint8; chunked (65,536 samples), shuffled and
//                deflate-compressed (level 1)
//   .mat         MATLAB v7.3 (HDF5 inside) through libmatio: one column vector per CSV column, same
//                names ('.' of an assembled plant's channel as '_'), uncompressed (matio's zlib
//                append took 9 us per sample, 35x the uncompressed write)
// Any other extension is an error naming the accepted ones (a file named .h5 is never CSV text).
// Every format streams: the run is written a chunk of samples at a time (memory constant whatever
// its length) to a temporary file beside the target, renamed over it once the run completes. The
// writing (HDF5's shuffle + deflate, matio, the CSV's number formatting) runs on a second thread
// while the next chunk is simulated (core/io/handoff.hpp); the file's bytes are those of doing it
// in turn.
//
// Reading (load_trace_columns): the columns of any of the three, by name, as doubles; the measured
// -record loader (core/io/measured_file.hpp) reads all three for identification.
#pragma once

#include <string>
#include <vector>

#include "core/io/csv.hpp"
#include "core/sim/assembly.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab {

enum class TraceFormat { Csv, Hdf5, Mat };

// The format of `path` by its extension (any case); throws InputError naming the path and the
// accepted extensions otherwise. `what` names the option in the message ("--out").
TraceFormat trace_format(const std::string& path, const std::string& what = "--out");

// Simulates and writes the trace to `path` in its format (trace_format), streamed and atomic.
// Returns the number of samples. Throws InputError (bad extension), SimulationError, IoError.
std::size_t save_trace_file(const Scenario& scenario, const std::string& path);
std::size_t save_assembly_trace_file(const AssemblyScenario& scenario, const std::string& path);

// Every numeric column of a trace file (CSV with a header, HDF5 or MATLAB), in file order (a .mat
// v7.3 file: as matio lists them, by name).
// Throws InputError naming the file and what is wrong.
std::vector<NamedColumn> load_trace_columns(const std::string& path);

// The 1-D numeric datasets at the root of an HDF5 file (names as stored). Throws InputError naming
// the file when it is not HDF5 or holds none.
std::vector<NamedColumn> load_hdf5_columns(const std::string& path);
// True when the file starts with the HDF5 signature (a .mat v7.3 has a MATLAB header first).
bool is_hdf5_file(const std::string& path);

}  // namespace gmslab

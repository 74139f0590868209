// gmslab core: a measured record from a file as it comes: CSV in any common dialect
// (core/io/csv.hpp), a MATLAB .mat file (v4, v5/v7 and v7.3/HDF5, read through libmatio) or an
// HDF5 file of 1-D datasets (core/io/trace_file.hpp: what gmslab simulate writes to .h5).
//
// MATLAB files: every real numeric variable (double, single or an integer class) of two dimensions
// is a column: a vector (1xN or Nx1) by its name ("time"), each column of an MxN matrix by
// NAME:COLUMN ("data:2", 1-based). Roles are chosen as in a CSV header: by name with an optional
// unit suffix (t_s, x_mm, F_N, ...) or by the explicit map "t=time,x=q,F=force" or
// "t=data:1,x=data:2,F=data:4". Structs, cells, strings, complex and sparse variables are listed
// in the error messages as not usable.
//
// One loader for the CLI (identify), the identify panel, sweeps and the Python module.
#pragma once

#include <string>
#include <vector>

#include "core/io/csv.hpp"

namespace gmslab {

// True when the file is a MATLAB file: a ".mat" extension (any case) or a "MATLAB" header.
bool is_mat_file(const std::string& path);
// Reads a MATLAB file; throws InputError naming the file, the variable and the element.
MeasuredRecord load_measured_mat(const std::string& path, const CsvColumns& columns = {});
// The numeric columns of a MATLAB file (vectors by name, matrix columns as NAME:COLUMN).
std::vector<NamedColumn> load_mat_columns(const std::string& path);
// A CSV, MATLAB or HDF5 file (is_mat_file, then the HDF5 signature, decide; else CSV). An HDF5
// file's columns are its 1-D numeric datasets at the root (as `gmslab simulate --out x.h5` writes).
MeasuredRecord load_measured(const std::string& path, const CsvColumns& columns = {});

}  // namespace gmslab

#include "core/io/trace_file.hpp"

#include <hdf5.h>
#include <matio.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <memory>
#include <mutex>

#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/handoff.hpp"
#include "core/io/measured_file.hpp"
#include "core/io/trace_csv.hpp"

namespace gmslab {

namespace {

constexpr std::size_t kChunkSamples = 1u << 14;  // samples simulated and written at a time
constexpr hsize_t kHdf5Chunk = 1u << 16;          // HDF5 chunk (samples)

// Debian's libhdf5 (serial) is not thread-safe: every HDF5 call of this file holds this lock (an
// identification may load a record on a worker thread while another loads one).
std::mutex& hdf5_lock() {
  static std::mutex m;
  return m;
}

struct ColumnSpec {
  std::string name, unit;
  bool flag = false;  // a 0/1 slip flag (uint8)
};

// Where the columns of a trace go, a chunk of samples at a time.
class ColumnSink {
 public:
  virtual ~ColumnSink() = default;
  virtual void append(const std::vector<std::vector<double>>& cols, std::size_t k) = 0;
  virtual void finish() = 0;  // complete the file and rename it over the target
};

class Hdf5Sink final : public ColumnSink {
 public:
  Hdf5Sink(const std::string& path, const std::vector<ColumnSpec>& specs) : path_(path), file_(path), specs_(specs) {
    const std::lock_guard<std::mutex> lock(hdf5_lock());
    try {
      create();
    } catch (...) {
      close();  // the destructor does not run for a constructor that throws
      throw;
    }
  }
  void create() {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // failures become IoError, not printed stacks
    // Links in creation order, so a reader lists the columns in the CSV's order.
    const hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
    H5Pset_link_creation_order(fcpl, H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED);
    fid_ = H5Fcreate(file_.temporary_path().c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
    H5Pclose(fcpl);
    if (fid_ < 0) throw IoError(path_ + ": cannot create the HDF5 file");
    for (const auto& s : specs_) {
      const hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {kHdf5Chunk};
      const hid_t space = H5Screate_simple(1, dims, maxdims);
      const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
      H5Pset_chunk(dcpl, 1, chunk);
      H5Pset_shuffle(dcpl);
      H5Pset_deflate(dcpl, 1);
      const hid_t d = H5Dcreate2(fid_, s.name.c_str(), s.flag ? H5T_STD_U8LE : H5T_IEEE_F64LE, space, H5P_DEFAULT,
                                 dcpl, H5P_DEFAULT);
      H5Pclose(dcpl);
      H5Sclose(space);
      if (d < 0) throw IoError(path_ + ": cannot create the dataset '" + s.name + "'");
      dsets_.push_back(d);
      const hid_t str = H5Tcopy(H5T_C_S1);
      H5Tset_size(str, std::max<std::size_t>(1, s.unit.size()));
      const hid_t as = H5Screate(H5S_SCALAR);
      const hid_t a = H5Acreate2(d, "unit", str, as, H5P_DEFAULT, H5P_DEFAULT);
      const herr_t rc = a < 0 ? -1 : H5Awrite(a, str, s.unit.empty() ? "" : s.unit.c_str());
      if (a >= 0) H5Aclose(a);
      H5Sclose(as);
      H5Tclose(str);
      if (rc < 0) throw IoError(path_ + ": cannot write the unit of '" + s.name + "'");
    }
  }
  ~Hdf5Sink() override {
    const std::lock_guard<std::mutex> lock(hdf5_lock());
    close();
  }

  void append(const std::vector<std::vector<double>>& cols, std::size_t k) override {
    if (k == 0) return;
    const std::lock_guard<std::mutex> lock(hdf5_lock());
    const hsize_t count[1] = {k}, start[1] = {n_}, size[1] = {n_ + k};
    for (std::size_t c = 0; c < dsets_.size(); ++c) {
      herr_t rc = H5Dset_extent(dsets_[c], size);
      const hid_t fs = H5Dget_space(dsets_[c]);
      const hid_t ms = H5Screate_simple(1, count, nullptr);
      if (rc >= 0) rc = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, nullptr, count, nullptr);
      if (rc >= 0) {
        if (specs_[c].flag) {
          flags_.resize(k);
          for (std::size_t i = 0; i < k; ++i) flags_[i] = static_cast<std::uint8_t>(cols[c][i] != 0.0);
          rc = H5Dwrite(dsets_[c], H5T_NATIVE_UINT8, ms, fs, H5P_DEFAULT, flags_.data());
        } else {
          rc = H5Dwrite(dsets_[c], H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, cols[c].data());
        }
      }
      H5Sclose(ms);
      H5Sclose(fs);
      if (rc < 0) throw IoError(path_ + ": cannot write '" + specs_[c].name + "' (disk full?)");
    }
    n_ += k;
  }

  void finish() override {
    bool ok = false;
    {
      const std::lock_guard<std::mutex> lock(hdf5_lock());
      ok = close();
    }
    if (!ok) throw IoError(path_ + ": cannot complete the HDF5 file (disk full?)");
    file_.commit();
  }

 private:
  bool close() {
    bool ok = true;
    for (const hid_t d : dsets_) ok &= H5Dclose(d) >= 0;
    dsets_.clear();
    if (fid_ >= 0) ok &= H5Fclose(fid_) >= 0;
    fid_ = -1;
    return ok;
  }
  std::string path_;
  AtomicFileWriter file_;
  std::vector<ColumnSpec> specs_;
  hid_t fid_ = -1;
  std::vector<hid_t> dsets_;
  hsize_t n_ = 0;
  std::vector<std::uint8_t> flags_;
};

// MATLAB variable names: letters, digits and '_' ('.' of an assembled plant's channel -> '_').
std::string mat_name(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return s;
}

class MatSink final : public ColumnSink {
 public:
  MatSink(const std::string& path, const std::vector<ColumnSpec>& specs) : path_(path), file_(path), specs_(specs) {
    mat_ = Mat_CreateVer(file_.temporary_path().c_str(), nullptr, MAT_FT_MAT73);
    if (!mat_) throw IoError(path_ + ": cannot create the MATLAB v7.3 file");
  }
  ~MatSink() override {
    if (mat_) Mat_Close(mat_);
  }
  // The samples are gathered into blocks of kBlock (fewer appends: each extends every dataset),
  // kBlock x columns x 8 bytes of memory.
  static constexpr std::size_t kBlock = 1u << 16;
  void append(const std::vector<std::vector<double>>& cols, std::size_t k) override {
    if (buf_.empty()) buf_.resize(specs_.size());
    for (std::size_t c = 0; c < specs_.size(); ++c) buf_[c].insert(buf_[c].end(), cols[c].begin(), cols[c].begin() + static_cast<std::ptrdiff_t>(k));
    if (!buf_.empty() && buf_[0].size() >= kBlock) write_block();
  }
  void write_block() {
    const std::size_t k = buf_.empty() ? 0 : buf_[0].size();
    if (k == 0) return;
    const auto& cols = buf_;
    for (std::size_t c = 0; c < specs_.size(); ++c) {
      std::size_t dims[2] = {k, 1};
      const std::string name = mat_name(specs_[c].name);
      matvar_t* v = nullptr;
      if (specs_[c].flag) {
        flags_.resize(k);
        for (std::size_t i = 0; i < k; ++i) flags_[i] = static_cast<std::uint8_t>(cols[c][i] != 0.0);
        v = Mat_VarCreate(name.c_str(), MAT_C_UINT8, MAT_T_UINT8, 2, dims, flags_.data(), MAT_F_DONT_COPY_DATA);
      } else {
        v = Mat_VarCreate(name.c_str(), MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, const_cast<double*>(cols[c].data()),
                          MAT_F_DONT_COPY_DATA);
      }
      const int rc = v ? Mat_VarWriteAppend(mat_, v, MAT_COMPRESSION_NONE, 1) : 1;
      if (v) Mat_VarFree(v);
      if (rc != 0) throw IoError(path_ + ": cannot write '" + name + "' (disk full?)");
    }
    for (auto& b : buf_) b.clear();
  }
  void finish() override {
    write_block();
    const int rc = Mat_Close(mat_);
    mat_ = nullptr;
    if (rc != 0) throw IoError(path_ + ": cannot complete the MATLAB file (disk full?)");
    file_.commit();
  }

 private:
  std::string path_;
  AtomicFileWriter file_;
  std::vector<ColumnSpec> specs_;
  mat_t* mat_ = nullptr;
  std::vector<std::uint8_t> flags_;
  std::vector<std::vector<double>> buf_;
};

// A sink that writes on a thread of its own (Handoff) while the simulation computes the next
// chunk: the file's bytes are those of the inner sink (the same chunks in the same order); an error
// of the writer is thrown by the next append() or by finish().
class PipelinedSink final : public ColumnSink {
 public:
  struct Chunk {
    std::vector<std::vector<double>> cols;
    std::size_t k = 0;
  };
  explicit PipelinedSink(std::unique_ptr<ColumnSink> inner)
      : inner_(std::move(inner)), writer_([this](Chunk& c) { inner_->append(c.cols, c.k); }) {}
  void append(const std::vector<std::vector<double>>& cols, std::size_t k) override {
    writer_.put([&](Chunk& c) {
      c.cols.resize(cols.size());
      for (std::size_t i = 0; i < cols.size(); ++i)
        c.cols[i].assign(cols[i].begin(), cols[i].begin() + static_cast<std::ptrdiff_t>(k));
      c.k = k;
    });
  }
  void finish() override {
    writer_.drain();
    inner_->finish();
  }

 private:
  std::unique_ptr<ColumnSink> inner_;
  Handoff<Chunk> writer_;  // after inner_: stopped before it is destroyed
};

std::unique_ptr<ColumnSink> make_sink(TraceFormat f, const std::string& path, const std::vector<ColumnSpec>& specs) {
  if (f == TraceFormat::Hdf5)
    return std::make_unique<PipelinedSink>(std::make_unique<Hdf5Sink>(path, specs));
  return std::make_unique<PipelinedSink>(std::make_unique<MatSink>(path, specs));
}

std::string lower_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

}  // namespace

TraceFormat trace_format(const std::string& path, const std::string& what) {
  const std::string ext = lower_extension(path);
  if (ext == ".csv") return TraceFormat::Csv;
  if (ext == ".h5" || ext == ".hdf5") return TraceFormat::Hdf5;
  if (ext == ".mat") return TraceFormat::Mat;
  throw InputError(what + " '" + path + "': " + (ext.empty() ? "no extension" : "unknown extension '" + ext + "'") +
                   "; the format is chosen by it: .csv (text), .h5 or .hdf5 (HDF5), .mat (MATLAB v7.3), or - "
                   "(CSV to stdout)");
}

std::size_t save_trace_file(const Scenario& scenario, const std::string& path) {
  const TraceFormat f = trace_format(path);
  if (f == TraceFormat::Csv) return save_trace_csv_streamed(scenario, path);
  AssemblySimulation sim = one_body_simulation(scenario, TraceOptions{.max_bytes = 0, .reserve_samples = kChunkSamples + 2});
  const std::size_t ne = sim.one_body_trace().n_elements;
  std::vector<ColumnSpec> specs = {{"t_s", "s"}, {"x_m", "m"}, {"v_mps", "m/s"}, {"F_friction_N", "N"}, {"F_applied_N", "N"}};
  for (std::size_t i = 0; i < ne; ++i) specs.push_back({"F" + std::to_string(i + 1) + "_N", "N"});
  for (std::size_t i = 0; i < ne; ++i) specs.push_back({"slip" + std::to_string(i + 1), "", true});
  auto sink = make_sink(f, path, specs);
  std::vector<std::vector<double>> cols(specs.size());
  std::size_t written = 0;
  auto drain = [&] {
    const Trace& tr = sim.one_body_trace();
    const std::size_t k = tr.size();
    cols[0].assign(tr.t.begin(), tr.t.end());
    cols[1].assign(tr.x.begin(), tr.x.end());
    cols[2].assign(tr.v.begin(), tr.v.end());
    cols[3].assign(tr.friction.begin(), tr.friction.end());
    cols[4].assign(tr.applied.begin(), tr.applied.end());
    for (std::size_t i = 0; i < ne; ++i) {
      auto& f_i = cols[5 + i];
      auto& s_i = cols[5 + ne + i];
      f_i.resize(k), s_i.resize(k);
      for (std::size_t j = 0; j < k; ++j) {
        f_i[j] = tr.element_force[j * ne + i];
        s_i[j] = tr.element_slip[j * ne + i];
      }
    }
    sink->append(cols, k);
    written += k;
    sim.clear_trace();
  };
  const auto chunk_steps = kChunkSamples * static_cast<std::size_t>(scenario.run.record_every);
  while (!sim.finished()) {
    sim.advance(chunk_steps);
    drain();
  }
  if (sim.one_body_trace().size() > 0) drain();  // a run of zero steps: its first sample
  sink->finish();
  return written;
}

std::size_t save_assembly_trace_file(const AssemblyScenario& scenario, const std::string& path) {
  const TraceFormat f = trace_format(path);
  if (f == TraceFormat::Csv) return save_assembly_trace_csv(scenario, path);
  AssemblySimulation sim(scenario, TraceOptions{.max_bytes = 0, .reserve_samples = kChunkSamples + 2});
  const AssemblyTrace& tr0 = sim.trace();
  // The CSV's columns: t_s, every channel NAME_UNIT, slip.CONTACT per contact.
  std::vector<ColumnSpec> specs = {{"t_s", "s"}};
  for (const auto& c : tr0.channels) specs.push_back({c.name + '_' + (c.unit == "m/s" ? "mps" : c.unit), c.unit});
  for (const auto& c : tr0.channels)
    if (c.kind == Channel::Kind::ContactForce) specs.push_back({"slip." + c.name.substr(2), "", true});
  auto sink = make_sink(f, path, specs);
  std::vector<std::vector<double>> cols(specs.size());
  std::size_t written = 0;
  auto drain = [&] {
    const AssemblyTrace& tr = sim.trace();
    const std::size_t k = tr.size(), nc = tr.channels.size();
    cols[0].assign(tr.t.begin(), tr.t.end());
    for (std::size_t c = 0; c < nc; ++c) {
      cols[1 + c].resize(k);
      for (std::size_t j = 0; j < k; ++j) cols[1 + c][j] = tr.values[j * nc + c];
    }
    for (std::size_t s = 0; s < tr.contact_slip.size() && 1 + nc + s < cols.size(); ++s)
      cols[1 + nc + s].assign(tr.contact_slip[s].begin(), tr.contact_slip[s].begin() + static_cast<std::ptrdiff_t>(k));
    sink->append(cols, k);
    written += k;
    sim.clear_trace();
  };
  const auto chunk_steps = kChunkSamples * static_cast<std::size_t>(scenario.run.record_every);
  while (!sim.finished()) {
    sim.advance(chunk_steps);
    drain();
  }
  if (sim.trace().size() > 0 || written == 0) drain();
  sink->finish();
  return written;
}

bool is_hdf5_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  char head[8] = {};
  return f.read(head, 8) && std::string(head, 8) == "\x89HDF\r\n\x1a\n";
}

std::vector<NamedColumn> load_hdf5_columns(const std::string& path) {
  if (!is_hdf5_file(path)) {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw InputError(path + ": cannot open the file (does it exist, is it readable?)");
    throw InputError(path + ": not an HDF5 file (no HDF5 signature at its start)");
  }
  const std::lock_guard<std::mutex> lock(hdf5_lock());
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t fid = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (fid < 0) throw InputError(path + ": not an HDF5 file that can be read");
  std::vector<NamedColumn> out;
  std::string skipped;
  H5G_info_t info{};
  H5Gget_info(fid, &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    char name[256] = {};
    if (H5Lget_name_by_idx(fid, ".", H5_INDEX_CRT_ORDER, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0 &&
        H5Lget_name_by_idx(fid, ".", H5_INDEX_NAME, H5_ITER_INC, i, name, sizeof name, H5P_DEFAULT) < 0)
      continue;
    H5O_info_t oi{};
    if (H5Oget_info_by_name(fid, name, &oi, H5P_DEFAULT) < 0 || oi.type != H5O_TYPE_DATASET) {
      skipped += (skipped.empty() ? "" : ", ") + std::string(name) + " (not a dataset)";
      continue;
    }
    const hid_t d = H5Dopen2(fid, name, H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    const hid_t ty = H5Dget_type(d);
    const int rank = H5Sget_simple_extent_ndims(sp);
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(sp, dims, nullptr);
    const H5T_class_t cls = H5Tget_class(ty);
    const bool column = rank == 1 || (rank == 2 && (dims[0] == 1 || dims[1] == 1));
    if (column && (cls == H5T_FLOAT || cls == H5T_INTEGER)) {
      NamedColumn c{name, std::vector<double>(rank == 1 ? dims[0] : dims[0] * dims[1])};
      if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, c.values.data()) >= 0)
        out.push_back(std::move(c));
      else
        skipped += (skipped.empty() ? "" : ", ") + std::string(name) + " (unreadable)";
    } else {
      skipped += (skipped.empty() ? "" : ", ") + std::string(name) + (column ? " (not numeric)" : " (not 1-D)");
    }
    H5Tclose(ty);
    H5Sclose(sp);
    H5Dclose(d);
  }
  H5Fclose(fid);
  if (out.empty())
    throw InputError(path + ": no 1-D numeric dataset at the root of the HDF5 file" +
                     (skipped.empty() ? std::string() : " (it has: " + skipped + ")"));
  return out;
}

std::vector<NamedColumn> load_trace_columns(const std::string& path) {
  if (is_mat_file(path)) return load_mat_columns(path);
  if (is_hdf5_file(path)) return load_hdf5_columns(path);
  return parse_csv_columns(read_file(path), path);
}

}  // namespace gmslab

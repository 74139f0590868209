// gmslab simulate PRESET[.json] --out trace.csv|trace.h5|trace.mat|-
#include <iostream>
#include <memory>

#include "app/cli/cli.hpp"
#include "core/error.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "core/io/trace_csv.hpp"
#include "core/io/trace_file.hpp"
#include "core/sim/simulation.hpp"

namespace gmslab::cli {

void register_simulate(CLI::App& app, Action& action) {
  struct Opts {
    std::string preset, out;
  };
  // Owned by the app (its callbacks hold it): each Cli has its own options.
  auto o = std::make_shared<Opts>();
  auto* sub = app.add_subcommand("simulate", "Simulate a scenario preset and write its trace (CSV, HDF5 or MATLAB by the extension)");
  sub->add_option("preset", o->preset,
                  "Scenario preset: a JSON file, or a shipped preset's name (fig4_stick_slip)")
      ->required();
  sub->add_option("--out,-o", o->out,
                  "Trace file: .csv, .h5/.hdf5 (HDF5, a dataset per column with its unit) or .mat "
                  "(MATLAB v7.3); columns t_s, x_m, v_mps, F_friction_N, F_applied_N, per-element force "
                  "and slip state; '-' for CSV on stdout")
      ->required();
  // Defaults again at every parse of this command (a Cli may be run many times).
  sub->preparse_callback([o](std::size_t) { *o = Opts{}; });
  sub->callback([&action, o] {
    action = [o] {
      if (o->out != "-") (void)trace_format(o->out);  // an unknown extension: before any work
      // An assembled plant (schema_version 2): every named output, streamed as it is computed.
      // A preset file or a shipped preset's bare name (fig4_stick_slip), as every front end.
      const std::string file = resolve_preset(o->preset, presets_dir());
      const Preset preset = load_preset(file);
      if (preset.assembled()) {
        const AssemblyScenario& as = preset.scenario;
        if (o->out == "-") {
          stream_assembly_trace_csv(as, [](std::string_view s) { std::cout.write(s.data(), static_cast<std::streamsize>(s.size())); });
          std::cout.flush();
        } else {
          std::cerr << "wrote " << save_assembly_trace_file(as, o->out) << " samples to " << o->out << '\n';
        }
        return 0;
      }
      const Scenario sc = preset.one_body();
      // The trace streams to the output as it is computed (constant memory whatever the run
      // length); a file is written atomically (temporary file, renamed once the run is complete).
      try {
        if (o->out == "-") {
          stream_trace_csv(sc, [](std::string_view s) { std::cout.write(s.data(), static_cast<std::streamsize>(s.size())); });
          std::cout.flush();
        } else {
          const std::size_t n = save_trace_file(sc, o->out);
          std::cerr << "wrote " << n << " samples to " << o->out << '\n';
        }
      } catch (const InputError& e) {  // e.g. a step too large for this plant: name the file
        throw InputError(file + ": " + e.what());
      }
      return 0;
    };
  });
}

}  // namespace gmslab::cli

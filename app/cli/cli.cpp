#include "app/cli/cli.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/text/closest_word.hpp"

namespace gmslab::cli {

void add_render_options(CLI::App& sub, RenderOptions& o) {
  sub.add_option("preset", o.preset,
                 "Scenario preset: a JSON file, or a shipped preset's name (fig4_stick_slip)")
      ->required();
  sub.add_option("--out,-o", o.out, "File to write (PNG, or SVG with --format svg)")->required();
  sub.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub.add_option("--view", o.view, "View to draw: auto, simulation, design, identify, plant")
      ->capture_default_str();
  sub.add_option("--time", o.time, "Simulated time to show [s] (default: the whole run)");
  sub.add_option("--data", o.data,
                 "Identify view: training CSV to identify before drawing (the panel's 'Identify')");
  sub.add_option("--validate", o.validate, "Identify view: validation CSV (default: a hold-out part)");
  sub.add_option("--mask-edges", o.mask_edges, "Identify view: COLUMN:BEFORE:AFTER [s] windows to ignore")
      ->capture_default_str();
  sub.add_flag("--compare", o.compare, "Identify view: also fit and compare every model (slower)");
  sub.add_flag("--no-run", o.no_run, "Identify view: load and show the records of --data without identifying");
  sub.add_option("--drive", o.drive, "Design view, assembled preset: the drive the controller acts through");
  sub.add_option("--output", o.output, "Design view, assembled preset: the measured output x.BODY");
  sub.add_option("--num", o.num, "Design view: a typed plant's numerator, highest power first (with --den)");
  sub.add_option("--den", o.den, "Design view: a typed plant's denominator, highest power first (with --num)");
  sub.add_option("--zeta", o.zeta, "Design view: damping ratio of the desired dominant roots, in [0.02, 0.98]");
  sub.add_option("--wn", o.wn, "Design view: natural frequency of the desired dominant roots [rad/s], > 0");
  sub.add_option("--sample-time", o.sample_time, "Design view: controller sample time [s], [0, 0.01] (0: continuous)");
  sub.add_option("--compensator", o.compensator, "Design view: compensator type built from the design")
      ->check(CLI::IsMember({"lead", "lag", "lead_lag", "pi", "pid"}));
  sub.add_option("--K", o.K, "Design view: target error constant (Kp / Kv / Ka by plant type), (0, 1e7]");
  sub.add_option("--reference", o.design_reference, "Design view: the loop's reference (the tab's amplitude)")
      ->check(CLI::IsMember({"step", "ramp", "sine"}));
  sub.add_option("--compensation", o.compensation, "Design view: friction compensation of the second loop")
      ->check(CLI::IsMember({"coulomb", "gms"}));
  sub.add_option("--feedforward", o.feedforward,
                 "Design view: the compensation driven by the reference or the measured velocity")
      ->check(CLI::IsMember({"reference", "measured"}));
  sub.add_option("--manual", o.manual,
                 "Design view: a manual compensator \"Kc z p [z2 p2]\" (Kc [N/m], zeros and poles [rad/s], p = 0: "
                 "an integrator), as if dragged");
  sub.add_option("--format", o.format,
                 "png: the app's view; svg: the simulation's plots (forces, position, friction, velocity) as vectors")
      ->check(CLI::IsMember({"png", "svg"}))
      ->capture_default_str();
}

void add_figures_options(CLI::App& sub, FiguresOptions& o) {
  sub.add_option("--out,-o", o.out, "Folder for the figures (PNG and/or SVG) and their CSV series")
      ->capture_default_str();
  sub.add_option("--only", o.only, "Comma-separated figure ids (default: all)");
  sub.add_option("--size", o.size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub.add_option("--format", o.format, "png, svg (vector, text as text) or both; the CSV series are always written")
      ->check(CLI::IsMember({"png", "svg", "both"}))
      ->capture_default_str();
}

void parse_size(const std::string& text, int& w, int& h) {
  char x = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w < 64 || h < 64 || w > 8192 || h > 8192)
    throw InputError("--size '" + text +
                     "': expected WIDTHxHEIGHT with each side from 64 to 8192 pixels, e.g. 1600x1000");
}

Cli::Cli(Host host)
    : host_(std::move(host)),
      app_("gmslab: friction simulation and compensation around the Generalized Maxwell-Slip model.\n"
           "With no command, opens the window (or, with no display, renders the figure set).") {
  app_.name("gmslab");  // help and errors say "gmslab", also when run as gmslab-headless
  app_.set_version_flag("--version", "gmslab 0.1.0");
  app_.require_subcommand(0, 1);
  auto* open = app_.add_option("--open", window_.open,
                               "Open the window on this preset (a path, or a shipped preset's name such as two_mass_drive)");
  app_.add_option("--tab", window_.tab, "With --open: the tab to show (default: Plant for an assembled plant, else Simulation)")
      ->check(CLI::IsMember({"simulation", "figures", "design", "identify", "plant"}, CLI::ignore_case))
      ->needs(open);
  app_.add_flag("--run", window_.run, "With --open: start the run of the Simulation or Plant tab")->needs(open);

  register_simulate(app_, action_);

  auto* r = app_.add_subcommand("render", "Render the app's view of a scenario to PNG, or its plots to SVG (headless)");
  add_render_options(*r, render_);
  r->preparse_callback([this](std::size_t) { render_ = RenderOptions{}; });
  r->callback([this] { action_ = [this] { return host_.render(render_); }; });

  auto* f = app_.add_subcommand("figures", "Render the paper's figure set to PNG and/or SVG, with CSV series (headless)");
  add_figures_options(*f, figures_);
  f->preparse_callback([this](std::size_t) { figures_ = FiguresOptions{}; });
  f->callback([this] { action_ = [this] { return host_.figures(figures_); }; });

  register_design(app_, action_);
  register_cycles(app_, action_);
  register_identify(app_, action_);

  // `gmslab sweep` runs python3 -m gmslab.sweep (app/main.cpp hands it over before parsing); it is
  // here so that help lists it and its arguments pass through unparsed.
  auto* sw = app_.add_subcommand("sweep", "Run a parameter sweep on Dask: gmslab sweep SPEC.json [--scheduler ADDR] "
                                          "(python3 -m gmslab.sweep; gmslab sweep --help)");
  sw->prefix_command();
  sw->set_help_flag();
  sw->callback([this] {
    action_ = [] () -> int {
      throw InputError("sweep runs in Python: call it as `gmslab sweep SPEC.json` (the gmslab executable) or "
                       "`python3 -m gmslab.sweep SPEC.json`");
    };
  });
}

std::string Cli::command_list() const {
  std::string out;
  for (const CLI::App* sub : app_.get_subcommands([](const CLI::App*) { return true; }))
    out += (out.empty() ? "" : ", ") + sub->get_name();
  return out;
}

std::string suggest(const std::string& word, const std::vector<std::string>& known) {
  return closest_word(word, known);
}

std::vector<std::string> Cli::known_words(const std::string& word) const {
  // The deepest command given: its options (and, at the top, the commands).
  const CLI::App* at = &app_;
  for (bool deeper = true; deeper;) {
    deeper = false;
    for (const CLI::App* sub : at->get_subcommands())
      if (sub->parsed()) at = sub, deeper = true;
  }
  std::vector<std::string> out;
  const bool is_option = !word.empty() && word[0] == '-';
  if (is_option) {
    for (const CLI::Option* o : at->get_options()) {
      for (const auto& l : o->get_lnames()) out.push_back("--" + l);
      for (const auto& sn : o->get_snames()) out.push_back("-" + sn);
    }
  } else {
    for (const CLI::App* sub : at->get_subcommands([](const CLI::App*) { return true; })) out.push_back(sub->get_name());
  }
  return out;
}

namespace {
// CLI11 2.1.2's App::clear() (called by every parse after the first) keeps parse_order(), so each
// parse of a reused app appends to it for ever: 8 bytes per parsed option and call, ~1 GB over
// the 10^7 inputs of a fuzz run (CLIUtils/CLI11#1216, fixed upstream by #1218 in clear()). This
// does what that fix does, for the app and every subcommand. parse_order_ is protected: a member
// pointer named through a derived class reaches it on any App.
struct ParseOrder : CLI::App {
  static void clear(CLI::App& app) {
    (app.*(&ParseOrder::parse_order_)).clear();
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) clear(*sub);
  }
};
}  // namespace

int Cli::run(int argc, char** argv) {
  action_ = nullptr;
  window_ = WindowOptions{};
  ParseOrder::clear(app_);
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help / version, exit 0); any other parse failure is bad
    // input: exit 2, as the README says (CLI11's own codes, e.g. 109 for an unknown option, are not).
    // A first word that is no command: say so and list the commands (not a suggestion for each
    // word after it, which are that command's arguments).
    bool sub_parsed = false;
    for (const CLI::App* sub : app_.get_subcommands()) sub_parsed |= sub->parsed();
    if (!sub_parsed && dynamic_cast<const CLI::ExtrasError*>(&e)) {
      for (const auto& word : app_.remaining()) {
        if (word.empty() || word[0] == '-') continue;
        std::cerr << "gmslab: unknown command '" << word << "'";
        if (const std::string s = suggest(word, known_words(word)); !s.empty())
          std::cerr << "; did you mean '" << s << "'?";
        std::cerr << "\ncommands: " << command_list() << " (gmslab --help; gmslab COMMAND --help)\n";
        return exit_code(ErrorKind::Input);
      }
    }
    const int rc = app_.exit(e);
    if (rc == 0) return 0;
    // A near miss gets a suggestion: "--outt" -> "--out", "rendr" -> "render".
    std::vector<std::string> extras;
    for (const CLI::App* a = &app_; a;) {
      for (const auto& r : a->remaining()) extras.push_back(r);
      const CLI::App* next = nullptr;
      for (const CLI::App* sub : a->get_subcommands())
        if (sub->parsed()) next = sub;
      a = next;
    }
    for (const auto& x : extras) {
      const std::string word = x.substr(0, x.find('='));
      if (const std::string s = suggest(word, known_words(word)); !s.empty())
        std::cerr << "gmslab: '" << word << "': did you mean '" << s << "'?\n";
    }
    return exit_code(ErrorKind::Input);
  }
  try {
    if (action_ && (!window_.open.empty() || !window_.tab.empty() || window_.run))
      throw InputError("--open, --tab and --run open the window; they do not go with a command (put them alone: "
                       "gmslab --open PRESET [--tab TAB] [--run])");
    if (!action_) {
      if (host_.window) return host_.window(window_);
      std::cerr << app_.help();
      return 2;
    }
    return action_();
  } catch (const Error& e) {  // typed: the kind decides the exit code (README)
    std::cerr << "gmslab: " << error_label(e.kind()) << ": " << e.what() << '\n';
    return exit_code(e.kind());
  } catch (const std::filesystem::filesystem_error& e) {  // a folder that cannot be created
    std::cerr << "gmslab: " << error_label(ErrorKind::Io) << ": " << e.what() << '\n';
    return exit_code(ErrorKind::Io);
  } catch (const std::exception& e) {  // not a typed error: a bug
    std::cerr << "gmslab: " << error_label(ErrorKind::Internal) << ": " << e.what() << '\n';
    return exit_code(ErrorKind::Internal);
  }
}

int run(int argc, char** argv, const Host& host) {
  Cli cli(host);
  return cli.run(argc, argv);
}

}  // namespace gmslab::cli

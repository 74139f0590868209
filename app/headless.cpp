#include "app/headless.hpp"

#include <GL/osmesa.h>
#include <backends/imgui_impl_opengl2.h>
#include <imgui.h>
#include <stb_image_write.h>
#include <strings.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/control/design_plant.hpp"
#include "core/control/linear_response.hpp"
#include "core/error.hpp"
#include "core/figures/figure_set.hpp"
#include "core/ident/dataset.hpp"
#include "core/io/assembly_io.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/json_reader.hpp"
#include "core/io/preset_io.hpp"
#include "core/io/scenario_io.hpp"
#include "ui/app.hpp"
#include "ui/app_files.hpp"
#include "ui/design/design_view.hpp"
#include "ui/figures/figure_svg.hpp"
#include "ui/figures/figure_view.hpp"
#include "ui/identify/identify_panel.hpp"
#include "ui/panels.hpp"
#include "ui/plot/plot.hpp"
#include "ui/style.hpp"

namespace gmslab::app {

namespace {
// ImGui_ImplOpenGL2_RenderDrawData of Dear ImGui 1.86 ignores ImDrawCmd::VtxOffset, so a draw list
// with more than 65536 vertices (plots of long traces, 16-bit indices) would be drawn wrongly.
// This is the same fixed-function drawing with the vertex offset honoured, which lets us declare
// ImGuiBackendFlags_RendererHasVtxOffset. (The font texture still comes from the backend.)
void render_draw_data(const ImDrawData* dd) {
  const int fb_w = static_cast<int>(dd->DisplaySize.x * dd->FramebufferScale.x);
  const int fb_h = static_cast<int>(dd->DisplaySize.y * dd->FramebufferScale.y);
  if (fb_w <= 0 || fb_h <= 0) return;
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_LIGHTING);
  glDisable(GL_COLOR_MATERIAL);
  glEnable(GL_SCISSOR_TEST);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_TEXTURE_COORD_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_NORMAL_ARRAY);
  glEnable(GL_TEXTURE_2D);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glShadeModel(GL_SMOOTH);
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
  glViewport(0, 0, fb_w, fb_h);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glOrtho(dd->DisplayPos.x, dd->DisplayPos.x + dd->DisplaySize.x, dd->DisplayPos.y + dd->DisplaySize.y,
          dd->DisplayPos.y, -1.0, 1.0);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  const ImVec2 off = dd->DisplayPos, scale = dd->FramebufferScale;
  for (int n = 0; n < dd->CmdListsCount; ++n) {
    const ImDrawList* cl = dd->CmdLists[n];
    for (const ImDrawCmd& cmd : cl->CmdBuffer) {
      if (cmd.UserCallback) {
        if (cmd.UserCallback != ImDrawCallback_ResetRenderState) cmd.UserCallback(cl, &cmd);
        continue;
      }
      const ImVec2 c0((cmd.ClipRect.x - off.x) * scale.x, (cmd.ClipRect.y - off.y) * scale.y);
      const ImVec2 c1((cmd.ClipRect.z - off.x) * scale.x, (cmd.ClipRect.w - off.y) * scale.y);
      if (c1.x <= c0.x || c1.y <= c0.y) continue;
      glScissor(static_cast<int>(c0.x), static_cast<int>(fb_h - c1.y), static_cast<int>(c1.x - c0.x),
                static_cast<int>(c1.y - c0.y));
      glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(reinterpret_cast<std::intptr_t>(cmd.GetTexID())));
      const ImDrawVert* v = cl->VtxBuffer.Data + cmd.VtxOffset;
      glVertexPointer(2, GL_FLOAT, sizeof(ImDrawVert), &v->pos);
      glTexCoordPointer(2, GL_FLOAT, sizeof(ImDrawVert), &v->uv);
      glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(ImDrawVert), &v->col);
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(cmd.ElemCount),
                     sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT, cl->IdxBuffer.Data + cmd.IdxOffset);
    }
  }
  glDisable(GL_SCISSOR_TEST);
}
}  // namespace

Offscreen::Offscreen(int width, int height, float font_px) : w_(width), h_(height) {
  gl_buf_.assign(static_cast<std::size_t>(w_) * h_ * 4, 0);
  OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!ctx) throw InternalError("OSMesa: cannot create an offscreen GL context");
  if (!OSMesaMakeCurrent(ctx, gl_buf_.data(), GL_UNSIGNED_BYTE, w_, h_)) {
    OSMesaDestroyContext(ctx);
    throw InternalError("OSMesa: cannot make the offscreen context current");
  }
  ctx_ = ctx;
  IMGUI_CHECKVERSION();
  imgui_ = ImGui::CreateContext();
  plot_ = ui::CreatePlotContext();
  if (font_px <= 0.0f) font_px = std::clamp(17.0f * static_cast<float>(h_) / 1000.0f, 12.0f, 26.0f);
  ui::setup_style(font_px);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(w_), static_cast<float>(h_));
  io.DeltaTime = 1.0f / 60.0f;
  ImGui_ImplOpenGL2_Init();
  io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;  // render_draw_data honours it
}

Offscreen::~Offscreen() {
  ImGui::SetCurrentContext(static_cast<ImGuiContext*>(imgui_));
  ImGui_ImplOpenGL2_Shutdown();
  ImGui::DestroyContext(static_cast<ImGuiContext*>(imgui_));
  ui::DestroyPlotContext(static_cast<ui::PlotContext*>(plot_));
  OSMesaDestroyContext(static_cast<OSMesaContext>(ctx_));
}

const std::vector<unsigned char>& Offscreen::render(const std::function<void()>& draw, int frames) {
  ImGui::SetCurrentContext(static_cast<ImGuiContext*>(imgui_));
  ui::SetCurrentPlotContext(static_cast<ui::PlotContext*>(plot_));
  ImGuiIO& io = ImGui::GetIO();
  for (int f = 0; f < std::max(1, frames); ++f) {
    io.DisplaySize = ImVec2(static_cast<float>(w_), static_cast<float>(h_));
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);  // no hover: deterministic
    ImGui_ImplOpenGL2_NewFrame();
    ImGui::NewFrame();
    draw();
    ImGui::Render();
    glViewport(0, 0, w_, h_);
    glClearColor(1.0f, 1.0f, 1.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    render_draw_data(ImGui::GetDrawData());
    glFinish();
  }
  // OSMesa's rows run bottom to top; PNG rows run top to bottom.
  out_.resize(gl_buf_.size());
  const std::size_t row = static_cast<std::size_t>(w_) * 4;
  for (int y = 0; y < h_; ++y)
    std::copy_n(&gl_buf_[static_cast<std::size_t>(h_ - 1 - y) * row], row, &out_[static_cast<std::size_t>(y) * row]);
  for (std::size_t i = 3; i < out_.size(); i += 4) out_[i] = 255;  // opaque
  return out_;
}

void draw_figure_window(const Figure& f) {
  const ImGuiViewport* vp = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(vp->Pos);
  ImGui::SetNextWindowSize(vp->Size);
  ImGui::PushStyleColor(ImGuiCol_WindowBg, IM_COL32(255, 255, 255, 255));
  ImGui::Begin("figure", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoMove);
  ui::draw_figure(f, false);
  ImGui::End();
  ImGui::PopStyleColor();
}

std::string encode_png(int width, int height, const std::vector<unsigned char>& rgba) {
  std::string bytes;
  auto sink = [](void* ctx, void* data, int size) {
    static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(sink, &bytes, width, height, 4, rgba.data(), width * 4))
    throw InternalError("PNG encoding failed (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  return bytes;
}

void write_png(const std::string& path, int width, int height, const std::vector<unsigned char>& rgba) {
  write_file_atomic(path, encode_png(width, height, rgba));
}

namespace {
// The main window of the app for a full-size frame.
void draw_app(ui::AppState& s) { ui::draw_frame(s); }

// The Simulation view's four plots as a Figure (the same trace the window draws), main model
// solid, overlay dashed.
Figure simulation_figure(const ui::AppState& s) {
  Figure f;
  f.id = "simulation";
  f.title = s.scenario.name;
  f.caption = s.scenario.description;
  struct Axis { const char* title; const char* xl; const char* yl; };
  const Axis axes[] = {{"Friction force against time", "t [s]", "F_f [N]"},
                       {"Position against time", "t [s]", "x [m]"},
                       {"Friction force against displacement", "x [m]", "F_f [N]"},
                       {"Velocity against time", "t [s]", "v [mm/s]"}};
  for (int k = 0; k < 4; ++k) f.panels.push_back({std::string(1, static_cast<char>('A' + k)), axes[k].title, axes[k].xl, axes[k].yl, {}});
  auto add = [&](const AssemblySimulation* sim, const std::string& name, Series::Style style,
                 int color) {
    if (!sim) return;
    const Trace& tr = sim->one_body_trace();
    std::vector<double> vmm(tr.v.size());
    for (std::size_t i = 0; i < tr.v.size(); ++i) vmm[i] = 1e3 * tr.v[i];
    f.panels[0].series.push_back({name, tr.t, tr.friction, style, color});
    f.panels[1].series.push_back({name, tr.t, tr.x, style, color});
    f.panels[2].series.push_back({name, tr.x, tr.friction, style, color});
    f.panels[3].series.push_back({name, tr.t, vmm, style, color});
  };
  add(s.main.sim.get(), std::string(model_info(s.scenario.friction.model).name), Series::Style::Solid, 0);
  if (s.compare) add(s.overlay.sim.get(), std::string(model_info(s.compare->model).name), Series::Style::Dashed, 1);
  return f;
}

std::vector<std::string> split_ids(const std::string& only) {
  std::vector<std::string> ids;
  std::stringstream in(only);
  std::string id;
  while (std::getline(in, id, ','))
    if (!id.empty()) ids.push_back(id);
  return ids;
}
}  // namespace

namespace {
// render_command once its preset names a file.
int render_resolved(const cli::RenderOptions& o) {
  int w = 0, h = 0;
  cli::parse_size(o.size, w, h);
  const ui::PanelEntry* panel = ui::find_panel(o.view.c_str());
  if (!panel) {
    std::string names;
    for (const auto& e : ui::panels()) names += std::string(names.empty() ? "" : ", ") + e.name;
    throw InputError("--view '" + o.view + "': unknown view (available: auto, " + names + ")");
  }
  if (!o.data.empty() && std::string(panel->name) != "Identify" && o.view != "auto")
    throw InputError("--data: only the identify view runs an identification (use --view identify)");
  if (!o.data.empty()) panel = ui::find_panel("identify");
  // The auto view of an assembled preset (schema 2) is the Plant view: the one view that shows it.
  const bool auto_view = o.view.empty() || strcasecmp(o.view.c_str(), "auto") == 0;
  // The preset, read and checked once, when it is first needed.
  std::optional<Preset> loaded;
  auto preset = [&]() -> const Preset& {
    if (!loaded) loaded = load_preset(o.preset);
    return *loaded;
  };
  if (auto_view && o.data.empty() && preset().assembled()) {
    if (o.format == "svg")
      throw InputError(o.preset + ": --format svg draws the Simulation view's plots, which an assembled preset (schema 2) "
                       "does not have; use --format png (its Plant view)");
    panel = ui::find_panel("plant");
  }
  ui::AppState s;
  const bool design_view = std::string(panel->name) == "Design";
  if ((!o.drive.empty() || !o.output.empty() || !o.num.empty() || !o.den.empty() || o.zeta != 0.0 || o.wn != 0.0 ||
       !o.compensator.empty() || o.K != 0.0 || !o.design_reference.empty() || !o.compensation.empty() ||
       !o.feedforward.empty() || !o.manual.empty()) &&
      !design_view)
    throw InputError("--drive, --output, --num, --den, --zeta, --wn, --compensator, --K, --reference, --compensation, "
                     "--feedforward, --manual: only the design view takes them (use --view design)");
  if (o.zeta != 0.0 && !(o.zeta >= 0.02 && o.zeta <= 0.98)) throw InputError("--zeta: must be in [0.02, 0.98]");
  if (o.wn != 0.0 && !(o.wn > 0.0 && o.wn <= 1e5)) throw InputError("--wn: must be in (0, 1e5] rad/s");
  if (o.num.empty() != o.den.empty()) throw InputError("--num and --den go together (a typed plant)");
  // The design view of an assembled preset (schema 2), or of a v1 preset with --drive / --output (its
  // one-body assembly, as `gmslab design`), designs on the assembled plant (as the Plant tab holds it
  // in the window).
  const bool assembled = design_view && o.format == "png" &&
                         (!o.drive.empty() || !o.output.empty() || preset().assembled());
  const bool plant_view = std::string(panel->name) == "Plant" || assembled;
  if (plant_view) {  // an assembled plant (schema 2) or a one-body preset, in the Plant panel
    ui::load_plant(s.plant, preset().scenario, o.preset);
    ui::plant_run_until(s.plant, o.time);
    // The other tabs need a scenario (the first frame draws the first tab): a v1 preset's own, else
    // the window's default preset, else the GMS defaults at rest.
    // (relative to the working directory when it lies below it, as a path the user typed would be)
    std::error_code ec;
    std::string dflt = ui::presets_dir() + "/fig4_stick_slip.json";
    if (const auto rel = std::filesystem::proximate(dflt, ec); !ec && !rel.empty() && *rel.begin() != "..") dflt = rel.string();
    if (!preset().assembled()) {
      ui::load_scenario_into(s, preset().one_body(), o.preset);
    } else if (std::filesystem::exists(dflt)) {
      ui::load_scenario_into(s, load_scenario(dflt), dflt);
    } else {
      Scenario rest;
      rest.name = "at rest";
      rest.friction = model_info("gms").defaults();
      ui::load_scenario_into(s, rest, "");
    }
  } else {
    ui::load_scenario_into(s, preset().one_body(), o.preset);
  }
  if (!(o.sample_time >= 0.0 && o.sample_time <= 0.01))
    throw InputError("--sample-time " + std::to_string(o.sample_time) + ": must be in [0, 0.01] s (0: continuous)");
  s.design.settings.sample_time = o.sample_time;
  ui::mark_clean(s);
  s.view.tab = panel->name;
  if (!plant_view || assembled) ui::run_until(s, o.time);
  if (design_view) {
    DesignSettings ds = ui::design_settings(s.design);
    if (assembled) {
      ds.plant.source = control::PlantSource::Assembly;
      ds.plant.drive = o.drive;
      ds.plant.output = o.output;
      // Errors in the names are this command's errors (listing the names there are).
      control::assembly_port(s.plant.scenario->plant, o.drive, o.output);
    }
    if (!o.num.empty()) {
      control::typed_plant(o.num, o.den, "--num", "--den");
      ds.plant.source = control::PlantSource::Typed;
      ds.plant.num = o.num;
      ds.plant.den = o.den;
    }
    if (o.zeta != 0.0) ds.zeta = o.zeta;
    if (o.wn != 0.0) ds.wn = o.wn;
    if (!o.compensator.empty()) ds.compensator = *control::compensator_type_from_string(o.compensator);
    if (o.K != 0.0) {
      if (!(o.K > 0.0 && o.K <= 1e7)) throw InputError("--K: must be in (0, 1e7]");
      ds.use_K = true, ds.K = o.K;
    }
    if (!o.design_reference.empty()) ds.reference = *design_reference_from_string(o.design_reference);
    if (!o.compensation.empty()) ds.compensation = o.compensation;
    if (!o.feedforward.empty()) ds.feedforward_source = *control::feedforward_source_from_string(o.feedforward);
    ui::apply_design_settings(s.design, ds);
    if (!o.manual.empty()) {  // "Kc z p [z2 p2]": the compensator as if dragged
      std::istringstream in(o.manual);
      std::vector<double> v;
      for (double x; in >> x;) v.push_back(x);
      if (!in.eof() || (v.size() != 3 && v.size() != 5))
        throw InputError("--manual '" + o.manual + "': expected 3 or 5 numbers \"Kc z p [z2 p2]\"");
      control::LeadCompensator c{v[0], v[1], v[2]};
      if (v.size() == 5) c.second = control::Section{v[3], v[4]};
      control::check_compensator(c, "--manual");
      s.design.in.manual = c;
    }
  }
  if (!o.data.empty()) {
    // Bad records are an error of this command (file, line, column), not only a red line in the view.
    ident::load_dataset({o.data, "", "", o.mask_edges});
    if (!o.validate.empty()) ident::load_dataset({o.validate, "", "", o.mask_edges});
    ui::IdentifyInputs in;
    in.data = o.data;
    in.validate = o.validate;
    in.mask_edges = o.mask_edges;
    in.compare = o.compare;
    if (o.no_run) {
      ui::apply_identify_settings(s.identify, in);
    } else {
      ui::identify_start(s.identify, in);
      std::cerr << "identifying " << o.data << " ...\n";
      while (ui::identify_busy(s.identify)) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // The run's failure in its own kind: bad records exit 2, a bug 1.
    if (!ui::identify_error(s.identify).empty())
      throw_error(s.identify.error_kind, "identification failed: " + ui::identify_error(s.identify));
  }
  if (o.format == "svg") {
    ui::write_figure_svg(simulation_figure(s), w, h, o.out);
    std::cout << "wrote " << o.out << " (" << w << "x" << h << ", SVG of the simulation's plots, t = "
              << s.main.sim->time() << " s)\n";
    return 0;
  }
  Offscreen off(w, h);
  if (design_view) {  // the hunting map's background job: a deterministic picture waits for it
    for (int frame = 0; frame < 3; ++frame) {  // the tab is selected, the design computed
      off.render([&] { draw_app(s); }, 1);
      while (ui::hunting_map_busy(s.design))
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  const auto& rgba = off.render([&] { draw_app(s); }, 4);
  write_png(o.out, w, h, rgba);
  std::cout << "wrote " << o.out << " (" << w << "x" << h << ", " << panel->name << " view, t = "
            << (plant_view && !assembled ? s.plant.sim->time() : s.main.sim->time()) << " s, title \""
            << ui::window_title(s) << "\")\n";
  return 0;
}
}  // namespace

int render_command(const cli::RenderOptions& given) {
  // A preset file, or a shipped preset's bare name (fig4_stick_slip), as every front end takes it.
  cli::RenderOptions o = given;
  o.preset = resolve_preset(given.preset, presets_dir());
  return render_resolved(o);
}

int figures_command(const cli::FiguresOptions& o) {
  int w = 0, h = 0;
  cli::parse_size(o.size, w, h);
  const std::vector<std::string> all = figure_ids();
  std::vector<std::string> ids = o.only.empty() ? all : split_ids(o.only);
  for (const auto& id : ids)
    if (std::find(all.begin(), all.end(), id) == all.end()) {
      std::string known;
      for (const auto& k : all) known += (known.empty() ? "" : ", ") + k;
      throw InputError("--only: unknown figure '" + id + "' (known: " + known + ")");
    }
  std::filesystem::create_directories(o.out);
  const std::string presets = ui::presets_dir();
  const bool png = o.format != "svg", svg = o.format != "png";
  std::optional<Offscreen> off;
  if (png) off.emplace(w, h);
  std::size_t k = 0;
  for (const auto& id : ids) {
    // Progress on stderr (full lines), the files written on stdout.
    std::cerr << "[" << ++k << "/" << ids.size() << "] " << id << '\n';
    const Figure f = make_figure(id, presets);
    const std::string base = (std::filesystem::path(o.out) / id).string();
    std::string wrote;
    if (png) {
      const auto& rgba = off->render([&] { draw_figure_window(f); }, 3);
      write_png(base + ".png", w, h, rgba);
      wrote += base + ".png ";
    }
    if (svg) {
      ui::write_figure_svg(f, w, h, base + ".svg");
      wrote += base + ".svg ";
    }
    std::ostringstream csv;
    write_figure_csv(f, csv);
    write_file_atomic(base + ".csv", csv.str());
    std::cout << wrote << base << ".csv\n";
  }
  return 0;
}

}  // namespace gmslab::app

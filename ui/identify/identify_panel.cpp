#include "ui/identify/identify_panel.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string_view>
#include <thread>

#include "core/ident/dataset.hpp"
#include "core/ident/job.hpp"
#include "core/ident/loop.hpp"
#include "ui/figures/figure_view.hpp"
#include "ui/plot/plot.hpp"
#include "ui/text_wrap.hpp"

namespace gmslab::ui {

namespace {

using Result = IdentifyResult;
using Job = IdentifyJob;
using Config = IdentifyInputs;
using Preview = IdentifyPreview;



ident::RecordSpec train_spec(const Config& c) {
  return {c.data, c.columns, c.mask, c.mask_edges, "training mask", "mask edges"};
}
ident::RecordSpec validation_spec(const Config& c) {
  return {c.validate, c.columns, c.validate_mask, c.mask_edges, "validation mask", "mask edges"};
}

std::string preview_key(const Config& c) {
  return c.data + '\n' + c.validate + '\n' + c.columns + '\n' + c.mask + '\n' + c.validate_mask + '\n' +
         c.mask_edges;
}

// Loads the records named by the inputs (only when they changed and nobody is typing).
void refresh_preview(IdentifyState& st) {
  const std::string key = preview_key(st);
  if (key == st.preview.key || ImGui::IsAnyItemActive()) return;
  Preview p;
  p.key = key;
  if (!st.data.empty()) {
    try {
      std::string note;
      p.train = ident::load_dataset(train_spec(st), &note);
      if (!note.empty()) p.notes.push_back(note);
      if (!st.validate.empty()) {
        note.clear();
        p.val = ident::load_dataset(validation_spec(st), &note);
        if (!note.empty()) p.notes.push_back(note);
      }
    } catch (const std::exception& e) {
      p.error = e.what();
      p.error_kind = error_kind_of(e);
    }
  }
  st.preview = std::move(p);
}

void start(IdentifyState& st) {
  st.error.clear();
  st.status.clear();
  auto job = std::make_unique<Job>();
  Job* j = job.get();
  const Config cfg = st;
  j->thread = std::thread([j, cfg] {
    try {
      auto r = std::make_unique<Result>();
      ident::IdentifyJob job;  // the CLI's job, with the CLI's defaults
      job.train = train_spec(cfg);
      job.validation = validation_spec(cfg);
      job.spec.model = cfg.model;
      job.spec.elements = static_cast<std::size_t>(cfg.elements);
      if (cfg.compare) job.compare = ident::parse_model_list("all");
      auto progress = [j](const ident::FitProgress& p) {
        std::lock_guard<std::mutex> lock(j->m);
        j->progress = p;
      };
      auto out = ident::run_identification(job, progress, &j->cancel);
      r->train = std::move(out.train);
      r->val = std::move(out.validation);
      r->report = std::move(out.report);
      r->figure = ident::report_figure(r->report, r->train, r->val);
      std::lock_guard<std::mutex> lock(j->m);
      j->result = std::move(r);
    } catch (const ident::Cancelled&) {
      std::lock_guard<std::mutex> lock(j->m);
      j->error = "cancelled";
      j->error_kind = ErrorKind::Cancelled;
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(j->m);
      j->error = e.what();
      j->error_kind = error_kind_of(e);
    }
    j->done = true;
  });
  st.job = std::move(job);
}

void tooltip(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void inputs(IdentifyState& st, bool busy) {
  const float w = ImGui::GetFontSize() * 28.0f;
  ImGui::BeginDisabled(busy);
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("training CSV", "path: header t_s, x_m, F_N [, v_mps, Fn_N] ...", &st.data);
  tooltip("Measured record (CSV or MATLAB .mat): t [s], x [m], F [N], optional v [m/s] and Fn [N].\n"
          "CSV: comma, semicolon, tab or whitespace separated, decimal point or comma, header optional.\n"
          "Columns are found by name, with or without a unit suffix (t_ms, x_mm, F_kN, ...).");
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("validation CSV", "(empty: hold out a quarter of the training record)", &st.validate);
  tooltip("Record the fit never sees: an effect is kept only when it lowers the error here");
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("columns", "t=t_s,x=x_m,F=F_N (empty: found by name)", &st.columns);
  tooltip("Map roles to header names when the names are not t, x, F, v, Fn; by 1-based position for a\n"
          "CSV without a header (t=1,x=2,F=4); MATLAB variables by name (t=time,x=q,F=force) or a\n"
          "column of a matrix (t=data:1,x=data:2,F=data:4)");
  ImGui::SetNextItemWidth(w * 0.5f - ImGui::GetStyle().ItemInnerSpacing.x);
  ImGui::InputTextWithHint("##mask", "training: t0:t1,... [s]", &st.mask);
  tooltip("Time windows of the training record to ignore, t0:t1,... [s] (still simulated, not fitted)");
  ImGui::SameLine(0, ImGui::GetStyle().ItemInnerSpacing.x);
  ImGui::SetNextItemWidth(w * 0.5f);
  ImGui::InputTextWithHint("masks", "validation: t0:t1,... [s]", &st.validate_mask);
  tooltip("Time windows of the validation record to ignore, t0:t1,... [s]");
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("mask edges", "COLUMN:BEFORE_s:AFTER_s", &st.mask_edges);
  tooltip("Ignore [-BEFORE, +AFTER] s around every change of this column (e.g. the EMPS pulse_code)");
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 14.0f);
  if (ImGui::BeginCombo("base model", st.model.c_str())) {
    for (const auto& m : model_registry())
      if (ImGui::Selectable(std::string(m.name).c_str(), st.model == m.tag)) st.model = std::string(m.tag);
    ImGui::EndCombo();
  }
  tooltip("The friction model the loop starts from; effects are added to it");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6.0f);
  ImGui::InputInt("elements", &st.elements);
  st.elements = std::clamp(st.elements, 0, 64);
  tooltip("Element count N of multi-element models (GMS: alpha_i, k_i per element; 1..64);\n"
          "0 = auto: the validation record chooses (GMS, Maxwell-slip; the CLI's --elements auto)");
  ImGui::SameLine();
  ImGui::Checkbox("compare", &st.compare);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("After the loop, fit every model with the effects it found and compare their RMS\n"
                      "(each fit limited to %.0f s)", ident::kCompareSeconds);
  ImGui::EndDisabled();
}

// "F_N" etc.: the record summary for the preview text.
std::string summary(const char* what, const ident::Dataset& d) {
  if (d.size() < 2) return "";
  const double T = d.t.back() - d.t.front();
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s: %s, %zu samples over %.4g s (mean step %.3g ms), %zu used%s", what,
                std::filesystem::path(d.source).filename().c_str(), d.size(), T,
                1e3 * T / static_cast<double>(d.size() - 1), d.used(), d.has_Fn ? ", normal force" : "");
  return buf;
}

void preview_plots(const IdentifyState& st, float height) {
  const Preview& p = st.preview;
  if (p.train.size() < 2) return;
  // Plot classes are the samples' use[] flags: 0 = masked (grey), 1 = used.
  static const ImU32 use_colors[2] = {IM_COL32(170, 170, 170, 255), palette(0)};
  const int n_plots = p.val.size() >= 2 ? 3 : 2;
  const float w = (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x * (n_plots - 1)) / n_plots;
  auto plot = [&](const char* id, const char* title, const ident::Dataset& d, const std::vector<double>& y,
                  const char* name, const char* unit) {
    PlotOptions o;
    o.title = title;
    o.legend = false;
    if (BeginPlot(id, ImVec2(w, height), o)) {
      SetupAxesSI("t", "s", name, unit);
      SeriesStyle s;
      s.x_sorted = true;
      s.thickness = 1.0f;
      s.classes = d.use.data();
      s.class_colors = use_colors;
      s.n_classes = 2;
      PlotLine(name, d.t.data(), y.data(), d.size(), s);
      EndPlot();
    }
  };
  plot("##train_F", "training record: force (grey: masked)", p.train, p.train.F, "F", "N");
  ImGui::SameLine();
  plot("##train_x", "training record: position", p.train, p.train.x, "x", "m");
  if (n_plots == 3) {
    ImGui::SameLine();
    plot("##val_F", "validation record: force (grey: masked)", p.val, p.val.F, "F", "N");
  }
}

// One line per candidate of a round: name, explained share, screening validation RMS.
std::string candidates_line(const ident::Round& rd, std::size_t max) {
  std::string out;
  char buf[120];
  for (std::size_t i = 0; i < rd.candidates.size() && i < max; ++i) {
    const auto& c = rd.candidates[i];
    std::snprintf(buf, sizeof buf, "%s%s %.1f %%", out.empty() ? "" : ", ",
                  std::string(ident::effect_name(c.effect)).c_str(), 100.0 * c.explained);
    out += buf;
  }
  return out;
}

// The evidence of every candidate of a round, scalar entries only (the spectra and velocity bins
// are plotted in the report figure).
std::string evidence_text(const ident::Round& rd) {
  std::string out;
  char buf[200];
  for (const auto& c : rd.candidates) {
    std::snprintf(buf, sizeof buf, "%s: explains %.1f %% of the residual variance; screening RMS train %.4g N, "
                  "validation %.4g N\n", std::string(ident::effect_name(c.effect)).c_str(), 100.0 * c.explained,
                  c.screen_rms_train, c.screen_rms_validation);
    out += buf;
    std::string ev;
    for (const auto& [k, v] : c.evidence.items())
      if (v.is_number()) {
        std::snprintf(buf, sizeof buf, "%s%s = %.4g", ev.empty() ? "    " : ", ", k.c_str(), v.get<double>());
        ev += buf;
      }
    if (!ev.empty()) out += ev + "\n";
  }
  for (const auto& a : rd.attempts) {
    std::snprintf(buf, sizeof buf, "tried %s: validation RMS %.4g N -> %s\n",
                  std::string(ident::effect_name(a.effect)).c_str(), a.rms_validation, a.kept ? "kept" : "rejected");
    out += buf;
  }
  return out;
}

// Credit by ablation: validation RMS with all named effects and with each left out, and why each
// effect is named or was dropped.
void ablation_table(const ident::IdentReport& r) {
  const auto& a = r.ablation;
  if (!a.ran) return;
  ImGui::Text("Ablation: validation RMS %.4g N with all named effects (floor %.3g N)", a.rms_validation_all, a.floor);
  tooltip(
      "Each effect the rounds added is refitted out from the final shape with the same budget. It "
      "is named "
      "only when the validation error without it is worse by more than the data resolve (block "
      "test over "
      "time, z >= 3, or a rise of the MSE above the floor's variance), its contribution is at "
      "least half "
      "the floor and the model without it stays above 1.15x the floor. It is also refitted out "
      "with one "
      "element more: when that model does as well by the same test, one more element explains the "
      "effect (alike: N+1 elements) and the data call for more elements.");
  const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg;
  if (!ImGui::BeginTable("ablation", 5, flags)) return;
  ImGui::TableSetupColumn("left out");
  ImGui::TableSetupColumn("RMS validation [N]");
  ImGui::TableSetupColumn("z (blocks)");
  ImGui::TableSetupColumn("contribution [N]");
  ImGui::TableSetupColumn("verdict", ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableHeadersRow();
  auto row = [](const ident::AblationRow& x) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    std::string name(ident::effect_name(x.effect));
    for (auto e : x.alike) name += " (or " + std::string(ident::effect_name(e)) + ")";
    if (x.explained_by_element)
      name += " (alike: " + std::to_string(x.more_elements) + " elements)";
    if (x.credited) ImGui::TextUnformatted(name.c_str());
    else ImGui::TextDisabled("%s", name.c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", x.rms_validation_without);
    ImGui::TableNextColumn();
    ImGui::Text("%.3g (%zu)", x.test.z, x.test.blocks);
    ImGui::TableNextColumn();
    ImGui::Text("%.3g", x.contribution);
    ImGui::TableNextColumn();
    TextWrappedAtSpaces(x.verdict);
  };
  for (const auto& x : a.rows) row(x);
  for (const auto& x : a.dropped) row(x);
  ImGui::EndTable();
}

// The model the report gives: the final fit on all training samples after the rounds, credited
// by ablation, at its minimum, with any discovered terms joined; its change is against the model
// the last round started from.
void final_model_row(const ident::IdentReport& r) {
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(r.discovery.joined ? "final: all samples, credited, + discovered"
                                            : "final: all samples, credited");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip(
        "The final fit on every training sample, the effects credited by ablation (a "
        "round's effect the credit drops is left out), the shape taken to a minimum%s.",
        r.discovery.joined ? ", and the discovered terms fitted jointly with the model" : "");
  const double train_from =
      r.rounds.empty() ? r.rms_before_train : r.rounds.back().rms_train_before;
  const double val_from =
      r.rounds.empty() ? r.rms_before_validation : r.rounds.back().rms_validation_before;
  ImGui::TableNextColumn();
  ImGui::Text("%.4g -> %.4g", train_from, r.rms_after_train);
  ImGui::TableNextColumn();
  ImGui::Text("%.4g -> %.4g", val_from, r.rms_after_validation);
  ImGui::TableNextColumn();
  if (val_from > 0) ImGui::Text("%+.1f %%", 100.0 * (r.rms_after_validation / val_from - 1.0));
  ImGui::TableNextColumn();
  ImGui::TableNextColumn();
}

void rounds_table(const ident::IdentReport& r) {
  const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg;
  if (!ImGui::BeginTable("rounds", 6, flags)) return;
  ImGui::TableSetupColumn("stage");
  ImGui::TableSetupColumn("RMS train [N]");
  ImGui::TableSetupColumn("RMS validation [N]");
  ImGui::TableSetupColumn("validation change");
  ImGui::TableSetupColumn("effect parameters");
  // The last column takes the rest of the width and wraps (at spaces), so no candidate is clipped.
  ImGui::TableSetupColumn("candidates (share of the residual variance each explains; hover: evidence)",
                          ImGuiTableColumnFlags_WidthStretch);
  ImGui::TableHeadersRow();
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::Text("base %s", r.model.c_str());
  ImGui::TableNextColumn();
  ImGui::Text("%.4g", r.rms_before_train);
  ImGui::TableNextColumn();
  ImGui::Text("%.4g", r.rms_before_validation);
  for (int i = 0; i < 3; ++i) ImGui::TableNextColumn();
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const auto& rd = r.rounds[i];
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    if (rd.added)
      ImGui::Text("round %zu: + %s", i + 1, std::string(ident::effect_name(*rd.added)).c_str());
    else
      ImGui::TextDisabled("round %zu: nothing kept (stop)", i + 1);
    // A round that kept nothing changed nothing: its numbers are the model it started from (the
    // report's last round carries the final model's, shown in the row below).
    ImGui::TableNextColumn();
    if (rd.added)
      ImGui::Text("%.4g -> %.4g", rd.rms_train_before, rd.rms_train_after);
    else
      ImGui::TextDisabled("%.4g", rd.rms_train_before);
    ImGui::TableNextColumn();
    if (rd.added)
      ImGui::Text("%.4g -> %.4g", rd.rms_validation_before, rd.rms_validation_after);
    else
      ImGui::TextDisabled("%.4g", rd.rms_validation_before);
    ImGui::TableNextColumn();
    if (rd.added && rd.rms_validation_before > 0)
      ImGui::Text("%+.1f %%", 100.0 * (rd.rms_validation_after / rd.rms_validation_before - 1.0));
    ImGui::TableNextColumn();
    std::string params;
    for (const auto& a : rd.attempts)
      if (a.kept)
        for (const auto& t : a.terms) {
          char buf[96];
          std::snprintf(buf, sizeof buf, "%s%s = %.4g %s", params.empty() ? "" : ", ", t.name.c_str(), t.value,
                        t.unit.c_str());
          params += buf;
        }
    if (params.size() > 60) params = params.substr(0, 57) + "...";
    ImGui::TextUnformatted(params.c_str());
    ImGui::TableNextColumn();
    TextWrappedAtSpaces(candidates_line(rd, 4));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", evidence_text(rd).c_str());
  }
  final_model_row(r);
  ImGui::EndTable();
}

// The final model's linear terms and the effects' scalars with their standard errors (the path
// and encoder shares they include), or why a parameter has none.
void parameters_table(const ident::IdentReport& r) {
  if (r.parameters.empty()) return;
  // Open where an error is given; where none is, the header says why (one reason for all, as
  // at an unverified minimum) and the values stay one click away.
  bool any = false, one_reason = true;
  for (const auto& p : r.parameters) {
    any |= std::isfinite(p.std_error);
    one_reason &= p.no_error == r.parameters.front().no_error;
  }
  const std::string header =
      any ? "Parameters (+- one standard error)"
          : "Parameters: no standard errors" + (one_reason && !r.parameters.front().no_error.empty()
                                                    ? " (" + r.parameters.front().no_error + ")"
                                                    : std::string());
  const bool open = ImGui::CollapsingHeader((header + "###parameters").c_str(),
                                            any ? ImGuiTreeNodeFlags_DefaultOpen : 0);
  tooltip(
      "Standard errors from the linearised least squares at the fitted shape (the larger of the "
      "white-noise and the block-robust variance), with the shares of the unmeasured path "
      "between samples and of the encoder's rounding added in quadrature. Given only at a "
      "verified minimum, and not for a Coulomb level the record does not reach");
  if (!open) return;
  const ImGuiTableFlags flags =
      ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg;
  if (!ImGui::BeginTable("parameters", 5, flags)) return;
  for (const char* h : {"parameter", "value", "std error", "of which path / encoder", "note"})
    ImGui::TableSetupColumn(h,
                            std::string_view(h) == "note" ? ImGuiTableColumnFlags_WidthStretch : 0);
  ImGui::TableHeadersRow();
  for (const auto& p : r.parameters) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("%s.%s", p.effect.c_str(), p.name.c_str());
    ImGui::TableNextColumn();
    const bool given = std::isfinite(p.std_error);
    // Digits down to a tenth of the error (5 without one).
    int digits = 5;
    if (given && p.std_error > 0 && p.value != 0)
      digits = std::clamp(
          static_cast<int>(std::ceil(std::log10(std::abs(p.value) / p.std_error))) + 2, 3, 12);
    ImGui::Text("%.*g %s", digits, p.value, p.unit.c_str());
    ImGui::TableNextColumn();
    if (given)
      ImGui::Text("%.2g %s", p.std_error, p.unit.c_str());
    else
      ImGui::TextDisabled("none");
    ImGui::TableNextColumn();
    if (given) ImGui::Text("%.2g / %.2g", p.path_error, p.encoder_error);
    ImGui::TableNextColumn();
    if (!given) TextWrappedAtSpaces(p.no_error);
  }
  ImGui::EndTable();
}

void comparison_table(const ident::IdentReport& r) {
  if (r.comparison.empty()) return;
  ImGui::Text("Model comparison: every model fitted with the effects added (%zu)", r.effects_added.size());
  const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg;
  if (!ImGui::BeginTable("comparison", 6, flags)) return;
  for (const char* h : {"model", "elements", "shape parameters", "RMS train [N]", "RMS validation [N]", "fit time [s]"})
    ImGui::TableSetupColumn(h);
  ImGui::TableHeadersRow();
  double best = 1e300;
  for (const auto& c : r.comparison) best = std::min(best, c.rms_validation);
  for (const auto& c : r.comparison) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(std::string(model_info(c.model).name).c_str());
    ImGui::TableNextColumn();
    if (c.elements) ImGui::Text("%zu", c.elements);
    ImGui::TableNextColumn();
    ImGui::Text("%zu", c.shape_parameters);
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", c.rms_train);
    ImGui::TableNextColumn();
    if (c.rms_validation == best)
      ImGui::TextColored(ImVec4(0.0f, 0.45f, 0.3f, 1.0f), "%.4g (best)", c.rms_validation);
    else
      ImGui::Text("%.4g", c.rms_validation);
    ImGui::TableNextColumn();
    ImGui::Text(c.time_limited ? "%.1f (limit: not converged)" : "%.1f", c.seconds);
  }
  ImGui::EndTable();
}

// Takes over a finished run (result or error); true when a run is still going.
bool collect(IdentifyState& st) {
  if (!st.job) return false;
  Job& j = *st.job;
  if (!j.done) return true;
  j.thread.join();
  std::lock_guard<std::mutex> lock(j.m);
  if (j.result) st.result = std::move(j.result);
  st.error = j.error;
  st.error_kind = j.error_kind;
  st.job.reset();
  return false;
}

void progress_line(Job& j) {
  ident::FitProgress p;
  {
    std::lock_guard<std::mutex> lock(j.m);
    p = j.progress;
  }
  if (ImGui::Button("Cancel")) j.cancel = true;
  tooltip("Stop the run (the last finished report stays)");
  ImGui::SameLine();
  // The loop's round count is not known in advance: the bar shows the current fit's share of its
  // evaluation budget, the text which fit it is.
  const float frac = p.budget > 0 ? std::min(1.0f, static_cast<float>(p.evaluations) / p.budget) : 0.0f;
  char overlay[64];
  std::snprintf(overlay, sizeof overlay, "%d / %d evaluations", p.evaluations, p.budget);
  ImGui::ProgressBar(frac, ImVec2(ImGui::GetFontSize() * 18.0f, 0), p.budget > 0 ? overlay : "loading");
  ImGui::SameLine();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - j.started).count();
  ImGui::Text("%s, best RMS %.4g N  (%.0f s)", p.stage.c_str(), p.best_rms, secs);
}

}  // namespace

std::optional<IdentifyInputs> emps_example() {
  const char* env = std::getenv("GMSLAB_SHARED");
  const std::filesystem::path dir =
      std::filesystem::path(env && *env ? env : GMSLAB_SOURCE_DIR "/../shared") / "data" / "emps";
  std::error_code ec;
  if (!std::filesystem::exists(dir / "DATA_EMPS.csv", ec) || !std::filesystem::exists(dir / "DATA_EMPS_PULSES.csv", ec))
    return std::nullopt;
  IdentifyInputs in;
  in.data = (dir / "DATA_EMPS.csv").lexically_normal().string();
  in.validate = (dir / "DATA_EMPS_PULSES.csv").lexically_normal().string();
  // As the documented command (README: gmslab identify ... --mask-edges pulse_code:0.005:0.060):
  // the validation pulses' edges are not friction.
  in.mask_edges = "pulse_code:0.005:0.060";
  return in;
}

IdentifySettings identify_settings(const IdentifyState& st) { return static_cast<const Config&>(st); }

void apply_identify_settings(IdentifyState& st, const IdentifySettings& in) {
  if (!collect(st)) static_cast<Config&>(st) = in;
}



void identify_start(IdentifyState& st, const IdentifyInputs& in) {
  if (collect(st)) return;  // one run at a time
  static_cast<Config&>(st) = in;
  start(st);
}

bool identify_busy(IdentifyState& st) { return collect(st); }

void identify_cancel(IdentifyState& st) {
  if (st.job) st.job->cancel = true;
}

const ident::IdentReport* identify_report(const IdentifyState& st) {
  return st.result ? &st.result->report : nullptr;
}

std::string identify_error(const IdentifyState& st) { return st.error; }

void identify_send_to_plant(IdentifyState& st, std::optional<Scenario>& plant_request) {
  if (!st.result) return;
  plant_request = ident::identified_scenario(st.result->report, st.result->train);
  st.status = "sent to the Simulation tab";
}


void draw_identify_panel(IdentifyState& st, std::optional<Scenario>& plant_request) {
  const bool busy = st.job != nullptr;
  static const std::optional<IdentifyInputs> example = emps_example();  // looked up once
  const ImGuiStyle& style = ImGui::GetStyle();
  const float input_w = ImGui::GetFontSize() * 38.0f;
  const float top_h = ImGui::GetFrameHeightWithSpacing() * 7.0f + style.WindowPadding.y;
  ImGui::BeginChild("##ident_inputs", ImVec2(input_w, top_h), false);
  inputs(st, busy);
  if (!busy) {
    const bool can_run = !st.data.empty() && st.preview.error.empty();
    ImGui::BeginDisabled(!can_run);
    if (ImGui::Button("Identify")) start(st);
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
      ImGui::SetTooltip(st.data.empty()             ? "Enter a training CSV first"
                        : !st.preview.error.empty() ? "Fix the error on the right first"
                                                    : "Fit the base model, then run the residual loop");
    if (example) {
      ImGui::SameLine();
      if (ImGui::Button("EMPS example")) {  // the records and their masks; the model choice stays
        st.data = example->data;
        st.validate = example->validate;
        st.columns = example->columns;
        st.mask = example->mask;
        st.validate_mask = example->validate_mask;
        st.mask_edges = example->mask_edges;
      }
      tooltip("Fill in the EMPS benchmark records of ../shared/data/emps with -5..+60 ms around each pulse_code edge "
              "masked (mask edges pulse_code:0.005:0.060), as the README's command: Identify then gives 1.96 N");
    }
  } else {
    progress_line(*st.job);
    collect(st);
  }
  ImGui::EndChild();
  if (!busy) refresh_preview(st);

  // Right of the inputs: what was loaded, notes and errors, the outcome.
  ImGui::SameLine();
  ImGui::BeginChild("##ident_info", ImVec2(0, top_h), false);
  const ImVec4 red(0.75f, 0.1f, 0.1f, 1), grey(0.4f, 0.4f, 0.4f, 1);
  if (st.data.empty()) {
    ImGui::TextWrapped("Identify a friction model from measured data. Give a CSV with a header row and "
                       "columns t, x, F (units in the names: t_s, x_mm, F_N, ...). The base model is fitted "
                       "first; then each round tests the residual against a catalog of effects (inertia, "
                       "offset, direction asymmetry, position ripple, drift, extra velocity dependence, "
                       "dwell stiction, normal load, force-channel lag, force filter, backlash) and keeps an effect only if it lowers the error on "
                       "the validation record.");
    if (example) ImGui::TextWrapped("'EMPS example' fills in the measured EMPS benchmark records.");
  }
  if (!st.preview.error.empty()) ImGui::TextColored(red, "%s", st.preview.error.c_str());
  for (const auto& line : {summary("training", st.preview.train), summary("validation", st.preview.val)})
    if (!line.empty()) ImGui::TextUnformatted(line.c_str());
  if (!st.data.empty() && st.validate.empty() && st.preview.error.empty())
    ImGui::TextColored(grey, "validation: every 4th of 8 time blocks of the training record is held out");
  ImGui::PushStyleColor(ImGuiCol_Text, grey);
  for (const auto& n : st.preview.notes) TextWrappedAtSpaces(n);
  ImGui::PopStyleColor();
  if (!st.error.empty()) ImGui::TextColored(red, "%s", st.error.c_str());
  if (st.result) {
    const auto& r = st.result->report;
    const std::string added = ident::named_effects(r.ablation, r.effects_added);
    char rms[160];
    std::snprintf(rms, sizeof rms, "Validation RMS %.4g N -> %.4g N (training %.4g -> %.4g N); ",
                  r.rms_before_validation, r.rms_after_validation, r.rms_before_train,
                  r.rms_after_train);
    // Wrapped: the reason nothing was added can be longer than the column.
    const std::string more = ident::more_elements_summary(r.ablation);
    TextWrappedAtSpaces(
        rms + (added.empty() ? ident::nothing_added(r)
                             : "effects added: " + added + (more.empty() ? "" : "; " + more)));
    if (!r.optimum.verified) {
      ImGui::PushStyleColor(ImGuiCol_Text, red);
      TextWrappedAtSpaces("Not converged: " + r.optimum.reason + "; no standard errors");
      ImGui::PopStyleColor();
    }
    if (!r.discovery.summary.empty()) {
      TextWrappedAtSpaces("Beyond the catalog: " + r.discovery.summary);
      tooltip(
          "A sparse regression of the final training residual on a library of candidate terms "
          "(travel since reversal, time since rest, sliding history, force lag, direction-gated "
          "ripple, ...), kept only when it passes the same credit test as the catalog effects");
    }
    ImGui::Text("Base model: %s, %zu element%s found", r.model.c_str(), r.final_fit().spec.elements,
                r.final_fit().spec.elements == 1 ? "" : "s");
    if (r.screen_every > 1) {
      ImGui::SameLine();
      ImGui::TextColored(grey, "(%s)", ident::screen_summary(r).c_str());
      tooltip("A long record: the base fit and the loop's decisions ran on every k-th sample of the "
              "training record; the noise floor, the ripple search, the final fit (polished from the "
              "screened shape) and all validation errors use every sample");
    }
    if (!r.remaining.summary.empty()) {
      TextWrappedAtSpaces("What remains: " + r.remaining.summary);
      tooltip("The final validation residual tested for structure by velocity, position, time, after "
              "reversals and in the position spectrum, each against the noise floor estimated from the data");
    }
    if (ImGui::Button("Send model to plant")) identify_send_to_plant(st, plant_request);
    tooltip("Replace the Simulation tab's scenario: identified friction, identified mass, training motion");
    if (!st.status.empty()) {
      ImGui::SameLine();
      ImGui::TextUnformatted(st.status.c_str());
    }
  }
  ImGui::EndChild();

  if (!st.result) {
    if (st.preview.train.size() >= 2) {
      ImGui::Separator();
      preview_plots(st, std::max(200.0f, ImGui::GetContentRegionAvail().y - style.ItemSpacing.y));
    }
    return;
  }
  rounds_table(st.result->report);
  ablation_table(st.result->report);
  parameters_table(st.result->report);
  comparison_table(st.result->report);
  ImGui::BeginChild("##identfig", ImVec2(0, 0), true, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_figure(st.result->figure, true);
  ImGui::EndChild();
}

}  // namespace gmslab::ui

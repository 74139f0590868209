#include "ui/identify_panel.hpp"

#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

#include "core/ident/loop.hpp"
#include "core/io/csv.hpp"
#include "ui/figure_view.hpp"

namespace gmslab::ui {

namespace {

struct Result {
  ident::IdentReport report;
  ident::Dataset train, val;
  Figure figure;
};

// The worker: runs identify() on its own copies, reports progress under a mutex.
struct Job {
  std::atomic<bool> cancel{false};
  std::atomic<bool> done{false};
  std::mutex m;
  std::string stage;             // guarded by m
  int evaluations = 0;           // guarded by m
  double best_rms = 0;           // guarded by m
  std::string error;             // guarded by m
  std::unique_ptr<Result> result;  // guarded by m
  std::thread thread;
  ~Job() {
    cancel = true;
    if (thread.joinable()) thread.join();
  }
};

using Config = IdentifyInputs;

struct IdentifyState : Config {
  std::unique_ptr<Job> job;
  std::unique_ptr<Result> result;
  std::string error, status;
};

ident::Dataset load(const std::string& path, const CsvColumns& cols, const std::string& edges) {
  const auto rec = load_measured_csv(path, cols);
  std::vector<ident::TimeWindow> w;
  const auto c1 = edges.find(':');
  if (!edges.empty() && c1 != std::string::npos) {
    const auto c2 = edges.find(':', c1 + 1);
    if (const auto* col = rec.extra_column(edges.substr(0, c1)); col && c2 != std::string::npos)
      w = ident::edge_windows(rec.t, *col, std::stod(edges.substr(c1 + 1, c2 - c1 - 1)),
                              std::stod(edges.substr(c2 + 1)));
  }
  return ident::prepare_dataset(rec, w);
}

void start(IdentifyState& st) {
  st.error.clear();
  st.status.clear();
  auto job = std::make_unique<Job>();
  Job* j = job.get();
  const Config cfg = st;
  j->thread = std::thread([j, cfg] {
    try {
      const CsvColumns cols = cfg.columns.empty() ? CsvColumns{} : parse_column_map(cfg.columns);
      auto r = std::make_unique<Result>();
      r->train = load(cfg.data, cols, cfg.mask_edges);
      if (cfg.validate.empty()) {
        auto split = ident::split_holdout(r->train);
        r->train = std::move(split.first);
        r->val = std::move(split.second);
      } else {
        r->val = load(cfg.validate, cols, cfg.mask_edges);
      }
      ident::LoopOptions lo;
      auto progress = [j](const ident::FitProgress& p) {
        std::lock_guard<std::mutex> lock(j->m);
        j->stage = p.stage;
        j->evaluations = p.evaluations;
        j->best_rms = p.best_rms;
      };
      lo.base.progress = lo.refit.progress = progress;
      lo.base.cancel = lo.refit.cancel = &j->cancel;
      ident::FitSpec spec;
      spec.model = cfg.model;
      spec.elements = static_cast<std::size_t>(cfg.elements);
      r->report = ident::identify(r->train, r->val, spec, lo);
      r->figure = ident::report_figure(r->report, r->train, r->val);
      std::lock_guard<std::mutex> lock(j->m);
      j->result = std::move(r);
    } catch (const ident::Cancelled&) {
      std::lock_guard<std::mutex> lock(j->m);
      j->error = "cancelled";
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(j->m);
      j->error = e.what();
    }
    j->done = true;
  });
  st.job = std::move(job);
}

void inputs(IdentifyState& st, bool busy) {
  const float w = ImGui::GetFontSize() * 28.0f;
  ImGui::BeginDisabled(busy);
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("training CSV", "t_s, x_m, F_N [, v_mps, Fn_N] ...", &st.data);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Measured record: header row, columns t [s], x [m], F [N], optional v [m/s], Fn [N]");
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("validation CSV", "(empty: hold out a quarter of the training record)", &st.validate);
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("columns", "t=t_s,x=x_m,F=F_N (empty: found by name)", &st.columns);
  ImGui::SetNextItemWidth(w);
  ImGui::InputTextWithHint("mask edges", "COLUMN:BEFORE_s:AFTER_s", &st.mask_edges);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Ignore windows [s] around every change of this column (e.g. the EMPS pulse_code)");
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 14.0f);
  if (ImGui::BeginCombo("base model", st.model.c_str())) {
    for (const auto& m : model_registry())
      if (ImGui::Selectable(std::string(m.name).c_str(), st.model == m.tag)) st.model = std::string(m.tag);
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6.0f);
  ImGui::InputInt("elements", &st.elements);
  st.elements = std::clamp(st.elements, 1, 64);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("Element count N of multi-element models (GMS: alpha_i, k_i per element)");
  ImGui::EndDisabled();
}

void rounds_table(const ident::IdentReport& r) {
  if (!ImGui::BeginTable("rounds", 5, ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) return;
  for (const char* h : {"stage", "RMS train before [N]", "after [N]", "RMS validation before [N]", "after [N]"})
    ImGui::TableSetupColumn(h);
  ImGui::TableHeadersRow();
  for (std::size_t i = 0; i < r.rounds.size(); ++i) {
    const auto& rd = r.rounds[i];
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::Text("round %zu: %s", i + 1, rd.added ? std::string(ident::effect_name(*rd.added)).c_str() : "nothing kept");
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", rd.rms_train_before);
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", rd.rms_train_after);
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", rd.rms_validation_before);
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", rd.rms_validation_after);
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
  st.job.reset();
  return false;
}

}  // namespace

void identify_start(AppState& s, const IdentifyInputs& in) {
  auto& st = s.slot<IdentifyState>("identify");
  if (collect(st)) return;  // one run at a time
  static_cast<Config&>(st) = in;
  start(st);
}

bool identify_busy(AppState& s) { return collect(s.slot<IdentifyState>("identify")); }

void identify_cancel(AppState& s) {
  auto& st = s.slot<IdentifyState>("identify");
  if (st.job) st.job->cancel = true;
}

const ident::IdentReport* identify_report(AppState& s) {
  auto& st = s.slot<IdentifyState>("identify");
  return st.result ? &st.result->report : nullptr;
}

std::string identify_error(AppState& s) { return s.slot<IdentifyState>("identify").error; }

void identify_send_to_plant(AppState& s) {
  auto& st = s.slot<IdentifyState>("identify");
  if (!st.result) return;
  s.pending.scenario = ident::identified_scenario(st.result->report, st.result->train);
  st.status = "sent to the Simulation panel";
}

void draw_identify_panel(AppState& s) {
  auto& st = s.slot<IdentifyState>("identify");
  const bool busy = st.job != nullptr;
  inputs(st, busy);
  if (!busy) {
    ImGui::BeginDisabled(st.data.empty());
    if (ImGui::Button("Identify")) start(st);
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Fit the base model, then run the residual loop");
  } else {
    Job& j = *st.job;
    std::string stage;
    int evals = 0;
    double rms = 0;
    {
      std::lock_guard<std::mutex> lock(j.m);
      stage = j.stage;
      evals = j.evaluations;
      rms = j.best_rms;
    }
    if (ImGui::Button("Cancel")) j.cancel = true;
    ImGui::SameLine();
    // Evaluations are not known in advance: the bar shows activity, the text what runs.
    ImGui::ProgressBar(static_cast<float>((evals % 500) / 500.0), ImVec2(ImGui::GetFontSize() * 16.0f, 0),
                       "");
    ImGui::SameLine();
    ImGui::Text("%s: %d evaluations, RMS %.4g N", stage.c_str(), evals, rms);
    collect(st);
  }
  if (!st.error.empty()) ImGui::TextColored(ImVec4(0.75f, 0.1f, 0.1f, 1), "%s", st.error.c_str());
  if (!st.result) return;
  const auto& r = st.result->report;
  ImGui::SameLine();
  if (ImGui::Button("Send model to plant")) identify_send_to_plant(s);
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Replace the Simulation panel's scenario: identified friction, identified mass, training motion");
  if (!st.status.empty()) {
    ImGui::SameLine();
    ImGui::TextUnformatted(st.status.c_str());
  }
  rounds_table(r);
  ImGui::BeginChild("##identfig", ImVec2(0, 0), true, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_figure(st.result->figure, true);
  ImGui::EndChild();
}

}  // namespace gmslab::ui

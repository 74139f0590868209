// gmslab ui: the Plant view - the assembled plant (core/sim/assembly.hpp) drawn as a schematic,
// the same code in the window and in `gmslab render PRESET --view plant`.
//
// Bodies are blocks on one axis (a body in contact with another is drawn on top of it), springs
// zig-zags, dampers dashpots, friction contacts hatched pads (blue while stuck, orange while
// slipping, with their force), ground hatched, drives arrows (a pull drive: its spring and damper
// to a drive point). Every part is labelled with its name and values in units. While a run goes the
// bodies move by their displacement times a magnification (auto: the largest displacement so far
// spans a third of a body's column), so springs stretch.
//
// layout_plant() is pure geometry (no ImGui), tested structurally; draw_plant() paints it.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/io/session_io.hpp"
#include "core/sim/assembly.hpp"

struct ImDrawList;

namespace gmslab::ui {

struct Box {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  float cx() const { return 0.5f * (x0 + x1); }
  float cy() const { return 0.5f * (y0 + y1); }
};

// Where a part is drawn at rest, in canvas pixels (origin top left).
struct PlantLayout {
  float width = 0, height = 0;
  float floor_y = 0;          // top of the ground hatch
  float wall_x = 0;           // right face of the left wall (ground for parts to ground)
  bool wall = false;          // some part ties to the wall
  std::vector<Box> bodies;    // per body
  std::vector<int> level;     // per body: 0 on the floor, 1 on top of a level-0 body, ...
  struct Link {               // a spring or damper
    float ax = 0, ay = 0;     // end at body a (moves with a)
    float bx = 0, by = 0;     // end at b (moves with b, fixed for ground)
    float lift = 0;           // > 0: drawn over the bodies at this height above the ends
  };
  std::vector<Link> springs, dampers;
  std::vector<Box> contacts;  // the pad between a and b (ground: a's bottom to the floor)
  struct DriveGlyph {
    float x = 0, y = 0;       // where the arrow / drive spring starts on the body
    float px = 0, py = 0;     // pull: the drive point at rest
    bool side = false;        // from the body's right face (nothing there), else from above
  };
  std::vector<DriveGlyph> drives;
};

PlantLayout layout_plant(const Assembly& a, float width, float height);

// What moves: from the last sample of a run (all zero before one).
struct PlantPose {
  std::vector<double> x;              // per body [m]
  std::vector<double> contact_force;  // per contact [N]
  std::vector<std::uint8_t> slipping; // per contact
  std::vector<double> spring_force;   // per spring [N]
  std::vector<double> drive_force;    // per drive [N]
  std::vector<double> drive_point;    // per drive: pull point position [m]
  double t = 0.0;                     // [s]
};
PlantPose rest_pose(const Assembly& a);
PlantPose pose_of(const AssemblySimulation& sim);

// Auto magnification [px per m] for a layout: max |x| over the trace so far -> a third of the
// smallest body column (1 when nothing moved).
double auto_magnification(const PlantLayout& l, const AssemblyTrace& tr);

// Where draw_plant put the bodies (as moved by the pose) and the labels of the parts (names,
// values, forces), in the draw list's pixels.
struct PlantDrawn {
  std::vector<Box> bodies, labels;
};
// Paints the schematic into `dl` with its top left at (x0, y0). Each part's label goes where it
// belongs (springs above, dampers below, ground contacts under the floor, drives above their
// arrow) and moves by half lines to the nearest place where it overlaps no body, no header row and
// no label placed before.
PlantDrawn draw_plant(ImDrawList* dl, float x0, float y0, const PlantLayout& l, const Assembly& a, const PlantPose& pose,
                      double px_per_m);

// Editing: a part of the plant, what the mouse hits, and the edits (pure data; the panel applies an
// edit only when the edited plant validates, with undo / redo).
struct PartRef {
  enum class Kind { None, Body, Spring, Damper, Contact, Drive };
  Kind kind = Kind::None;
  int index = -1;
  bool operator==(const PartRef&) const = default;
};
const char* to_string(PartRef::Kind k);
// The part under canvas point (mx, my) for the layout drawn with `pose` and `px_per_m`; None if
// nothing is within 6 px. Drives and contacts before bodies, springs and dampers last.
PartRef hit_test(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double px_per_m, float mx, float my);
// The plant without the part; removing a body removes every part attached to it and renumbers.
Assembly remove_part(const Assembly& a, PartRef p);
// The plant with a new part (unique name "<kind><n>") attached to body `at` and ground (a body:
// tied to `at` - or ground when the plant is empty - by a 1000 N/m spring). Returns its ref.
PartRef add_part(Assembly& a, PartRef::Kind kind, int at);

// Connecting by dragging: the end under canvas point (mx, my) - a body (its block, as drawn with
// `pose`, or within 8 px of its faces), ground (the floor hatch and below, or the wall when one is
// drawn) or kNoEnd (also anywhere outside the schematic's width x height).
inline constexpr int kNoEnd = -2;
int attachment_at(const PlantLayout& l, const Assembly& a, const PlantPose& pose, double px_per_m, float mx, float my);
// Adds a `kind` (spring 1000 N/m, damper 1 N s/m or contact with GMS defaults; unique name) from
// `from` to `to` (body indices or kGround; ground becomes end b). Returns None and leaves `a` as it
// was when the ends are the same, both ground, either is kNoEnd, or `kind` is not one of the three.
PartRef connect_parts(Assembly& a, PartRef::Kind kind, int from, int to);

// The Plant panel's state: its own assembled scenario and run (v1 presets load as one body).
struct PlantPanelState {
  std::string path;
  std::unique_ptr<AssemblyScenario> scenario;
  std::unique_ptr<AssemblySimulation> sim;
  bool running = false;
  // Largest memory of the run's trace [bytes]: a longer run is compacted keeping every output's
  // extremes (AssemblySimulation, TraceOptions::max_bytes), as the Simulation tab's.
  std::size_t history_bytes = std::size_t{64} << 20;
  double speed = 1.0;                  // simulated s per wall-clock s
  float magnification = 0.0f;          // px per mm; 0 = auto
  std::vector<std::uint8_t> plotted;   // per output channel
  int tf_drive = 0, tf_output = 0;     // linear plant: drive index, body index of the output
  bool tf_sliding = true;              // contacts sliding at their default v0 (else stuck)
  PartRef selected;                    // the part being edited
  std::vector<AssemblyScenario> undo, redo;
  std::string edit_msg;                // why the last edit was not applied
  // Drag-to-connect: the part kind a drag creates, the end the drag started on (kNoEnd: none),
  // where it started (canvas px), and the hint after a drag that connected nothing.
  PartRef::Kind connect_kind = PartRef::Kind::Spring;
  int drag_from = kNoEnd;
  float drag_x = 0.0f, drag_y = 0.0f;
  std::string hint;
  // The schematic as last drawn (screen position of its top left, layout, pose, px per m), for
  // input and tests.
  float canvas_x = 0.0f, canvas_y = 0.0f;
  PlantLayout canvas_layout;
  PlantPose canvas_pose;
  double canvas_mag = 1.0;
  PlantDrawn canvas_drawn;
  std::string error;
};

// Loads (validated: throws InputError); resets the run.
void load_plant(PlantPanelState& st, const AssemblyScenario& s, const std::string& path);
// Runs to simulated time t (t < 0: the end). Throws SimulationError.
void plant_run_until(PlantPanelState& st, double t);
// Applies an edited scenario when it validates (the run restarts; the old one goes on the undo
// stack); else keeps the plant and sets edit_msg. Returns whether it was applied.
bool apply_plant_edit(PlantPanelState& st, const AssemblyScenario& edited);
// The panel as the session saves it (PlantTabSettings, core/io/session_io.hpp): plant, path,
// speed, magnification, plotted outputs, linear-plant choice; and back (loads the plant: the run
// restarts, the undo history is empty).
PlantTabSettings plant_tab_settings(const PlantPanelState& st);  // st.scenario must be set
void apply_plant_tab_settings(PlantPanelState& st, const PlantTabSettings& t);
void plant_undo(PlantPanelState& st);
void plant_redo(PlantPanelState& st);
// A preset the panel's combo offers: its menu label and file.
struct PresetChoice {
  std::string label, path;
};
// `presets` (called only while the presets combo is open; none: no combo) lists what it offers.
void draw_plant_panel(PlantPanelState& st, double frame_dt,
                      const std::function<std::vector<PresetChoice>()>& presets = {});

}  // namespace gmslab::ui

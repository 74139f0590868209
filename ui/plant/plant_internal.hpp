// Internals shared by the Plant panel's files (ui/plant/*.cpp): the schematic's colours and the
// displacement of a drawn body. Not part of the panel's interface (plant_view.hpp).
#pragma once

#include <imgui.h>

#include "ui/plant/plant_view.hpp"

namespace gmslab::ui::plant_detail {

inline const ImU32 kInk = IM_COL32(30, 30, 34, 255);
inline const ImU32 kDimInk = IM_COL32(90, 90, 98, 255);
inline const ImU32 kBody = IM_COL32(205, 215, 228, 255);
inline const ImU32 kStick = IM_COL32(0, 114, 178, 255);
inline const ImU32 kSlip = IM_COL32(230, 120, 0, 255);
inline const ImU32 kDrive = IM_COL32(0, 158, 115, 255);

// Horizontal offset [px] at which a body is drawn: its displacement times the magnification,
// clamped to the canvas.
float body_dx(const PlantLayout& l, const PlantPose& pose, double mag, int body);

// The selected part's fields; an edit is applied only when the plant validates.
void part_editor(PlantPanelState& st);

}  // namespace gmslab::ui::plant_detail

// gmslab ui: editors for the plant, the drive (kind and signal) and the run settings of a
// scenario. Every field has its SI unit and a tooltip; with marks, a value out of range is
// rejected on the field (FieldMarks), else clamped to the range.
#pragma once

#include "core/sim/scenario.hpp"
#include "ui/param_editor.hpp"

namespace gmslab::ui {

// Mass [kg], spring to ground [N/m], damper to ground [N s/m]. Returns true when changed.
bool edit_plant(Plant& p, FieldMarks* marks = nullptr);
// Drive kind, its signal (fields by signal kind, in the driven quantity's unit) and, for pull,
// the pulling spring and damper. Returns true when changed.
bool edit_drive(Drive& d, FieldMarks* marks = nullptr);
// Step dt [s], duration [s], record_every [-]. Returns true when changed.
bool edit_run(RunSettings& r, FieldMarks* marks = nullptr);

// Unit of the driven quantity: "m" (displacement, pull), "m/s" (velocity) or "N" (force).
const char* drive_unit(Drive::Kind k);

}  // namespace gmslab::ui

// gmslab ui: editors for the plant, the drive (kind and signal) and the run settings of a
// scenario. Every field has its SI unit and a tooltip; values are clamped to their ranges.
#pragma once

#include "core/sim/scenario.hpp"

namespace gmslab::ui {

// Mass [kg], spring to ground [N/m], damper to ground [N s/m]. Returns true when changed.
bool edit_plant(Plant& p);
// Drive kind, its signal (fields by signal kind, in the driven quantity's unit) and, for pull,
// the pulling spring and damper. Returns true when changed.
bool edit_drive(Drive& d);
// Step dt [s], duration [s], record_every [-]. Returns true when changed.
bool edit_run(RunSettings& r);

// Unit of the driven quantity: "m" (displacement, pull), "m/s" (velocity) or "N" (force).
const char* drive_unit(Drive::Kind k);

}  // namespace gmslab::ui

// gmslab ui: Escape closes popups. ImGui 1.86 closes popups on Escape only with keyboard
// navigation, which the window does not enable; these two calls give every popup that key.
#pragma once

namespace gmslab::ui {

// Once per frame, outside any popup (handle_shortcuts calls it): Escape closes the topmost open
// popup (a context menu, a menu of the menu bar, a combo's list) unless it is a modal; a modal
// runs its own Cancel (escape_cancels_popup). While a text field has the keyboard, Escape
// belongs to the field (it leaves the field; the next Escape closes). True when one was closed.
bool close_popup_on_escape();

// Inside a modal's BeginPopupModal / EndPopup: true when Escape was pressed and this modal is the
// topmost popup (no text field has the keyboard); the caller runs its Cancel and closes it.
bool escape_cancels_popup();

}  // namespace gmslab::ui

#pragma once
// The status bar's line for the PVS debugger (PvsView.h): the bake's progress or its source file,
// the cut-off, the selected gap, and what the shown cell sees.

#include <QString>

#include "editor/PvsView.h"

namespace sightline::ui {

QString pvsStatusText(const PvsView& view);

} // namespace sightline::ui

#pragma once
// Qt painting (fonts, charts) needs a QApplication; the CLI has none, so one is made on demand,
// on Qt's offscreen platform when there is no display.

#include <memory>

#include <QApplication>

namespace sightline {

/// A new application when none exists (keep it alive while painting), else null.
std::unique_ptr<QApplication> ensureApplication();

} // namespace sightline

#pragma once
// Edit > Preferences: the designer's own settings, kept with QSettings (per user, not in the
// project): how fast an orbit turns and how fast flying moves ("orbit speed as a
// setting"), as multiples of the defaults.

#include <QDialog>

#include "ViewportController.h"

class QDoubleSpinBox;

namespace sightline::ui {

/// The saved speeds ("navigation/orbitSpeed", "navigation/flySpeed"); a missing or nonsensical
/// value reads as 1x, and values are kept within the dialog's range.
NavigationSpeeds loadNavigationSpeeds();
void saveNavigationSpeeds(const NavigationSpeeds& speeds);

class PreferencesDialog : public QDialog {
    Q_OBJECT
public:
    explicit PreferencesDialog(const NavigationSpeeds& speeds, QWidget* parent = nullptr);

    NavigationSpeeds speeds() const;
    QDoubleSpinBox* orbitField() const { return orbit_; }
    QDoubleSpinBox* flyField() const { return fly_; }

private:
    QDoubleSpinBox* orbit_ = nullptr;
    QDoubleSpinBox* fly_ = nullptr;
};

} // namespace sightline::ui

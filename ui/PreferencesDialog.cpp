#include "PreferencesDialog.h"

#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QSettings>

#include <algorithm>
#include <cmath>

namespace sightline::ui {

namespace {
constexpr const char* kOrbitKey = "navigation/orbitSpeed";
constexpr const char* kFlyKey = "navigation/flySpeed";
constexpr double kMinSpeed = 0.1, kMaxSpeed = 10.0;

double speedSetting(const char* key)
{
    bool ok = false;
    const double value = QSettings().value(key, 1.0).toDouble(&ok);
    return ok && std::isfinite(value) ? std::clamp(value, kMinSpeed, kMaxSpeed) : 1.0;
}
} // namespace

NavigationSpeeds loadNavigationSpeeds() { return {speedSetting(kOrbitKey), speedSetting(kFlyKey)}; }

void saveNavigationSpeeds(const NavigationSpeeds& speeds)
{
    QSettings settings;
    settings.setValue(kOrbitKey, speeds.orbit);
    settings.setValue(kFlyKey, speeds.fly);
}

PreferencesDialog::PreferencesDialog(const NavigationSpeeds& speeds, QWidget* parent) : QDialog(parent)
{
    setWindowTitle(tr("Preferences"));
    auto* form = new QFormLayout(this);
    auto field = [this](double value, const QString& tip) {
        auto* box = new QDoubleSpinBox(this);
        box->setRange(kMinSpeed, kMaxSpeed);
        box->setDecimals(2);
        box->setSingleStep(0.1);
        box->setSuffix(QString::fromUtf8("×"));
        box->setValue(value);
        box->setToolTip(tip);
        return box;
    };
    orbit_ = field(speeds.orbit, tr("How far an orbit (left drag) turns per pixel of mouse motion; 1× is 0.46° a pixel"));
    orbit_->setObjectName("orbitSpeed");
    fly_ = field(speeds.fly, tr("How fast W A S D Q E move while the right button is held; 1× crosses 40% of the level a second"));
    fly_->setObjectName("flySpeed");
    form->addRow(tr("Orbit speed"), orbit_);
    form->addRow(tr("Fly speed"), fly_);
    auto* note = new QLabel(tr("Kept for this user, not in the project."), this);
    note->setEnabled(false);
    form->addRow(note);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
    connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    form->addRow(buttons);
}

NavigationSpeeds PreferencesDialog::speeds() const { return {orbit_->value(), fly_->value()}; }

} // namespace sightline::ui

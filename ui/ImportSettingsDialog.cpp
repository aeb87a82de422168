#include "ImportSettingsDialog.h"

#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include <cmath>

namespace sightline::ui {

namespace {

struct Unit {
    const char* name;
    double metres;
};
const Unit kUnits[] = {{"metres (glTF, Unity, Godot)", 1.0},       {"centimetres (Unreal, Maya)", 0.01},
                       {"millimetres (CAD)", 0.001},               {"inches (Quake, Source, Hammer)", 0.0254},
                       {"feet", 0.3048},                           {"other: metres per unit below", 0.0}};
const std::pair<const char*, const char*> kUps[] = {{"+y", "+Y (glTF, Unity, Godot, Maya)"}, {"+z", "+Z (Blender, Quake, Unreal, 3ds Max)"},
                                                    {"-y", "-Y"},                              {"-z", "-Z"},
                                                    {"+x", "+X"},                              {"-x", "-X"}};

} // namespace

ImportSettingsDialog::ImportSettingsDialog(const SceneImport& current, std::string guessedUp, QWidget* parent)
    : QDialog(parent), guessedUp_(std::move(guessedUp))
{
    setWindowTitle(tr("Import Settings"));
    setObjectName("importSettings");
    auto* layout = new QVBoxLayout(this);
    auto* intro = new QLabel(tr("How the level's file is written: which way is up in it, and what one of its units "
                                "measures. The level is turned and scaled before everything else (patches, occluders, "
                                "lights and cells stay where they are in the world)."),
                             this);
    intro->setWordWrap(true);
    layout->addWidget(intro);
    auto* form = new QFormLayout;
    up_ = new QComboBox(this);
    up_->setObjectName("sceneUp");
    for (const auto& [key, label] : kUps)
        up_->addItem(tr(label), QString::fromLatin1(key));
    auto* guess = new QPushButton(tr("Guess from the Geometry (%1)").arg(QString::fromStdString(guessedUp_)), this);
    guess->setObjectName("guessUp");
    connect(guess, &QPushButton::clicked, this, [this] { up_->setCurrentIndex(up_->findData(QString::fromStdString(guessedUp_))); });
    auto* upRow = new QHBoxLayout;
    upRow->addWidget(up_, 1);
    upRow->addWidget(guess);
    form->addRow(tr("Up in the file"), upRow);
    units_ = new QComboBox(this);
    units_->setObjectName("sceneUnits");
    for (const Unit& unit : kUnits)
        units_->addItem(tr(unit.name), unit.metres);
    form->addRow(tr("One file unit is"), units_);
    scale_ = new QDoubleSpinBox(this);
    scale_->setObjectName("sceneScale");
    scale_->setDecimals(6);
    scale_->setRange(kMinSceneScale, kMaxSceneScale);
    scale_->setSuffix(tr(" m"));
    form->addRow(tr("Metres per unit"), scale_);
    layout->addLayout(form);
    connect(units_, &QComboBox::currentIndexChanged, this, [this](int index) {
        const double metres = units_->itemData(index).toDouble();
        scale_->setEnabled(metres == 0.0);
        if (metres > 0.0)
            scale_->setValue(metres);
    });
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel, this);
    connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    layout->addWidget(buttons);
    setSettings(current);
}

void ImportSettingsDialog::setSettings(const SceneImport& settings)
{
    up_->setCurrentIndex(std::max(0, up_->findData(QString::fromStdString(settings.up))));
    int unit = units_->count() - 1;   // other
    for (int i = 0; i + 1 < units_->count(); ++i)
        if (std::abs(units_->itemData(i).toDouble() - settings.scale) < 1e-12)
            unit = i;
    units_->setCurrentIndex(unit);
    scale_->setEnabled(unit == units_->count() - 1);
    scale_->setValue(settings.scale);
}

SceneImport ImportSettingsDialog::settings() const
{
    const double metres = units_->currentData().toDouble();
    return SceneImport{up_->currentData().toString().toStdString(), metres > 0.0 ? metres : scale_->value()};
}

} // namespace sightline::ui

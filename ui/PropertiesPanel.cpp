#include "PropertiesPanel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>
#include <QVBoxLayout>

#include <cmath>
#include <numbers>

#include "EditorDocument.h"
#include "editor/LightObjects.h"
#include "editor/PatchPresets.h"
#include "project/ProjectLights.h"
#include "base/Error.h"

namespace sightline::ui {

PropertiesPanel::PropertiesPanel(EditorDocument& document, QWidget* parent) : QWidget(parent), document_(document)
{
    auto* layout = new QVBoxLayout(this);
    title_ = new QLabel(this);
    title_->setStyleSheet("font-weight: bold");
    layout->addWidget(title_);

    addPatchGroup(layout);
    addLightGroup(layout);
    addTransformGroup(layout);
    layout->addStretch(1);

    // The panel's width followed its content (the patch fields are wider than "Nothing
    // selected"), and the viewport jumped between 745 and 1040 px as the selection changed. The widest
    // content is measured once, every group shown, and kept as the minimum and the preferred width.
    width_ = layout->sizeHint().width();
    setMinimumWidth(width_);

    connect(&document_, &EditorDocument::changed, this, &PropertiesPanel::refresh);
    connect(&document_, &EditorDocument::selectionChanged, this, [this] {
        samplesError_->hide();   // said of the patch that was selected
        refresh();
    });
    refresh();
}

/// The patch's group: its size preset, centre, edges, sample grid and the errors under them.
void PropertiesPanel::addPatchGroup(QVBoxLayout* layout)
{
    patchBox_ = new QGroupBox(tr("Patch"), this);
    auto* patchForm = new QFormLayout(patchBox_);
    addSizePresets(patchForm);
    centre_ = addVec3(patchForm, tr("Centre"), 0.05, " m");
    u_ = addVec3(patchForm, tr("Edge u"), 0.05, " m");
    v_ = addVec3(patchForm, tr("Edge v"), 0.05, " m");
    auto* samples = new QWidget(patchBox_);
    auto* samplesRow = new QHBoxLayout(samples);
    samplesRow->setContentsMargins(0, 0, 0, 0);
    na_ = new QSpinBox(samples);
    nb_ = new QSpinBox(samples);
    na_->setObjectName("samplesA");
    nb_->setObjectName("samplesB");
    // Any whole number may be typed: one out of range is refused with the reason (a spin box's own
    // range turned "-5" into 5 and 100000 into the maximum without a word).
    for (QSpinBox* box : {na_, nb_}) {
        box->setRange(-kTypedSamplesLimit, kTypedSamplesLimit);
        box->setKeyboardTracking(false);
        samplesRow->addWidget(box);
        connect(box, &QSpinBox::editingFinished, this, &PropertiesPanel::commit);
    }
    patchForm->addRow(tr("Samples"), samples);
    samplesError_ = new QLabel(patchBox_);
    samplesError_->setObjectName("samplesError");
    samplesError_->setStyleSheet("color: #e05050");
    patchForm->addRow(samplesError_);
    samplesError_->hide();
    pairError_ = new QLabel(patchBox_);
    pairError_->setWordWrap(true);
    pairError_->setStyleSheet("color: #e05050");
    patchForm->addRow(pairError_);
    layout->addWidget(patchBox_);
}

/// Size presets: doorway, window, player... (one undoable resize; "Custom" is what the fields say).
void PropertiesPanel::addSizePresets(QFormLayout* patchForm)
{
    size_ = new QComboBox(patchBox_);
    size_->setObjectName("patchSize");
    size_->addItem(tr("Custom"));
    for (const PatchPreset& preset : patchPresets())
        size_->addItem(tr("%1 %2 × %3 m").arg(QString::fromUtf8(preset.name.data(), qsizetype(preset.name.size())))
                           .arg(preset.width, 0, 'g', 3)
                           .arg(preset.height, 0, 'g', 3));
    size_->setToolTip(tr("Width × height (height upwards on a wall, whose patch keeps its bottom edge)"));
    connect(size_, &QComboBox::activated, this, [this](int index) {
        const ObjectRef selection = document_.selection();
        if (refreshing_ || index < 1 || !selection.isPatch() || document_.flags(selection).locked)
            return;
        const PatchPreset& preset = patchPresets()[std::size_t(index - 1)];
        const Patch before = std::get<Patch>(document_.state(selection));
        const Patch after = resizedPatch(before, preset.width, preset.height);
        if (after.u != before.u || after.v != before.v || after.corner != before.corner)
            document_.editState(selection, before, after,
                                tr("Resize %1 to %2").arg(document_.objectName(selection), QString::fromUtf8(preset.name.data(), qsizetype(preset.name.size())).toLower()));
    });
    patchForm->addRow(tr("Size"), size_);
}

/// The light's group: name, colour, intensity, range, spot cone, area samples and sides.
void PropertiesPanel::addLightGroup(QVBoxLayout* layout)
{
    lightBox_ = new QGroupBox(tr("Light"), this);
    lightForm_ = new QFormLayout(lightBox_);
    lightName_ = new QLineEdit(lightBox_);
    lightName_->setObjectName("lightName");
    connect(lightName_, &QLineEdit::editingFinished, this, &PropertiesPanel::commitLight);
    lightForm_->addRow(tr("Name"), lightName_);
    colour_ = addVec3(lightForm_, tr("Colour"), 0.05, "");
    for (QDoubleSpinBox* field : colour_) {
        field->setRange(0.0, 1000.0);
        disconnect(field, &QDoubleSpinBox::editingFinished, this, &PropertiesPanel::commit);
        connect(field, &QDoubleSpinBox::editingFinished, this, &PropertiesPanel::commitLight);
    }
    auto spin = [this](double lo, double hi, double step, const QString& suffix, const char* name) {
        auto* box = new QDoubleSpinBox(lightBox_);
        box->setObjectName(name);
        box->setRange(lo, hi);
        box->setDecimals(3);
        box->setSingleStep(step);
        box->setSuffix(suffix);
        box->setKeyboardTracking(false);
        connect(box, &QDoubleSpinBox::editingFinished, this, &PropertiesPanel::commitLight);
        return box;
    };
    intensity_ = spin(0.0, 1e7, 1.0, "", "lightIntensity");
    intensityLabel_ = new QLabel(tr("Intensity"), lightBox_);
    lightForm_->addRow(intensityLabel_, intensity_);
    range_ = spin(0.0, 1e5, 0.5, " m", "lightRange");
    range_->setSpecialValueText(tr("none"));
    range_->setToolTip(tr("The distance where the light fades to nothing (glTF's range); none: inverse square only"));
    lightForm_->addRow(tr("Range"), range_);
    inner_ = spin(0.0, 90.0, 1.0, QString::fromUtf8("°"), "lightInner");
    outer_ = spin(0.0, 90.0, 1.0, QString::fromUtf8("°"), "lightOuter");
    lightForm_->addRow(tr("Inner cone"), inner_);
    lightForm_->addRow(tr("Outer cone"), outer_);
    auto* lightSamples = new QWidget(lightBox_);
    auto* lightSamplesRow = new QHBoxLayout(lightSamples);
    lightSamplesRow->setContentsMargins(0, 0, 0, 0);
    lightNa_ = new QSpinBox(lightSamples);
    lightNb_ = new QSpinBox(lightSamples);
    for (QSpinBox* box : {lightNa_, lightNb_}) {
        box->setRange(-kTypedSamplesLimit, kTypedSamplesLimit);   // refused by validateLights, with the reason
        box->setKeyboardTracking(false);
        lightSamplesRow->addWidget(box);
        connect(box, &QSpinBox::editingFinished, this, &PropertiesPanel::commitLight);
    }
    lightSamples->setToolTip(tr("Point lights the area light is sampled into (its soft shadows' steps)"));
    lightForm_->addRow(tr("Samples"), lightSamples);
    twoSided_ = new QCheckBox(tr("Emits on both sides"), lightBox_);
    connect(twoSided_, &QCheckBox::toggled, this, &PropertiesPanel::commitLight);
    lightForm_->addRow(twoSided_);
    lightError_ = new QLabel(lightBox_);
    lightError_->setWordWrap(true);
    lightError_->setStyleSheet("color: #e05050");
    lightError_->setVisible(false);
    lightForm_->addRow(lightError_);
    layout->addWidget(lightBox_);
}

/// The object's transform group: position, rotation and scale.
void PropertiesPanel::addTransformGroup(QVBoxLayout* layout)
{
    transformBox_ = new QGroupBox(tr("Transform"), this);
    auto* transformForm = new QFormLayout(transformBox_);
    position_ = addVec3(transformForm, tr("Position"), 0.05, " m");
    rotation_ = addVec3(transformForm, tr("Rotation"), 5.0, QString::fromUtf8("°"));
    scale_ = addVec3(transformForm, tr("Scale"), 0.05, "");
    layout->addWidget(transformBox_);
}

QSize PropertiesPanel::sizeHint() const
{
    return {width_, QWidget::sizeHint().height()};
}

PropertiesPanel::Vec3Fields PropertiesPanel::addVec3(QFormLayout* form, const QString& label, double step, const QString& suffix)
{
    auto* row = new QWidget(form->parentWidget());
    auto* h = new QHBoxLayout(row);
    h->setContentsMargins(0, 0, 0, 0);
    Vec3Fields fields{};
    for (auto& field : fields) {
        field = new QDoubleSpinBox(row);
        field->setRange(-1e5, 1e5);
        field->setDecimals(3);
        field->setSingleStep(step);
        field->setSuffix(suffix);
        field->setKeyboardTracking(false);
        h->addWidget(field);
        connect(field, &QDoubleSpinBox::editingFinished, this, &PropertiesPanel::commit);
    }
    form->addRow(label, row);
    return fields;
}

void PropertiesPanel::setPairError(const QString& error)
{
    pairError_->setText(error);
    pairError_->setVisible(!error.isEmpty());
}

void PropertiesPanel::refresh()
{
    refreshing_ = true;
    const ObjectRef selection = document_.selection();
    // A locked object is shown, not edited (ObjectFlags.h).
    const bool locked = selection && document_.flags(selection).locked;
    title_->setText(selection ? (locked ? tr("%1 (locked)").arg(document_.objectName(selection)) : document_.objectName(selection))
                              : tr("Nothing selected"));
    patchBox_->setEnabled(!locked);
    transformBox_->setEnabled(!locked);
    patchBox_->setVisible(selection.isPatch());
    lightBox_->setVisible(selection.kind == ObjectKind::Light);
    transformBox_->setVisible(selection.kind == ObjectKind::Occluder || selection.kind == ObjectKind::SceneObject ||
                              selection.kind == ObjectKind::Light);
    auto set = [](const Vec3Fields& fields, const glm::dvec3& value) {
        for (int i = 0; i < 3; ++i)
            fields[std::size_t(i)]->setValue(value[i]);
    };
    if (selection.isPatch()) {
        const Patch p = std::get<Patch>(document_.state(selection));
        set(centre_, p.centre());
        set(u_, p.u);
        set(v_, p.v);
        na_->setValue(p.na);
        nb_->setValue(p.nb);
        const std::optional<std::size_t> preset = presetOf(p);
        size_->setCurrentIndex(preset ? int(*preset) + 1 : 0);
    } else if (selection) {
        const Decomposed parts = decompose(std::get<glm::mat4>(document_.state(selection)));
        set(position_, parts.position);
        set(rotation_, parts.rotationDegrees);
        set(scale_, parts.scale);
        // A light shows the rows that mean something for its type: a point light has no turn,
        // only an area light a size, and a sun no place (it is drawn above the level).
        const LightType type = selection.kind == ObjectKind::Light && selection.index < document_.lights().size()
                                   ? document_.lights()[selection.index].type
                                   : LightType::Area;
        const bool light = selection.kind == ObjectKind::Light;
        const auto showRow = [](const Vec3Fields& fields, bool shown) {
            QWidget* row = fields[0]->parentWidget();
            row->setVisible(shown);
            if (auto* form = qobject_cast<QFormLayout*>(row->parentWidget()->layout()))
                if (QWidget* label = form->labelForField(row))
                    label->setVisible(shown);
        };
        showRow(position_, !light || type != LightType::Directional);
        showRow(rotation_, !light || type != LightType::Point);
        showRow(scale_, !light || type == LightType::Area);
        if (light)
            refreshLight();
    }
    refreshing_ = false;
}

void PropertiesPanel::refreshLight()
{
    const ObjectRef selection = document_.selection();
    if (selection.index >= document_.lights().size())
        return;
    const Light& light = document_.lights()[selection.index];
    const bool area = light.type == LightType::Area, spot = light.type == LightType::Spot;
    const bool punctual = light.type == LightType::Point || spot;
    lightName_->setText(QString::fromStdString(light.name));
    for (int i = 0; i < 3; ++i)
        colour_[std::size_t(i)]->setValue(light.colour[i]);
    intensityLabel_->setText(area ? tr("Radiance") : tr("Intensity"));
    intensity_->setSuffix(area ? tr(" W/m²/sr") : light.type == LightType::Directional ? tr(" W/m²") : tr(" W/sr"));
    intensity_->setValue(area ? light.radiance : light.intensity);
    range_->setValue(light.range);
    inner_->setValue(light.innerAngle * 180.0 / std::numbers::pi);
    outer_->setValue(light.outerAngle * 180.0 / std::numbers::pi);
    lightNa_->setValue(light.area.na);
    lightNb_->setValue(light.area.nb);
    twoSided_->setChecked(light.twoSided);
    for (QWidget* w : std::initializer_list<QWidget*>{range_, lightForm_->labelForField(range_)})
        w->setVisible(punctual);
    for (QWidget* w : std::initializer_list<QWidget*>{inner_, outer_, lightForm_->labelForField(inner_), lightForm_->labelForField(outer_)})
        w->setVisible(spot);
    for (QWidget* w : std::initializer_list<QWidget*>{lightNa_->parentWidget(), lightForm_->labelForField(lightNa_->parentWidget()), twoSided_})
        w->setVisible(area);
    lightError_->setVisible(false);
}

void PropertiesPanel::commitLight()
{
    const ObjectRef selection = document_.selection();
    if (refreshing_ || selection.kind != ObjectKind::Light || selection.index >= document_.lights().size())
        return;
    const Light& light = document_.lights()[selection.index];
    nlohmann::json entry = document_.lightsJson().at(selection.index);
    const std::string name = lightName_->text().trimmed().toStdString();
    if (name.empty())
        entry.erase("name");
    else
        entry["name"] = name;
    // Fields the user did not touch keep their exact values (the boxes round to 3 decimals).
    auto kept = [](double field, double old) { return std::abs(field - old) <= 5e-4 ? old : field; };
    entry["colour"] = {kept(colour_[0]->value(), light.colour.r), kept(colour_[1]->value(), light.colour.g),
                       kept(colour_[2]->value(), light.colour.b)};
    if (light.type == LightType::Area) {
        entry["radiance"] = kept(intensity_->value(), light.radiance);
        entry["samples"] = {lightNa_->value(), lightNb_->value()};
        if (twoSided_->isChecked())
            entry["two_sided"] = true;
        else
            entry.erase("two_sided");
    } else {
        entry["intensity"] = kept(intensity_->value(), light.intensity);
    }
    if (light.type == LightType::Point || light.type == LightType::Spot) {
        if (range_->value() > 0.0)
            entry["range"] = kept(range_->value(), light.range);
        else
            entry.erase("range");
    }
    if (light.type == LightType::Spot) {
        const double toRadians = std::numbers::pi / 180.0;
        entry["inner_angle"] = kept(inner_->value() * toRadians, light.innerAngle);
        entry["outer_angle"] = kept(outer_->value() * toRadians, light.outerAngle);
    }
    try {
        document_.editLight(selection.index, entry, tr("Edit %1").arg(document_.objectName(selection)));
        lightError_->setVisible(false);
    } catch (const Error& e) {
        lightError_->setText(QString::fromStdString(e.what()));
        lightError_->setVisible(true);
    }
}

void PropertiesPanel::commit()
{
    const ObjectRef selection = document_.selection();
    if (refreshing_ || !selection || document_.flags(selection).locked)
        return;
    auto get = [](const Vec3Fields& fields) {
        return glm::dvec3(fields[0]->value(), fields[1]->value(), fields[2]->value());
    };
    const ObjectState before = document_.state(selection);
    ObjectState after;
    if (selection.isPatch()) {
        const Patch& old = std::get<Patch>(before);
        Patch p = old;
        // Fields the user did not touch keep their exact values (the boxes round to 3 decimals).
        auto differs = [](const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b) > 5e-4; };
        const glm::dvec3 u = get(u_), v = get(v_), centre = get(centre_);
        if (differs(u, old.u) || differs(v, old.v) || differs(centre, old.centre())) {
            p.u = differs(u, old.u) ? u : old.u;
            p.v = differs(v, old.v) ? v : old.v;
            p.corner = (differs(centre, old.centre()) ? centre : old.centre()) - 0.5 * (p.u + p.v);
        }
        p.na = na_->value();
        p.nb = nb_->value();
        if (p.corner == old.corner && p.u == old.u && p.v == old.v && p.na == old.na && p.nb == old.nb)
            return;
        try {
            Patch samples = old;   // the sample grid alone judged here; the pair's geometry below the fields
            samples.na = p.na;
            samples.nb = p.nb;
            validatePatch(samples, selection.kind == ObjectKind::Source ? "source" : "receiver");
            samplesError_->hide();
        } catch (const Error& e) {
            // One line that fits under the fields; the whole reason in the tooltip.
            const bool few = p.na < 1 || p.nb < 1;
            const QString limit = selection.kind == ObjectKind::Source ? tr("at most %1 samples in all").arg(kMaxSourceSamples)
                                                                       : tr("at most %1 a side").arg(kMaxReceiverSide);
            samplesError_->setText(tr("Refused %1 x %2: %3; kept %4 x %5")
                                       .arg(p.na).arg(p.nb).arg(few ? tr("at least 1 a side") : limit).arg(old.na).arg(old.nb));
            samplesError_->setToolTip(QString::fromUtf8(e.what()));
            samplesError_->show();
            refreshing_ = true;
            na_->setValue(old.na);
            nb_->setValue(old.nb);
            refreshing_ = false;
            return;
        }
        after = p;
    } else {
        Decomposed parts;
        parts.position = get(position_);
        parts.rotationDegrees = get(rotation_);
        parts.scale = get(scale_);
        const Decomposed old = decompose(std::get<glm::mat4>(before));
        auto same = [](const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b) <= 5e-4; };
        if (same(parts.position, old.position) && same(parts.rotationDegrees, old.rotationDegrees) && same(parts.scale, old.scale))
            return;
        after = compose(parts);
        if (selection.kind == ObjectKind::Light) {
            nlohmann::json lights = document_.lightsJson();
            lights.at(selection.index) =
                placedLightJson(lights.at(selection.index), document_.lights().at(selection.index).type, std::get<glm::mat4>(after));
            try {
                (void)parseLights(lights, "lights");
            } catch (const Error& e) {
                lightError_->setText(QString::fromStdString(e.what()));
                lightError_->setVisible(true);
                return;
            }
        }
    }
    document_.editState(selection, before, after, tr("Edit %1").arg(document_.objectName(selection)));
}

} // namespace sightline::ui

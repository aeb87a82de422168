#include "PropertiesPanel.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSpinBox>
#include <QVBoxLayout>

#include "EditorDocument.h"
#include "PatchPresets.h"

namespace sightline::ui {

PropertiesPanel::PropertiesPanel(EditorDocument& document, QWidget* parent) : QWidget(parent), document_(document)
{
    auto* layout = new QVBoxLayout(this);
    title_ = new QLabel(this);
    title_->setStyleSheet("font-weight: bold");
    layout->addWidget(title_);

    patchBox_ = new QGroupBox(tr("Patch"), this);
    auto* patchForm = new QFormLayout(patchBox_);
    // Size presets: doorway, window, player... (one undoable resize; "Custom" is what the fields say).
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
    centre_ = addVec3(patchForm, tr("Centre"), 0.05, " m");
    u_ = addVec3(patchForm, tr("Edge u"), 0.05, " m");
    v_ = addVec3(patchForm, tr("Edge v"), 0.05, " m");
    auto* samples = new QWidget(patchBox_);
    auto* samplesRow = new QHBoxLayout(samples);
    samplesRow->setContentsMargins(0, 0, 0, 0);
    na_ = new QSpinBox(samples);
    nb_ = new QSpinBox(samples);
    for (QSpinBox* box : {na_, nb_}) {
        box->setRange(1, kMaxReceiverSide);
        box->setKeyboardTracking(false);
        samplesRow->addWidget(box);
        connect(box, &QSpinBox::editingFinished, this, &PropertiesPanel::commit);
    }
    patchForm->addRow(tr("Samples"), samples);
    pairError_ = new QLabel(patchBox_);
    pairError_->setWordWrap(true);
    pairError_->setStyleSheet("color: #e05050");
    patchForm->addRow(pairError_);
    layout->addWidget(patchBox_);

    transformBox_ = new QGroupBox(tr("Transform"), this);
    auto* transformForm = new QFormLayout(transformBox_);
    position_ = addVec3(transformForm, tr("Position"), 0.05, " m");
    rotation_ = addVec3(transformForm, tr("Rotation"), 5.0, QString::fromUtf8("°"));
    scale_ = addVec3(transformForm, tr("Scale"), 0.05, "");
    layout->addWidget(transformBox_);
    layout->addStretch(1);

    // Issue 16 §2: the panel's width followed its content (the patch fields are wider than "Nothing
    // selected"), and the viewport jumped between 745 and 1040 px as the selection changed. The widest
    // content is measured once, every group shown, and kept as the minimum and the preferred width.
    width_ = layout->sizeHint().width();
    setMinimumWidth(width_);

    connect(&document_, &EditorDocument::changed, this, &PropertiesPanel::refresh);
    connect(&document_, &EditorDocument::selectionChanged, this, &PropertiesPanel::refresh);
    refresh();
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
    transformBox_->setVisible(selection.kind == ObjectKind::Occluder || selection.kind == ObjectKind::SceneObject);
    auto set = [](const Vec3Fields& fields, const glm::dvec3& value) {
        for (int i = 0; i < 3; ++i)
            fields[std::size_t(i)]->setValue(value[i]);
    };
    if (selection.isPatch()) {
        const Patch p = std::get<Patch>(document_.state(selection));
        set(centre_, p.centre());
        set(u_, p.u);
        set(v_, p.v);
        const int limit = selection.kind == ObjectKind::Source ? kMaxSourceSamples : kMaxReceiverSide;
        na_->setRange(1, limit);
        nb_->setRange(1, limit);
        na_->setValue(p.na);
        nb_->setValue(p.nb);
        const std::optional<std::size_t> preset = presetOf(p);
        size_->setCurrentIndex(preset ? int(*preset) + 1 : 0);
    } else if (selection) {
        const Decomposed parts = decompose(std::get<glm::mat4>(document_.state(selection)));
        set(position_, parts.position);
        set(rotation_, parts.rotationDegrees);
        set(scale_, parts.scale);
    }
    refreshing_ = false;
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
    }
    document_.editState(selection, before, after, tr("Edit %1").arg(document_.objectName(selection)));
}

} // namespace sightline::ui

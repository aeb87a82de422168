#pragma once
// Numeric editing of the selected object: a patch's size preset (PatchPresets.h), centre, edge
// vectors and sample grid, or an object's position, rotation (degrees) and scale; a light's name,
// colour, intensity (radiance for an area light), range, spot angles, samples and sides besides
// its transform (LightObjects.h). Each finished field, and each preset chosen, is one undo
// command; a light's field that would make it invalid is refused with the reason shown. A locked
// object's fields are greyed.

#include <array>

#include <QWidget>

class QComboBox;
class QDoubleSpinBox;
class QFormLayout;
class QGroupBox;
class QCheckBox;
class QLabel;
class QLineEdit;
class QSpinBox;
class QVBoxLayout;

namespace sightline::ui {

class EditorDocument;

class PropertiesPanel : public QWidget {
    Q_OBJECT
public:
    explicit PropertiesPanel(EditorDocument& document, QWidget* parent = nullptr);

    /// Shows the pair's problem under the patch fields (empty: valid).
    void setPairError(const QString& error);

    /// The patch's size: "Custom" (0) or a preset (1 + its index in patchPresets()).
    QComboBox* sizeCombo() const { return size_; }

    /// One width whatever is selected, so the dock (and the viewport beside it) never jumps.
    QSize sizeHint() const override;

private:
    using Vec3Fields = std::array<QDoubleSpinBox*, 3>;
    Vec3Fields addVec3(QFormLayout* form, const QString& label, double step, const QString& suffix);
    // One builder per group of fields, in the panel's order (the tab order follows).
    void addPatchGroup(QVBoxLayout* layout);
    void addSizePresets(QFormLayout* patchForm);
    void addLightGroup(QVBoxLayout* layout);
    void addTransformGroup(QVBoxLayout* layout);
    void refresh();
    void refreshLight();
    void commit();
    void commitLight();

    EditorDocument& document_;
    QLabel* title_ = nullptr;
    QGroupBox* patchBox_ = nullptr;
    QGroupBox* transformBox_ = nullptr;
    QComboBox* size_ = nullptr;
    Vec3Fields centre_{}, u_{}, v_{};
    QSpinBox* na_ = nullptr;
    QSpinBox* nb_ = nullptr;
    Vec3Fields position_{}, rotation_{}, scale_{};
    QLabel* pairError_ = nullptr;
    QLabel* samplesError_ = nullptr;   ///< a typed sample count refused, and why
    static constexpr int kTypedSamplesLimit = 1'000'000'000;
    QGroupBox* lightBox_ = nullptr;
    QLineEdit* lightName_ = nullptr;
    Vec3Fields colour_{};
    QDoubleSpinBox* intensity_ = nullptr;
    QLabel* intensityLabel_ = nullptr;
    QDoubleSpinBox* range_ = nullptr;
    QDoubleSpinBox* inner_ = nullptr;
    QDoubleSpinBox* outer_ = nullptr;
    QSpinBox* lightNa_ = nullptr;
    QSpinBox* lightNb_ = nullptr;
    QCheckBox* twoSided_ = nullptr;
    QLabel* lightError_ = nullptr;
    QFormLayout* lightForm_ = nullptr;
    bool refreshing_ = false;
    int width_ = 0;   // the widest content's width, measured once with every group shown
};

} // namespace sightline::ui

#pragma once
// File > Import Settings: which way is up in the level's file and its unit (project/SceneImport.h),
// with the usual tools' conventions named, a custom scale, and a guess from the geometry.

#include <QDialog>

#include <string>

#include "project/SceneImport.h"

class QComboBox;
class QDoubleSpinBox;
class QLabel;

namespace sightline::ui {

class ImportSettingsDialog : public QDialog {
    Q_OBJECT
public:
    /// `guessedUp`: what guessSceneUp says of the file, offered by a button.
    ImportSettingsDialog(const SceneImport& current, std::string guessedUp, QWidget* parent = nullptr);

    SceneImport settings() const;
    void setSettings(const SceneImport& settings);

private:
    QComboBox* up_ = nullptr;
    QComboBox* units_ = nullptr;
    QDoubleSpinBox* scale_ = nullptr;
    std::string guessedUp_;
};

} // namespace sightline::ui

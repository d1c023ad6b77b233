#pragma once
/// File ▸ Import Animated Mesh's options: which take of the file, which part of it, and whether it loops
/// (io::AnimationRequest). A rig often arrives with several takes (swim, turn, idle); the editor used to take
/// the first, whole and looping.

#include "io/import/animation_import.h"

#include <QDialog>

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;

namespace softtouch::ui {

class TakeDialog final : public QDialog {
    Q_OBJECT
public:
    /// `takes` as io::animationTakes() lists them (at least one); `fileName` for the title.
    TakeDialog(io::TakeList takes, const QString& fileName, QWidget* parent = nullptr);

    /// The take, range and looping chosen (the default sample rate).
    io::AnimationRequest request() const;

private:
    void takeChosen(int index);

    io::TakeList m_takes;
    QComboBox* m_take = nullptr;
    QDoubleSpinBox* m_start = nullptr;
    QDoubleSpinBox* m_end = nullptr;
    QCheckBox* m_loop = nullptr;
};

}  // namespace softtouch::ui

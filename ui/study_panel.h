#pragma once
/// The speed/accuracy dock: the study's error-against-cost plot (docs/study.csv, made by
/// `softtouch-cli study`) with the current integrator, time step and lattice marked on it, and the
/// cheapest measured setting within the user's error target, so the trade is chosen by measurement.

#include "bench/study.h"
#include "ui/document.h"

#include <QWidget>

class QDoubleSpinBox;
class QLabel;
class QPushButton;

namespace softtouch::ui {

/// Plot of the study with the current settings.
class StudyPanel : public QWidget {
    Q_OBJECT
public:
    /// `csvPath`: the study to show (docs/study.csv).
    StudyPanel(Document* document, const QString& csvPath, QWidget* parent = nullptr);

    /// The study row matching the current settings, or nullptr (settings the study did not measure).
    const bench::StudyRow* currentRow() const;
    /// The cheapest measured setting whose RMS error is within the target, or nullptr.
    const bench::StudyRow* suggestion() const;
    /// Whether the study file was read.
    bool hasStudy() const { return !m_study.rows.empty(); }

protected:
    void resizeEvent(QResizeEvent* event) override;

private:
    void refresh();
    void applySuggestion();

    Document* m_document;
    bench::StudyResult m_study;
    QString m_problem;
    QLabel* m_plot = nullptr;
    QLabel* m_text = nullptr;
    QDoubleSpinBox* m_target = nullptr;
    QPushButton* m_apply = nullptr;
};

/// "4x4x4 bezier": how the study names a lattice.
std::string studyResolutionName(const Lattice& lattice);

}  // namespace softtouch::ui

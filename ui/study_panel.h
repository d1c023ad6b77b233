#pragma once
/// The speed/accuracy dock: measures the open scene (analysis::runStudy, quick grid, on a worker thread with
/// progress and Cancel), charts error against cost with the scene's own setting marked (point at a dot
/// to read its setting, click it to use it), names the cheapest measured setting within the user's error
/// target, applies a pick as one undo step and re-measures the scene as it then stands, so the trade is
/// chosen, and checked, by measurement on this scene.

#include "analysis/study.h"
#include "ui/document.h"

#include <QWidget>

#include <atomic>
#include <functional>
#include <optional>
#include <thread>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QStackedWidget;

namespace softtouch::ui {

class StudyChartView;

/// Measures the open scene's speed/accuracy trade and applies a pick.
class StudyPanel : public QWidget {
    Q_OBJECT
public:
    explicit StudyPanel(Document* document, QWidget* parent = nullptr);
    /// Cancels a running measurement and waits for its thread (the run in progress finishes first).
    ~StudyPanel() override;

    /// Whether a measurement of the scene finished (a cancelled one is not kept).
    bool hasStudy() const { return !m_study.rows.empty(); }
    /// The last finished measurement; its `error` is the kind chosen in the dock.
    const analysis::StudyResult& study() const { return m_study; }
    /// The measured row of the scene's own setting (integrator, step, lattice of its first object), or
    /// nullptr (not measured yet, or a setting the study did not measure).
    const analysis::StudyRow* currentRow() const;
    /// The cheapest measured setting whose error (the chosen kind) is within the target, or nullptr.
    const analysis::StudyRow* suggestion() const;
    /// The error target as a fraction of the box diagonal (the dock shows it in %).
    double target() const;
    /// A measurement or a re-measurement is running.
    bool isMeasuring() const { return m_worker.joinable(); }
    /// The scene changed (not by this dock's own pick) since it was measured.
    bool isOutOfDate() const { return hasStudy() && m_edits != m_studyEdits; }
    /// The scene's errors re-measured after the last pick was applied, against the study's reference.
    std::optional<analysis::Remeasured> remeasured() const { return m_remeasured; }
    /// Where the clip to measure comes from: the name of the clip Export… would write now ("" for the drivers),
    /// asked when a measurement starts. Without it, or when the clip plays a take or keys (which no other lattice
    /// can play), the dock measures what a bake plays by default.
    void setClipSource(std::function<std::string()> clip) { m_clipSource = std::move(clip); }

public slots:
    /// Measures a copy of the scene on a worker thread ("Measure this scene"); emits finished().
    void measure();
    /// Asks a running measurement to stop after the run in progress; emits finished() when it has. A
    /// re-measure (two runs) is not cancelled.
    void cancel();
    /// Applies suggestion() as one undo step, then re-measures the scene (emits finished() after).
    void applySuggestion();
    /// Applies the measured setting of row `row` (a click on its point in the chart) the same way;
    /// false when it cannot be used now (rowBlocker() says why).
    bool applyRow(int row);

signals:
    /// A measurement or re-measurement ended: finished, cancelled or failed (the dock says which).
    void finished();

protected:
    /// Keeps the panel's minimum height at what its wrapped text needs at this width, so the scroll area
    /// around it scrolls instead of laying the text over the plot (a layout's minimum ignores wrapping).
    void resizeEvent(QResizeEvent* event) override;
    void updateMinimumHeight();

private:
    /// Runs `job` on the worker thread; the job hands its result to the GUI thread with post().
    void startWorker(std::function<void()> job);
    /// Queues `call` on the GUI thread (the worker's only way to touch the dock).
    void post(std::function<void()> call);
    void studyDone(analysis::StudyResult result);
    void remeasureDone(Result<analysis::Remeasured> result);
    void sceneChanged();
    /// Flags the row that measured the scene's own setting as current (none when none did).
    void markCurrent();
    /// The texts, buttons and the line about the dot under the pointer.
    void refresh();
    /// The chart: rebuilt only when the study, its error kind or the current setting's mark changes.
    void refreshPlot();
    /// Why "Use the cheapest…" cannot be pressed now and what to do; empty when it can.
    QString applyBlocker() const;
    /// Why row `row`'s setting cannot be applied now (-1: any row); empty when it can.
    QString rowBlocker(int row) const;
    /// Names the setting of the point under the pointer (-1: none) below the chart and in a tooltip.
    void showPointer(int row);

    Document* m_document;
    std::function<std::string()> m_clipSource;  ///< See setClipSource().
    analysis::StudyResult m_study;
    std::thread m_worker;
    std::atomic<bool> m_cancel{false};  ///< Read by the worker's progress callback.
    // Staleness by counting the scene's changes: a result is current while the count is the one its
    // run started from. Our own pick does not count (the study measured it; the re-measure checks it).
    int m_edits = 0;                  ///< Changes to the scene seen so far.
    int m_runEdits = 0;               ///< m_edits when the running job started.
    int m_studyEdits = 0;             ///< m_edits when m_study's run started.
    int m_remeasuredEdits = 0;        ///< m_edits when m_remeasured's run started.
    bool m_applying = false;          ///< Our own pick is being pushed: its change signals are expected.
    bool m_remeasuring = false;       ///< The running job is a re-measure (it cannot be cancelled).
    QString m_notice;                 ///< The last job's outcome when it gave nothing (cancelled, failed).
    std::optional<analysis::Remeasured> m_remeasured;
    QStackedWidget* m_plotStack = nullptr;
    QLabel* m_plotNote = nullptr;
    StudyChartView* m_plot = nullptr;
    QLabel* m_pointer = nullptr;
    QLabel* m_text = nullptr;
    QDoubleSpinBox* m_target = nullptr;
    QComboBox* m_errorKind = nullptr;
    QPushButton* m_measure = nullptr;
    QPushButton* m_cancelButton = nullptr;
    QProgressBar* m_progress = nullptr;
    QPushButton* m_apply = nullptr;
    QLabel* m_check = nullptr;
};

}  // namespace softtouch::ui

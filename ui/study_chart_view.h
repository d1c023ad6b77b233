#pragma once
/// The Study dock's chart (ui/study_plot.h's StudyChart in a QChartView): the point under the pointer
/// is reported (and shown in a tooltip) with the setting it measured, and a click on a point picks it.

#include "ui/study_plot.h"

#include <QChartView>

namespace softtouch::ui {

class StudyChartView : public QChartView {
    Q_OBJECT
public:
    /// How near (pixels) the pointer must come to a point to be on it.
    static constexpr double kPickRadius = 8.0;

    explicit StudyChartView(QWidget* parent = nullptr);

    /// Shows `result` (its own error kind) with `marker`; a study with nothing plottable shows an empty chart.
    void setStudy(const analysis::StudyResult& result, const std::optional<PlotMarker>& marker);
    /// The chart shown (never null).
    const StudyChart* studyChart() const { return m_chart; }
    /// Where row `row` is drawn, in the viewport's coordinates (for the tests, which move the mouse there).
    QPoint viewportPositionOf(int row) const;
    /// The row under the pointer, or -1.
    int hoveredRow() const { return m_hovered; }

signals:
    /// The pointer came onto a row's point (index into the study's rows) or left every point (-1).
    void hovered(int row);
    /// A left click on a row's point.
    void clicked(int row);

protected:
    void mouseMoveEvent(QMouseEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void leaveEvent(QEvent* event) override;

private:
    int rowAt(QPoint viewportPosition) const;
    void setHovered(int row);

    StudyChart* m_chart = nullptr;  ///< Owned by the view (QChartView::setChart).
    int m_hovered = -1;
};

}  // namespace softtouch::ui

#include "ui/study_chart_view.h"

#include <QMouseEvent>
#include <QToolTip>

namespace softtouch::ui {

StudyChartView::StudyChartView(QWidget* parent) : QChartView(parent) {
    setRenderHint(QPainter::Antialiasing);
    setMouseTracking(true);
    viewport()->setMouseTracking(true);  // hover without a button held
    setStudy({}, std::nullopt);
}

void StudyChartView::setStudy(const analysis::StudyResult& result, const std::optional<PlotMarker>& marker) {
    auto* next = new StudyChart(result, marker, StudyChartSize::Dock);
    QChart* previous = chart();
    setChart(next);  // the view owns the new chart and hands the old one back
    delete previous;
    m_chart = next;
    setHovered(-1);
}

QPoint StudyChartView::viewportPositionOf(int row) const {
    return mapFromScene(m_chart->mapToScene(m_chart->positionOf(row)));
}

int StudyChartView::rowAt(QPoint viewportPosition) const {
    return m_chart->rowAt(m_chart->mapFromScene(mapToScene(viewportPosition)), kPickRadius);
}

void StudyChartView::setHovered(int row) {
    if (row == m_hovered)
        return;
    m_hovered = row;
    emit hovered(row);
}

void StudyChartView::mouseMoveEvent(QMouseEvent* event) {
    setHovered(rowAt(event->position().toPoint()));
    QChartView::mouseMoveEvent(event);
}

void StudyChartView::mousePressEvent(QMouseEvent* event) {
    if (event->button() == Qt::LeftButton)
        if (const int row = rowAt(event->position().toPoint()); row >= 0) {
            emit clicked(row);
            event->accept();
            return;
        }
    QChartView::mousePressEvent(event);
}

void StudyChartView::leaveEvent(QEvent* event) {
    setHovered(-1);
    QChartView::leaveEvent(event);
}

}  // namespace softtouch::ui

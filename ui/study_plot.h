#pragma once
/// The study's error-against-cost chart (log-log, a colour per integrator and a shape per lattice, the Pareto
/// front joined by a line, the do-nothing line, the current setting marked), built once with Qt Charts: the
/// editor's Study dock shows it in a StudyChartView (hover a point, click to use it) and `softtouch-cli study`
/// renders the same chart to study.png.

#include "analysis/study.h"

#include <QChart>
#include <QImage>

#include <optional>
#include <string>
#include <vector>

namespace softtouch::ui {

/// A point to mark on the plot (the editor's current settings).
struct PlotMarker {
    double costPerSecond = 0.0;  ///< Wall seconds per simulated second.
    double rmsError = 0.0;       ///< The study's error (StudyResult::error), relative to the box diagonal.
    std::string label;           ///< Shown beside the mark.
};

/// Whether `row` has a place on the log-log chart (finite, measured cost and error above zero: the
/// reference lattice's model error is 0).
bool plottable(const analysis::StudyRow& row, analysis::StudyError error);

/// Where the chart is shown: a picture of its own (study.png: legend on the right, full axis titles) or
/// the editor's dock (short names and titles, small text: the plot keeps most of a narrow dock).
enum class StudyChartSize { Picture, Dock };

/// How the legend names an integrator and a lattice: in full on a picture ("implicit-euler", "4x4x4 bezier solid");
/// short in the dock, whose legend is a narrow column beside the plot ("implicit", "4x4x4 solid", "6x6x6 B-spl.").
QString integratorLegendName(IntegratorKind kind, StudyChartSize size);
QString latticeLegendName(const analysis::StudyRow& row, StudyChartSize size);

/// The chart of one study. Needs a QApplication (Qt Charts draws through QGraphicsWidget).
class StudyChart : public QChart {
public:
    /// An empty chart when no row is plottable (hasPoints() false).
    StudyChart(const analysis::StudyResult& result, const std::optional<PlotMarker>& marker, StudyChartSize size);

    bool hasPoints() const { return !m_points.empty(); }
    /// The study row (index into result.rows) drawn nearest `position` (chart item coordinates) within
    /// `radius` pixels, or -1.
    int rowAt(QPointF position, double radius) const;
    /// Where row `row` is drawn (chart item coordinates); only for a row plottable() in the chart's error.
    QPointF positionOf(int row) const;

private:
    struct Point {
        int row;
        QPointF value;              ///< (cost per second, error)
        QAbstractSeries* series;    ///< The series it is drawn in (mapToPosition needs it).
    };
    std::vector<Point> m_points;
};

/// Renders the chart at the given size (pixels), titled, on white. Needs a QApplication (headless: the
/// offscreen platform, app/cli_offscreen_gui.h). A null image when no row is plottable.
QImage renderStudyPlot(const analysis::StudyResult& result, int width, int height, const std::optional<PlotMarker>& marker = {});

/// Writes the 1000x700 plot as a PNG atomically (needs a QApplication); returns an empty string or the
/// reason it failed.
std::string writeStudyPlot(const analysis::StudyResult& result, const std::string& path);

}  // namespace softtouch::ui

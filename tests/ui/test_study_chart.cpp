// The study's chart (ui/study_plot.h, ui/study_chart_view.h) on a made-up study, without a scene: every
// plottable row is drawn where its cost and error put it, in the PNG `softtouch-cli study` writes as
// in the editor's view; the pointer on a dot names that row and a click picks it.

#include "ui/study_chart_view.h"

#include <QApplication>
#include <QGraphicsScene>
#include <QLegendMarker>
#include <QLineSeries>
#include <QScatterSeries>
#include <QSignalSpy>
#include <QTest>

#include <cmath>
#include <map>
#include <set>

using namespace softtouch;
using namespace softtouch::ui;

namespace {

/// Twelve rows, three per integrator (on 3x3x3 and 4x4x4 Bezier and 5x5x5 B-spline lattices), spread over
/// three decades of cost and two of error (no two drawn within a few pixels of each other), plus one that
/// blew up and one measured at no cost.
analysis::StudyResult madeUpStudy() {
    analysis::StudyResult result;
    const IntegratorKind kinds[] = {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                    IntegratorKind::Xpbd};
    for (int i = 0; i < 12; ++i) {
        analysis::StudyRow r;
        r.integrator = kinds[i % 4];
        r.dt = 1.0 / (24 << (i % 3));
        r.lattice = LatticeShape{i < 8 ? LatticeKind::Bezier : LatticeKind::BSpline, {3 + i / 4, 3 + i / 4, 3 + i / 4}};
        r.resolution = analysis::latticeShapeName(r.lattice);
        r.costPerSecond = 1e-4 * std::pow(10.0, 3.0 * i / 11.0);
        r.rmsError = 5e-2 * std::pow(10.0, -2.0 * ((i * 5) % 12) / 11.0);  // not monotonic: a real front
        r.timeError = r.rmsError / 2;
        r.modelError = i == 11 ? 0.0 : r.rmsError / 3;  // the reference lattice has no model error
        result.rows.push_back(r);
    }
    analysis::StudyRow blewUp = result.rows[0];
    blewUp.finite = false;
    result.rows.push_back(blewUp);
    result.restError = 0.08;
    result.motionAmplitude = 0.1;
    analysis::markPareto(result);
    return result;
}

/// Dots in the integrators' series (the front's rings and the marker are series of their own).
int plottedPoints(const QChart& chart) {
    int points = 0;
    for (QAbstractSeries* s : chart.series())
        for (const IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                       IntegratorKind::Xpbd})
            if (s->name() == integratorLegendName(k, StudyChartSize::Picture) || s->name() == integratorLegendName(k, StudyChartSize::Dock))
                points += int(static_cast<QScatterSeries*>(s)->count());
    return points;
}

/// How near `image` comes to `colour` within `radius` pixels of `at` (sum of channel differences).
int nearestColour(const QImage& image, QPoint at, const QColor& colour, int radius) {
    int best = 3 * 255;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            const QColor c = image.pixelColor(at + QPoint(dx, dy));
            best = std::min(best, std::abs(c.red() - colour.red()) + std::abs(c.green() - colour.green()) +
                                      std::abs(c.blue() - colour.blue()));
        }
    return best;
}

}  // namespace

class TestStudyChart : public QObject {
    Q_OBJECT
private slots:
    // Every finite row with an error above zero is one dot, in its integrator's series; the front is the
    // rows markPareto flagged, joined in order of cost; the marker is its own series.
    void chartHoldsEveryPlottableRow() {
        analysis::StudyResult result = madeUpStudy();
        for (const analysis::StudyError kind : {analysis::StudyError::Total, analysis::StudyError::Model}) {
            result.error = kind;
            analysis::markPareto(result);
            int expected = 0, front = 0;
            for (const analysis::StudyRow& r : result.rows) {
                expected += plottable(r, kind) ? 1 : 0;
                front += r.pareto && plottable(r, kind) ? 1 : 0;  // a model error of 0 is on the front, off a log axis
            }
            QCOMPARE(expected, kind == analysis::StudyError::Model ? 11 : 12);
            const StudyChart chart(result, PlotMarker{1e-3, 1e-2, "current"}, StudyChartSize::Dock);
            QVERIFY(chart.hasPoints());
            QCOMPARE(plottedPoints(chart), expected);
            int frontPoints = -1, markers = 0;
            for (QAbstractSeries* s : chart.series()) {
                if (s->name() == "Pareto front")
                    frontPoints = int(static_cast<QLineSeries*>(s)->count());
                if (s->name() == "current settings")
                    markers = int(static_cast<QScatterSeries*>(s)->count());
            }
            QVERIFY(front >= 2);
            QCOMPARE(frontPoints, front);
            QCOMPARE(markers, 1);
        }
        // Nothing plottable: no chart, and no PNG (the CLI says so rather than write an empty plot).
        analysis::StudyResult blewUp = madeUpStudy();
        for (analysis::StudyRow& r : blewUp.rows)
            r.finite = false;
        QVERIFY(!StudyChart(blewUp, std::nullopt, StudyChartSize::Picture).hasPoints());
        QVERIFY(renderStudyPlot(blewUp, 400, 300).isNull());
        QVERIFY(!writeStudyPlot(blewUp, QDir::temp().filePath("never.png").toStdString()).empty());
    }

    // A dot's colour is its integrator and its shape its lattice (hollow on a B-spline): every row of one
    // lattice has one style, the three lattices three; the legend names each integrator once and each
    // lattice in its style.
    void latticesAreToldApartByShape() {
        const analysis::StudyResult result = madeUpStudy();
        for (const StudyChartSize size : {StudyChartSize::Picture, StudyChartSize::Dock}) {
            QGraphicsScene scene;  // laid out, as drawn: a legend marker is visible only in a scene
            auto* laidOut = new StudyChart(result, std::nullopt, size);
            scene.addItem(laidOut);
            laidOut->setGeometry(QRectF(0, 0, 1000, 700));
            const StudyChart& chart = *laidOut;
            // lattice -> the styles its dots have: marker shape, and 1 when hollow (a white fill)
            const auto styleOf = [](const QScatterSeries* s) { return 10 * int(s->markerShape()) + (s->brush().color() == Qt::white); };
            std::map<std::string, std::set<int>> shapes;
            for (int i = 0; i < 12; ++i) {
                const std::string& lattice = result.rows[std::size_t(i)].resolution;
                for (QAbstractSeries* s : chart.series()) {
                    auto* scatter = qobject_cast<QScatterSeries*>(s);
                    if (!scatter || scatter->name() != integratorLegendName(result.rows[std::size_t(i)].integrator, size))
                        continue;
                    for (const QPointF& p : scatter->points())
                        if (p == QPointF(result.rows[std::size_t(i)].costPerSecond, result.rows[std::size_t(i)].rmsError))
                            shapes[lattice].insert(styleOf(scatter));
                }
            }
            QCOMPARE(int(shapes.size()), 3);
            std::set<int> all;
            for (const auto& [lattice, used] : shapes) {
                QVERIFY2(used.size() == 1, lattice.c_str());
                all.insert(*used.begin());
            }
            QCOMPARE(int(all.size()), 3);
            QCOMPARE(*shapes["5x5x5 bspline"].begin() % 10, 1);  // hollow
            QCOMPARE(*shapes["3x3x3 bezier"].begin() % 10, 0);
            // The dock's narrow legend names them short, the picture in full.
            const analysis::StudyRow& bspline = *std::find_if(result.rows.begin(), result.rows.end(),
                                                              [](const analysis::StudyRow& r) { return r.resolution == "5x5x5 bspline"; });
            QCOMPARE(latticeLegendName(bspline, size), size == StudyChartSize::Dock ? QString("5x5x5 B-spl.") : QString("5x5x5 bspline"));
            analysis::StudyRow solid = bspline;
            solid.lattice = {LatticeKind::Bezier, {4, 4, 4}};
            solid.element = BodyElement::Solid;
            solid.resolution = analysis::studyModelName(solid.lattice, solid.element);
            QCOMPARE(latticeLegendName(solid, size), size == StudyChartSize::Dock ? QString("4x4x4 solid") : QString("4x4x4 bezier solid"));
            QCOMPARE(integratorLegendName(IntegratorKind::ImplicitEuler, size),
                     size == StudyChartSize::Dock ? QString("implicit") : QString("implicit-euler"));
            // The legend: one visible entry per integrator, one per lattice drawn in its shape.
            std::map<QString, int> visible;
            for (QLegendMarker* m : chart.legend()->markers())
                if (m->isVisible())
                    ++visible[m->label()];
            for (const IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                           IntegratorKind::Xpbd})
                QCOMPARE(visible[integratorLegendName(k, size)], 1);
            for (const auto& [lattice, used] : shapes) {
                const auto first = std::find_if(result.rows.begin(), result.rows.end(),
                                                [&, wanted = lattice](const analysis::StudyRow& r) { return r.resolution == wanted; });
                const QString label = latticeLegendName(*first, size);
                QCOMPARE(visible[label], 1);
                for (QLegendMarker* m : chart.legend()->markers())
                    if (m->label() == label) {
                        QCOMPARE(m->shape(), QLegend::MarkerShapeFromSeries);
                        QCOMPARE(styleOf(static_cast<QScatterSeries*>(m->series())), *used.begin());
                    }
            }
        }
    }

    // The headless PNG is the laid-out chart: at each row's position there is its integrator's colour,
    // and a row higher in error is drawn higher, a costlier one further right.
    void renderedPlotDrawsEachRowWhereItBelongs() {
        const analysis::StudyResult result = madeUpStudy();
        const QImage image = renderStudyPlot(result, 1000, 700);
        QCOMPARE(image.size(), QSize(1000, 700));
        // The same chart laid out at that size gives the positions (renderStudyPlot puts it at the origin).
        QGraphicsScene scene;
        auto* chart = new StudyChart(result, std::nullopt, StudyChartSize::Picture);
        scene.addItem(chart);
        chart->setGeometry(QRectF(0, 0, 1000, 700));
        const QRectF plot = chart->plotArea();
        QVERIFY2(plot.width() > 500 && plot.height() > 400, "the axes take most of the picture");
        std::map<IntegratorKind, QColor> colours;
        for (QAbstractSeries* s : chart->series())
            if (auto* scatter = qobject_cast<QScatterSeries*>(s))
                for (const IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                               IntegratorKind::Xpbd})
                    if (scatter->name() == QString::fromLatin1(integratorName(k).data()))
                        colours[k] = scatter->borderColor();  // a hollow dot (B-spline) is filled white
        QCOMPARE(int(colours.size()), 4);
        for (int i = 0; i < 12; ++i) {
            const QPointF at = chart->positionOf(i);
            QVERIFY2(plot.adjusted(-1, -1, 1, 1).contains(at), qPrintable(QString("row %1 at %2, %3").arg(i).arg(at.x()).arg(at.y())));
            // The dot's colour within its radius (the front's dashed line may run through its centre).
            const QColor want = colours[result.rows[std::size_t(i)].integrator];
            const int distance = nearestColour(image, at.toPoint(), want, 3);
            QVERIFY2(distance < 30, qPrintable(QString("row %1: nothing of its series' %2 near it").arg(i).arg(want.name())));
            // Far from every dot (between two decades of error, above the plot's top row) there is none of it.
            QVERIFY(nearestColour(image, QPoint(int(at.x()), int(plot.top()) + 2), want, 1) >= 30 ||
                    std::abs(at.y() - plot.top()) < 12);
            if (i > 0) {
                QVERIFY(at.x() > chart->positionOf(i - 1).x());
                const bool higher = result.rows[std::size_t(i)].rmsError > result.rows[std::size_t(i - 1)].rmsError;
                QCOMPARE(at.y() < chart->positionOf(i - 1).y(), higher);
            }
        }
        // The row that blew up has no place.
        QCOMPARE(chart->rowAt(chart->positionOf(0), 1.0), 0);
        QVERIFY(chart->positionOf(12).isNull());
    }

    // In the editor's view: the pointer on a dot reports that row, off every dot none; a click on a dot
    // picks its row and a click beside the dots picks nothing.
    void pointerAndClickPickARow() {
        const analysis::StudyResult result = madeUpStudy();
        StudyChartView view;
        view.resize(900, 600);
        view.setStudy(result, PlotMarker{2e-3, 3e-3, "current"});
        view.show();
        QVERIFY(QTest::qWaitForWindowExposed(&view));
        QSignalSpy hovered(&view, &StudyChartView::hovered);
        QSignalSpy clicked(&view, &StudyChartView::clicked);
        for (const int row : {0, 5, 11}) {
            const QPoint at = view.viewportPositionOf(row);
            QVERIFY(view.viewport()->rect().contains(at));
            QTest::mouseMove(view.viewport(), at + QPoint(3, -2));
            QTRY_COMPARE(view.hoveredRow(), row);
            QCOMPARE(hovered.last().at(0).toInt(), row);
            QTest::mouseClick(view.viewport(), Qt::LeftButton, {}, at);
            QCOMPARE(clicked.count(), 1);
            QCOMPARE(clicked.takeFirst().at(0).toInt(), row);
        }
        // Top left of the plot area: far from every dot (errors there are above every row's).
        const QPoint empty = view.mapFromScene(view.chart()->mapToScene(view.chart()->plotArea().topLeft() + QPointF(4, 4)));
        QTest::mouseMove(view.viewport(), empty);
        QTRY_COMPARE(view.hoveredRow(), -1);
        QCOMPARE(hovered.last().at(0).toInt(), -1);
        QTest::mouseClick(view.viewport(), Qt::LeftButton, {}, empty);
        QCOMPARE(clicked.count(), 0);
    }
};

int main(int argc, char** argv) {
    qputenv("QT_QPA_PLATFORM", "offscreen");  // widgets without a display; the chart needs no OpenGL
    QApplication app(argc, argv);
    TestStudyChart test;
    return QTest::qExec(&test, argc, argv);
}

#include "test_study_chart.moc"

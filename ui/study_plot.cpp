#include "ui/study_plot.h"

#include <array>
#include <QGraphicsScene>
#include <QLegendMarker>
#include <QLineSeries>
#include <QLogValueAxis>
#include <QPainter>
#include <QSaveFile>
#include <QScatterSeries>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace softtouch::ui {

using analysis::StudyResult;
using analysis::StudyRow;

bool plottable(const StudyRow& row, analysis::StudyError error) {
    return row.finite && row.costPerSecond > 0 && row.error(error) > 0;
}

namespace {

constexpr auto kKinds = integratorKinds();
const QColor kColours[] = {QColor(31, 119, 180), QColor(255, 127, 14), QColor(44, 160, 44), QColor(214, 39, 40)};
static_assert(std::size(kColours) >= kKinds.size(), "a colour for every integrator");
const QColor kMarkerColour(200, 0, 160);
const QColor kLatticeKeyColour(110, 110, 110);
/// Dot shapes of the lattices (the star marks the current setting).
constexpr QScatterSeries::MarkerShape kLatticeShapes[] = {
    QScatterSeries::MarkerShapeCircle, QScatterSeries::MarkerShapeRectangle, QScatterSeries::MarkerShapeTriangle,
    QScatterSeries::MarkerShapeRotatedRectangle, QScatterSeries::MarkerShapePentagon};

QString name(std::string_view text) { return QString::fromLatin1(text.data(), qsizetype(text.size())); }

/// [low, high] widened by a third of a decade each way (dots clear of the frame), then towards the nearer
/// power of ten until two lie inside: a log axis labels only those, and two labels give the scale.
std::pair<double, double> logRange(double low, double high) {
    double from = std::log10(low) - 0.15, to = std::log10(high) + 0.15;
    while (std::floor(to) - std::ceil(from) < 1) {
        const double below = std::ceil(from) - 1, above = std::floor(to) + 1;  // the next powers outside
        if (from - below <= above - to)
            from = below;
        else
            to = above;
    }
    return {std::pow(10.0, from), std::pow(10.0, to)};
}

QLogValueAxis* logAxis(const QString& title, double low, double high, const QFont& font) {
    auto* axis = new QLogValueAxis;
    axis->setBase(10.0);
    axis->setLabelFormat("%g");
    axis->setMinorTickCount(8);  // 2..9 of each decade: where a point sits between powers of ten reads off
    axis->setTitleText(title);
    axis->setTitleFont(font);
    axis->setLabelsFont(font);
    const auto [from, to] = logRange(low, high);
    // A hair beyond the range: the axis takes log(x)/log(10), which puts 0.01 at -1.9999999999999996, and
    // then leaves a power of ten at the very edge unlabelled.
    axis->setRange(from * (1 - 1e-9), to * (1 + 1e-9));
    return axis;
}

/// A series in the chart but not in its legend (the front's rings repeat the front's line).
void hideFromLegend(QChart* chart, QAbstractSeries* series) {
    for (QLegendMarker* marker : chart->legend()->markers(series))
        marker->setVisible(false);
}

}  // namespace

QString integratorLegendName(IntegratorKind kind, StudyChartSize size) {
    if (size == StudyChartSize::Picture)
        return name(integratorName(kind));
    return name(integratorInfo(kind).shortLabel);
}

QString latticeLegendName(const StudyRow& row, StudyChartSize size) {
    if (size == StudyChartSize::Picture)
        return QString::fromStdString(row.resolution);
    const std::array<int, 3>& n = row.lattice.nodes;
    QString text = QString("%1x%2x%3").arg(n[0]).arg(n[1]).arg(n[2]);
    if (row.lattice.kind != LatticeKind::Bezier)
        text += QObject::tr(" B-spl.");
    if (row.element == BodyElement::Solid)
        text += QObject::tr(" solid");
    return text;
}

StudyChart::StudyChart(const StudyResult& result, const std::optional<PlotMarker>& marker, StudyChartSize size) {
    const bool dock = size == StudyChartSize::Dock;
    setBackgroundRoundness(0);
    QFont font;
    font.setPixelSize(dock ? 11 : 13);
    legend()->setFont(font);
    legend()->setAlignment(Qt::AlignRight);
    if (dock) {
        setMargins(QMargins(2, 2, 2, 2));  // the dock's own title names the chart
    } else {
        setTitle(QObject::tr("Speed against accuracy (every integrator × dt × lattice)"));
        QFont title = font;
        title.setPixelSize(16);
        title.setBold(true);
        setTitleFont(title);
    }
    const auto error = [&](const StudyRow& r) { return r.error(result.error); };

    double xmin = std::numeric_limits<double>::max(), xmax = 0, ymin = std::numeric_limits<double>::max(), ymax = 0;
    const auto extend = [&](double x, double y) {
        xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
    };
    for (const StudyRow& r : result.rows)
        if (plottable(r, result.error))
            extend(r.costPerSecond, error(r));
    if (xmax <= 0)
        return;
    const bool marked = marker && marker->costPerSecond > 0 && marker->rmsError > 0;
    if (marked)
        extend(marker->costPerSecond, marker->rmsError);
    if (result.restError > 0)
        ymax = std::max(ymax, result.restError);  // doing nothing: the line every setting must stay well below
    // Ten times the reference's own uncertainty: targets below it cannot be certified (refusalOfTarget).
    const double floor = result.error == analysis::StudyError::Integration ? 0.0 : result.certifiedFrom();
    const bool showFloor = std::isfinite(floor) && floor > 0;
    if (showFloor)
        ymax = std::max(ymax, floor), ymin = std::min(ymin, floor);

    const QString errorKind = name(analysis::studyErrorName(result.error));
    auto* x = logAxis(dock ? QObject::tr("cost (s per clip s)") : QObject::tr("cost: wall seconds per second of clip"), xmin, xmax, font);
    auto* y = logAxis(dock ? QObject::tr("%1 error / diagonal").arg(errorKind)
                           : QObject::tr("%1 error / mesh diagonal (RMS, worst object)").arg(errorKind),
                      ymin, ymax, font);
    addAxis(x, Qt::AlignBottom);
    addAxis(y, Qt::AlignLeft);
    const auto add = [&](QXYSeries* series) {
        addSeries(series);
        series->attachAxis(x);
        series->attachAxis(y);
    };

    if (result.restError > 0) {
        auto* rest = new QLineSeries;
        rest->setName((dock ? QObject::tr("nothing: %1") : QObject::tr("doing nothing (the bodies at rest): %1")).arg(result.restError, 0, 'g', 3));
        rest->setPen(QPen(QColor(120, 120, 120), 1.5, Qt::DotLine));
        rest->append(x->min(), result.restError);
        rest->append(x->max(), result.restError);
        add(rest);
        if (dock) {  // named on the line itself: the dock's legend has room for the integrators only
            hideFromLegend(this, rest);
            auto* label = new QScatterSeries;
            label->setMarkerSize(0.1);
            // Left of the middle, the certified line's label right of it: the two lines often lie close.
            label->append(std::pow(x->min(), 0.7) * std::pow(x->max(), 0.3), result.restError);
            label->setPointLabelsFormat(rest->name());
            label->setPointLabelsColor(QColor(90, 90, 90));
            label->setPointLabelsFont(font);
            label->setPointLabelsVisible(true);
            add(label);
            hideFromLegend(this, label);
        }
    }
    if (showFloor) {
        auto* certifiable = new QLineSeries;
        certifiable->setName(QObject::tr("targets certified from: %1").arg(floor, 0, 'g', 3));
        certifiable->setPen(QPen(QColor(40, 40, 40), 1.5, Qt::DashDotLine));
        certifiable->append(x->min(), floor);
        certifiable->append(x->max(), floor);
        add(certifiable);
        if (dock) {  // named on the line itself, as doing nothing is
            hideFromLegend(this, certifiable);
            auto* label = new QScatterSeries;
            label->setMarkerSize(0.1);
            label->append(std::pow(x->min(), 0.3) * std::pow(x->max(), 0.7), floor);
            label->setPointLabelsFormat(QObject::tr("certified: %1").arg(floor, 0, 'g', 3));
            label->setPointLabelsColor(QColor(40, 40, 40));
            label->setPointLabelsFont(font);
            label->setPointLabelsVisible(true);
            add(label);
            hideFromLegend(this, label);
        }
    }
    // A dot's colour is its integrator, its shape its lattice: a shape per resolution in the order the study
    // lists them, filled on Bezier lattices and hollow on B-splines. Each integrator's legend entry is its
    // first series; each lattice has a grey entry of its own shape.
    struct DotStyle {
        std::string lattice;
        QScatterSeries::MarkerShape shape;
        bool hollow;
        QString legend;  ///< latticeLegendName()
    };
    std::vector<DotStyle> styles;  // one per lattice, in the order the study lists them
    std::map<LatticeKind, std::size_t> ofKind;
    for (const StudyRow& r : result.rows) {
        if (!plottable(r, result.error) ||
            std::any_of(styles.begin(), styles.end(), [&](const DotStyle& d) { return d.lattice == r.resolution; }))
            continue;
        const std::size_t n = ofKind[r.lattice.kind]++;
        styles.push_back({r.resolution, kLatticeShapes[n % std::size(kLatticeShapes)], r.lattice.kind != LatticeKind::Bezier,
                          latticeLegendName(r, size)});
    }
    const auto styleOf = [&](const std::string& lattice) -> const DotStyle& {
        return *std::find_if(styles.begin(), styles.end(), [&](const DotStyle& d) { return d.lattice == lattice; });
    };
    const auto styleDots = [&](QScatterSeries* s, const std::string& lattice, const QColor& colour) {
        const DotStyle& style = styleOf(lattice);
        s->setMarkerShape(style.shape);
        s->setMarkerSize(dock ? 8 : 9);
        s->setColor(colour);
        s->setBorderColor(colour);
        if (style.hollow) {
            s->setBrush(Qt::white);
            s->setPen(QPen(colour, 1.8));
        }
    };
    std::map<std::pair<std::size_t, std::string>, QScatterSeries*> series;  // (integrator, lattice)
    bool named[std::size(kKinds)] = {};
    const auto seriesFor = [&](std::size_t k, const std::string& lattice) {
        QScatterSeries*& s = series[{k, lattice}];
        if (!s) {
            s = new QScatterSeries;
            s->setName(integratorLegendName(kKinds[k], size));
            styleDots(s, lattice, kColours[k]);
            add(s);
            if (named[k])
                hideFromLegend(this, s);
            named[k] = true;
        }
        return s;
    };
    std::vector<int> front;
    for (int i = 0; i < int(result.rows.size()); ++i) {
        const StudyRow& r = result.rows[std::size_t(i)];
        if (!plottable(r, result.error))
            continue;
        const auto k = std::size_t(std::find(std::begin(kKinds), std::end(kKinds), r.integrator) - std::begin(kKinds)) % std::size(kKinds);
        const QPointF value(r.costPerSecond, error(r));
        QScatterSeries* s = seriesFor(k, r.resolution);
        s->append(value);
        m_points.push_back({i, value, s});
        if (r.pareto)
            front.push_back(i);
    }
    if (styles.size() > 1) {
        for (const DotStyle& style : styles) {
            auto* key = new QScatterSeries;  // no dots: a legend entry naming the shape
            key->setName(style.legend);
            styleDots(key, style.lattice, kLatticeKeyColour);
            add(key);
            for (QLegendMarker* m : legend()->markers(key))
                m->setShape(QLegend::MarkerShapeFromSeries);
        }
    }
    std::sort(front.begin(), front.end(), [&](int a, int b) {
        return result.rows[std::size_t(a)].costPerSecond < result.rows[std::size_t(b)].costPerSecond;
    });
    if (!front.empty()) {
        auto* line = new QLineSeries;
        line->setName(QObject::tr("Pareto front"));
        line->setPen(QPen(Qt::black, 2, Qt::DashLine));
        auto* rings = new QScatterSeries;
        rings->setMarkerSize(16);
        rings->setBrush(Qt::NoBrush);
        rings->setPen(QPen(Qt::black, 1.5));
        for (int i : front) {
            const StudyRow& r = result.rows[std::size_t(i)];
            line->append(r.costPerSecond, error(r));
            rings->append(r.costPerSecond, error(r));
        }
        add(line);
        add(rings);
        hideFromLegend(this, rings);
        if (dock)
            hideFromLegend(this, line);  // the dock's text says the ringed dots are the front
    }
    if (marked) {
        auto* mark = new QScatterSeries;
        mark->setName(QObject::tr("current settings"));
        mark->setMarkerShape(QScatterSeries::MarkerShapeStar);
        mark->setMarkerSize(22);
        mark->setColor(kMarkerColour);
        mark->setBorderColor(kMarkerColour);
        mark->append(marker->costPerSecond, marker->rmsError);
        mark->setPointLabelsFormat(QString::fromStdString(marker->label));
        mark->setPointLabelsColor(kMarkerColour);
        mark->setPointLabelsVisible(!marker->label.empty());
        add(mark);
        if (dock)
            hideFromLegend(this, mark);  // labelled on the chart
    }
}

int StudyChart::rowAt(QPointF position, double radius) const {
    auto* self = const_cast<StudyChart*>(this);  // QChart::mapToPosition only reads, but is not const
    int best = -1;
    double bestDistance = radius;
    for (const Point& p : m_points) {
        const double d = QLineF(self->mapToPosition(p.value, p.series), position).length();
        if (d <= bestDistance)
            best = p.row, bestDistance = d;
    }
    return best;
}

QPointF StudyChart::positionOf(int row) const {
    const auto it = std::find_if(m_points.begin(), m_points.end(), [row](const Point& p) { return p.row == row; });
    return it == m_points.end() ? QPointF() : const_cast<StudyChart*>(this)->mapToPosition(it->value, it->series);
}

QImage renderStudyPlot(const StudyResult& result, int width, int height, const std::optional<PlotMarker>& marker) {
    QGraphicsScene scene;
    auto* chart = new StudyChart(result, marker, StudyChartSize::Picture);  // the scene owns it
    if (!chart->hasPoints()) {
        delete chart;
        return {};
    }
    scene.addItem(chart);
    chart->setGeometry(QRectF(0, 0, width, height));
    scene.setSceneRect(0, 0, width, height);
    QImage image(width, height, QImage::Format_RGB32);
    image.fill(Qt::white);
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    scene.render(&painter, QRectF(0, 0, width, height), QRectF(0, 0, width, height));
    painter.end();
    return image;
}

std::string writeStudyPlot(const StudyResult& result, const std::string& path) {
    const QImage image = renderStudyPlot(result, 1000, 700);
    if (image.isNull())
        return "nothing finite to plot";
    QSaveFile file(QString::fromStdString(path));  // atomic: a failed write keeps the previous plot
    if (!file.open(QIODevice::WriteOnly) || !image.save(&file, "PNG") || !file.commit())
        return "cannot write '" + path + "': " + file.errorString().toStdString();
    return {};
}

}  // namespace softtouch::ui

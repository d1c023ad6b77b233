#include "ui/study_plot.h"

#include <QImage>
#include <QPainter>
#include <QPainterPath>
#include <QSaveFile>

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

using analysis::StudyResult;
using analysis::StudyRow;
using analysis::studyErrorName;

QImage renderStudyPlot(const StudyResult& result, int W, int H, const std::optional<PlotMarker>& marker) {
    const int left = 90, right = 200, top = 50, bottom = 70;
    QImage image(W, H, QImage::Format_RGB32);
    image.fill(Qt::white);
    QPainter p(&image);
    p.setRenderHint(QPainter::Antialiasing);

    // The error the study picks by (total, integration or model); rows without one (the reference lattice's
    // model error is 0) have no place on a log axis.
    auto error = [&](const StudyRow& r) { return r.error(result.error); };
    double xmin = 1e300, xmax = 0, ymin = 1e300, ymax = 0;
    for (const auto& r : result.rows) {
        if (!r.finite || r.costPerSecond <= 0 || error(r) <= 0)
            continue;
        xmin = std::min(xmin, r.costPerSecond);
        xmax = std::max(xmax, r.costPerSecond);
        ymin = std::min(ymin, error(r));
        ymax = std::max(ymax, error(r));
    }
    if (result.restError > 0)
        ymax = std::max(ymax, result.restError);  // doing nothing: the line every setting must stay well below
    if (marker && marker->costPerSecond > 0 && marker->rmsError > 0) {
        xmin = std::min(xmin, marker->costPerSecond);
        xmax = std::max(xmax, marker->costPerSecond);
        ymin = std::min(ymin, marker->rmsError);
        ymax = std::max(ymax, marker->rmsError);
    }
    if (xmax <= 0)
        return {};
    const double lx0 = std::floor(std::log10(xmin)), lx1 = std::ceil(std::log10(xmax));
    const double ly0 = std::floor(std::log10(ymin)), ly1 = std::ceil(std::log10(ymax));
    auto X = [&](double v) { return left + (std::log10(v) - lx0) / std::max(1e-9, lx1 - lx0) * (W - left - right); };
    auto Y = [&](double v) { return H - bottom - (std::log10(v) - ly0) / std::max(1e-9, ly1 - ly0) * (H - top - bottom); };

    p.setPen(QColor(220, 220, 220));
    QFont font = p.font();
    font.setPixelSize(13);
    p.setFont(font);
    for (double e = lx0; e <= lx1; ++e) {
        p.setPen(QColor(225, 225, 225));
        p.drawLine(QPointF(X(std::pow(10, e)), top), QPointF(X(std::pow(10, e)), H - bottom));
        p.setPen(Qt::black);
        p.drawText(QRectF(X(std::pow(10, e)) - 40, H - bottom + 6, 80, 20), Qt::AlignCenter, QString("1e%1").arg(int(e)));
    }
    for (double e = ly0; e <= ly1; ++e) {
        p.setPen(QColor(225, 225, 225));
        p.drawLine(QPointF(left, Y(std::pow(10, e))), QPointF(W - right, Y(std::pow(10, e))));
        p.setPen(Qt::black);
        p.drawText(QRectF(0, Y(std::pow(10, e)) - 10, left - 8, 20), Qt::AlignRight | Qt::AlignVCenter, QString("1e%1").arg(int(e)));
    }
    p.setPen(QPen(Qt::black, 1.5));
    p.drawRect(QRectF(left, top, W - left - right, H - top - bottom));
    p.drawText(QRectF(left, H - 35, W - left - right, 25), Qt::AlignCenter, "cost: wall seconds per simulated second (log)");
    p.save();
    p.translate(22, (H - bottom + top) / 2.0);
    p.rotate(-90);
    p.drawText(QRectF(-250, -12, 500, 24), Qt::AlignCenter,
               QString("%1 error / box diagonal (RMS, log)").arg(QString::fromLatin1(studyErrorName(result.error).data())));
    p.restore();
    font.setPixelSize(16);
    font.setBold(true);
    p.setFont(font);
    p.drawText(QRectF(left, 10, W - left - right, 30), Qt::AlignCenter, "Speed against accuracy (every integrator x dt x lattice)");
    font.setPixelSize(13);
    font.setBold(false);
    p.setFont(font);

    const QColor colours[] = {QColor(31, 119, 180), QColor(255, 127, 14), QColor(44, 160, 44), QColor(214, 39, 40)};
    const IntegratorKind kinds[] = {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                    IntegratorKind::Xpbd};
    std::vector<const StudyRow*> front;
    if (result.restError > 0) {
        p.setPen(QPen(QColor(120, 120, 120), 1.5, Qt::DotLine));
        p.drawLine(QPointF(left, Y(result.restError)), QPointF(W - right, Y(result.restError)));
        p.setPen(QColor(90, 90, 90));
        p.drawText(QRectF(left + 6, Y(result.restError) - 20, 400, 18), Qt::AlignLeft,
                   QString("doing nothing (the rest pose): %1").arg(result.restError, 0, 'g', 3));
    }
    for (const auto& r : result.rows) {
        if (!r.finite || r.costPerSecond <= 0 || error(r) <= 0)
            continue;
        const int k = int(std::find(std::begin(kinds), std::end(kinds), r.integrator) - std::begin(kinds));
        p.setPen(Qt::NoPen);
        p.setBrush(colours[k % 4]);
        p.drawEllipse(QPointF(X(r.costPerSecond), Y(error(r))), 4.5, 4.5);
        if (r.pareto)
            front.push_back(&r);
    }
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->costPerSecond < b->costPerSecond; });
    if (front.size() > 1) {
        QPainterPath line(QPointF(X(front[0]->costPerSecond), Y(error(*front[0]))));
        for (auto* r : front)
            line.lineTo(X(r->costPerSecond), Y(error(*r)));
        p.setBrush(Qt::NoBrush);
        p.setPen(QPen(Qt::black, 2, Qt::DashLine));
        p.drawPath(line);
    }
    for (auto* r : front) {
        p.setPen(QPen(Qt::black, 1.5));
        p.setBrush(Qt::NoBrush);
        p.drawEllipse(QPointF(X(r->costPerSecond), Y(error(*r))), 7.5, 7.5);
    }
    for (int k = 0; k < 4; ++k) {
        p.setPen(Qt::NoPen);
        p.setBrush(colours[k]);
        p.drawEllipse(QPointF(W - right + 25, top + 20 + 24 * k), 5, 5);
        p.setPen(Qt::black);
        p.drawText(QPointF(W - right + 38, top + 25 + 24 * k), QString::fromLatin1(integratorName(kinds[k]).data()));
    }
    p.setPen(QPen(Qt::black, 2, Qt::DashLine));
    p.drawLine(QPointF(W - right + 15, top + 125), QPointF(W - right + 35, top + 125));
    p.setPen(Qt::black);
    p.drawText(QPointF(W - right + 38, top + 130), "Pareto front");
    if (marker && marker->costPerSecond > 0 && marker->rmsError > 0) {
        const QPointF at(X(marker->costPerSecond), Y(marker->rmsError));
        p.setPen(QPen(QColor(200, 0, 160), 3));
        p.setBrush(Qt::NoBrush);
        p.drawLine(at + QPointF(-11, 0), at + QPointF(11, 0));
        p.drawLine(at + QPointF(0, -11), at + QPointF(0, 11));
        p.drawEllipse(at, 9, 9);
        p.drawText(QRectF(at.x() + 12, at.y() - 24, 260, 20), Qt::AlignLeft, QString::fromStdString(marker->label));
        p.drawLine(QPointF(W - right + 17, top + 150), QPointF(W - right + 33, top + 150));
        p.drawLine(QPointF(W - right + 25, top + 142), QPointF(W - right + 25, top + 158));
        p.setPen(Qt::black);
        p.drawText(QPointF(W - right + 38, top + 155), "current settings");
    }
    p.end();
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

#include "ui/frame_ruler.h"

#include <QActionGroup>
#include <QContextMenuEvent>
#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

namespace {

constexpr double kMargin = 12.0;     ///< Room left and right of the span, pixels (frame 0's label, the handles).
constexpr double kNumbersBottom = 20.0;
constexpr double kBandTop = 22.0, kBandBottom = 36.0;  ///< The span and its in/out range.
constexpr double kKeysY = 46.0;      ///< Centre of the key ticks.
constexpr double kKeyGrab = 7.0;     ///< How near a tick or handle the cursor must be, pixels.

}  // namespace

FrameRuler::FrameRuler(QWidget* parent) : QWidget(parent) {
    setObjectName("frameRuler");
    setFocusPolicy(Qt::ClickFocus);
    setMouseTracking(false);
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
}

QSize FrameRuler::sizeHint() const { return {480, 58}; }
QSize FrameRuler::minimumSizeHint() const { return {160, 58}; }

void FrameRuler::setSpan(int lastFrame, double fps, double originSeconds) {
    m_lastFrame = std::max(0, lastFrame);
    m_fps = fps > 0.0 ? fps : 24.0;
    m_origin = originSeconds;
    m_frame = 0;
    m_inOut.reset();
    update();
    emit spanChanged();
    emit playheadMoved(m_frame);
}

void FrameRuler::setGutter(double pixels) {
    m_gutter = std::max(0.0, pixels);
    update();
    emit spanChanged();
}

void FrameRuler::setFrame(int frame) {
    m_frame = std::clamp(frame, 0, m_lastFrame);
    update();
    emit playheadMoved(m_frame);
}

void FrameRuler::setInOut(std::optional<std::pair<int, int>> range) {
    if (range)
        range = std::pair(std::clamp(range->first, 0, m_lastFrame), std::clamp(range->second, 0, m_lastFrame));
    m_inOut = range;
    update();
}

void FrameRuler::setRanges(std::vector<Range> ranges) {
    m_ranges = std::move(ranges);
    update();
}

void FrameRuler::setKeys(std::vector<double> seconds, std::vector<KeyInterpolation> interpolation) {
    m_keys = std::move(seconds);
    m_interpolation = std::move(interpolation);
    m_interpolation.resize(m_keys.size(), KeyInterpolation::Smooth);
    if (m_selectedKey >= int(m_keys.size()))
        m_selectedKey = -1;
    update();
}

double FrameRuler::xOfFrame(double f) const {
    return m_gutter + kMargin + f * (width() - m_gutter - 2.0 * kMargin) / std::max(1, m_lastFrame);
}

int FrameRuler::frameAt(double x) const {
    const double f = (x - m_gutter - kMargin) * std::max(1, m_lastFrame) / std::max(1.0, width() - m_gutter - 2.0 * kMargin);
    return std::clamp(int(std::lround(f)), 0, m_lastFrame);
}

QPointF FrameRuler::keyPoint(int k) const { return {xOfFrame(frameOfSeconds(m_keys[std::size_t(k)])), kKeysY}; }

int FrameRuler::keyAt(const QPointF& pos) const {
    int best = -1;
    double bestDistance = kKeyGrab;
    for (int k = 0; k < int(m_keys.size()); ++k) {
        const QPointF p = keyPoint(k);
        const double d = std::max(std::abs(pos.x() - p.x()), std::abs(pos.y() - p.y()));
        if (d <= bestDistance) {
            bestDistance = d;
            best = k;
        }
    }
    return best;
}

void FrameRuler::setKeysLabel(const QString& label) {
    m_keysLabel = label;
    update();
}

void FrameRuler::paintEvent(QPaintEvent*) {
    QPainter painter(this);
    painter.setRenderHint(QPainter::Antialiasing);
    painter.fillRect(rect(), palette().base());
    if (m_gutter > 0.0) {  // the dope sheet's names below; here, what the row of ticks is
        painter.fillRect(QRectF(0, 0, m_gutter, height()), palette().window());
        painter.setPen(palette().color(QPalette::PlaceholderText));
        const QRectF label(4, kKeysY - 9, m_gutter - 6, 18);
        painter.drawText(label, Qt::AlignLeft | Qt::AlignVCenter,
                         painter.fontMetrics().elidedText(m_keysLabel, Qt::ElideRight, int(label.width())));
    }
    // Frame numbers every `step` frames, at least 48 px apart; a small tick on every frame when there is room.
    const double perFrame = (width() - m_gutter - 2.0 * kMargin) / std::max(1, m_lastFrame);
    int step = 1;
    for (const int s : {1, 2, 5, 10, 12, 24, 25, 50, 100, 120, 240, 250, 500, 1000, 2500, 5000, 10000, 100000, 1000000})
        if ((step = s) * perFrame >= 48.0)
            break;
    painter.setPen(palette().color(QPalette::Mid));
    if (perFrame >= 4.0)
        for (int f = 0; f <= m_lastFrame; ++f)
            painter.drawLine(QPointF(xOfFrame(f), kNumbersBottom - 3), QPointF(xOfFrame(f), kNumbersBottom));
    painter.setPen(palette().color(QPalette::Text));
    for (int f = 0; f <= m_lastFrame; f += step) {
        const double x = xOfFrame(f);
        painter.drawLine(QPointF(x, kNumbersBottom - 7), QPointF(x, kNumbersBottom));
        painter.drawText(QRectF(x - 30, 0, 60, kNumbersBottom - 6), Qt::AlignHCenter | Qt::AlignBottom, QString::number(f));
    }
    // The span, and the in/out range cut from it.
    const QRectF band(xOfFrame(0), kBandTop, xOfFrame(m_lastFrame) - xOfFrame(0), kBandBottom - kBandTop);
    painter.fillRect(band, palette().color(QPalette::AlternateBase).darker(108));
    if (m_inOut) {
        const QRectF range(xOfFrame(m_inOut->first), kBandTop, xOfFrame(m_inOut->second) - xOfFrame(m_inOut->first),
                           kBandBottom - kBandTop);
        painter.fillRect(range, QColor(90, 150, 230, 150));
        painter.setPen(QPen(QColor(40, 90, 180), 2));
        for (const int f : {m_inOut->first, m_inOut->second})
            painter.drawLine(QPointF(xOfFrame(f), kBandTop - 2), QPointF(xOfFrame(f), kBandBottom + 2));
    }
    // Named stretches (clips cut from this take, base animations): outlined, labelled, clipped to the span.
    for (const Range& r : m_ranges) {
        const double a = std::clamp(xOfFrame(frameOfSeconds(r.fromSeconds)), xOfFrame(0), xOfFrame(m_lastFrame));
        const double b = std::clamp(xOfFrame(frameOfSeconds(r.toSeconds)), xOfFrame(0), xOfFrame(m_lastFrame));
        if (b - a < 2.0)
            continue;
        const QRectF box(a, kBandTop + 1, b - a, kBandBottom - kBandTop - 2);
        painter.setPen(QPen(QColor(40, 130, 70), 1.5));
        painter.setBrush(QColor(60, 170, 90, 60));
        painter.drawRoundedRect(box, 3, 3);
        painter.setPen(palette().color(QPalette::Text));
        painter.drawText(box.adjusted(4, 0, -2, 0), Qt::AlignLeft | Qt::AlignVCenter,
                         painter.fontMetrics().elidedText(r.label, Qt::ElideRight, int(box.width()) - 6));
    }
    painter.setBrush(Qt::NoBrush);
    // Keys: their shape says how each moves on (smooth a diamond, linear a circle, constant a square whose hold
    // bar runs to the next key); the selected one filled orange; a dragged one drawn where it would land.
    for (int k = 0; k < int(m_keys.size()); ++k) {
        QPointF p = keyPoint(k);
        if (m_drag == Drag::Key && k == m_selectedKey)
            p.setX(xOfFrame(m_dragFrame));
        const KeyInterpolation how = m_interpolation[std::size_t(k)];
        if (how == KeyInterpolation::Constant && k + 1 < int(m_keys.size())) {
            painter.setPen(Qt::NoPen);
            painter.setBrush(QColor(120, 120, 120));
            painter.drawRect(QRectF(p.x(), p.y() - 1.5, keyPoint(k + 1).x() - p.x(), 3));
        }
        drawKeyGlyph(painter, p, how, k == m_selectedKey);
    }
    // The playhead, with its frame.
    const double x = xOfFrame(m_frame);
    painter.setPen(QPen(QColor(220, 40, 40), 2));
    painter.drawLine(QPointF(x, kNumbersBottom - 2), QPointF(x, height()));
    const QString label = QString::number(m_frame);
    const QRectF box(x - 16, 0, 32, kNumbersBottom - 4);
    painter.fillRect(box, QColor(220, 40, 40));
    painter.setPen(Qt::white);
    painter.drawText(box, Qt::AlignCenter, label);
}

void FrameRuler::mousePressEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton)
        return;
    const QPointF pos = event->position();
    if (const int k = keyAt(pos); k >= 0) {
        m_selectedKey = k;
        m_drag = Drag::Key;
        m_copy = event->modifiers() & Qt::ControlModifier;
        m_dragFrame = int(std::lround(frameOfSeconds(m_keys[std::size_t(k)])));
        emit keySelected(k);
    } else if (m_inOut && pos.y() >= kBandTop - 4 && pos.y() <= kBandBottom + 4 &&
               std::abs(pos.x() - xOfFrame(m_inOut->first)) <= kKeyGrab) {
        m_drag = Drag::In;
    } else if (m_inOut && pos.y() >= kBandTop - 4 && pos.y() <= kBandBottom + 4 &&
               std::abs(pos.x() - xOfFrame(m_inOut->second)) <= kKeyGrab) {
        m_drag = Drag::Out;
    } else {
        m_drag = Drag::Scrub;
        m_frame = frameAt(pos.x());
        emit frameChanged(m_frame);
    }
    update();
}

void FrameRuler::mouseMoveEvent(QMouseEvent* event) {
    const int f = frameAt(event->position().x());
    switch (m_drag) {
    case Drag::Scrub:
        if (f != m_frame) {
            m_frame = f;
            emit frameChanged(f);
        }
        break;
    case Drag::Key: m_dragFrame = f; break;
    case Drag::In:
        if (m_inOut && f < m_inOut->second && f != m_inOut->first) {
            m_inOut->first = f;
            emit inOutChanged(m_inOut->first, m_inOut->second);
        }
        break;
    case Drag::Out:
        if (m_inOut && f > m_inOut->first && f != m_inOut->second) {
            m_inOut->second = f;
            emit inOutChanged(m_inOut->first, m_inOut->second);
        }
        break;
    case Drag::None: return;
    }
    update();
}

void FrameRuler::mouseReleaseEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton)
        return;
    if (m_drag == Drag::Key && m_selectedKey >= 0) {
        const int from = int(std::lround(frameOfSeconds(m_keys[std::size_t(m_selectedKey)])));
        if (m_dragFrame != from || m_copy)
            emit keyMoved(m_selectedKey, m_origin + m_dragFrame / m_fps, m_copy);
    }
    m_drag = Drag::None;
    update();
}

void FrameRuler::keyPressEvent(QKeyEvent* event) {
    if ((event->key() == Qt::Key_Delete || event->key() == Qt::Key_Backspace) && m_selectedKey >= 0) {
        const int k = m_selectedKey;
        m_selectedKey = -1;
        emit keyDeleted(k);
        return;
    }
    QWidget::keyPressEvent(event);
}

void drawKeyGlyph(QPainter& painter, QPointF p, KeyInterpolation how, bool selected, bool editable) {
    QPainterPath shape;
    if (how == KeyInterpolation::Linear) {
        shape.addEllipse(p, 5.5, 5.5);
    } else if (how == KeyInterpolation::Constant) {
        shape.addRect(QRectF(p.x() - 5, p.y() - 5, 10, 10));
    } else {
        shape.moveTo(p + QPointF(0, -6));
        shape.lineTo(p + QPointF(6, 0));
        shape.lineTo(p + QPointF(0, 6));
        shape.lineTo(p + QPointF(-6, 0));
        shape.closeSubpath();
    }
    painter.setPen(QPen(editable ? Qt::black : QColor(120, 120, 120), 1));
    painter.setBrush(selected ? QColor(255, 160, 40) : editable ? QColor(235, 235, 235) : QColor(175, 175, 175));
    painter.drawPath(shape);
}

QString keyInterpolationLabel(KeyInterpolation interpolation) {
    switch (interpolation) {
    case KeyInterpolation::Linear: return FrameRuler::tr("Linear");
    case KeyInterpolation::Constant: return FrameRuler::tr("Constant (hold)");
    case KeyInterpolation::Smooth: break;
    }
    return FrameRuler::tr("Smooth");
}

void FrameRuler::contextMenuEvent(QContextMenuEvent* event) {
    const int k = keyAt(event->pos());
    if (k < 0) {
        QWidget::contextMenuEvent(event);
        return;
    }
    m_selectedKey = k;
    emit keySelected(k);
    update();
    QMenu menu(this);
    menu.setObjectName("keyMenu");
    auto* group = new QActionGroup(&menu);
    for (KeyInterpolation how : {KeyInterpolation::Smooth, KeyInterpolation::Linear, KeyInterpolation::Constant}) {
        QAction* action = menu.addAction(keyInterpolationLabel(how));
        action->setCheckable(true);
        action->setChecked(m_interpolation[std::size_t(k)] == how);
        action->setActionGroup(group);
        connect(action, &QAction::triggered, this, [this, k, how] { emit keyInterpolationChosen(k, how); });
    }
    menu.addSeparator();
    connect(menu.addAction(tr("Delete key")), &QAction::triggered, this, [this, k] {
        m_selectedKey = -1;
        emit keyDeleted(k);
    });
    menu.exec(event->globalPos());
}

}  // namespace softtouch::ui

#include "ui/dope_sheet.h"

#include "ui/frame_ruler.h"

#include <QActionGroup>
#include <QContextMenuEvent>
#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

namespace {

constexpr double kSheetRowHeight = 20.0;
constexpr double kSheetTop = 2.0;
constexpr double kSheetKeyGrab = 7.0;  ///< How near a key the cursor must be, pixels.

}  // namespace

DopeSheet::DopeSheet(const FrameRuler* ruler, QWidget* parent) : QWidget(parent), m_ruler(ruler) {
    setObjectName("dopeSheet");
    setFocusPolicy(Qt::ClickFocus);
    // Every row when there is room; in a short dock it gives way first (down to one row), not the ruler above it.
    setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Preferred);
    connect(ruler, &FrameRuler::spanChanged, this, qOverload<>(&QWidget::update));
    connect(ruler, &FrameRuler::playheadMoved, this, qOverload<>(&QWidget::update));
}

QSize DopeSheet::sizeHint() const { return {480, int(2 * kSheetTop + kSheetRowHeight * double(std::max<std::size_t>(1, m_rows.size())))}; }
QSize DopeSheet::minimumSizeHint() const { return {160, int(2 * kSheetTop + kSheetRowHeight)}; }

void DopeSheet::setRows(std::vector<Row> rows) {
    const bool resized = rows.size() != m_rows.size();
    m_rows = std::move(rows);
    for (Row& r : m_rows)
        r.interpolation.resize(r.keys.size(), KeyInterpolation::Smooth);
    // The selection holds the keys still there (by time: an edit renumbers them).
    const int row = currentRow();
    std::erase_if(m_selected, [&](double s) {
        return row < 0 || std::none_of(m_rows[std::size_t(row)].keys.begin(), m_rows[std::size_t(row)].keys.end(),
                                       [s](double k) { return std::abs(k - s) < 1e-9; });
    });
    if (resized)
        updateGeometry();
    clampScroll();
    update();
}

QList<int> DopeSheet::selectedKeys() const {
    QList<int> out;
    if (const int row = currentRow(); row >= 0)
        for (int k = 0; k < int(m_rows[std::size_t(row)].keys.size()); ++k)
            if (isSelected(m_rows[std::size_t(row)].keys[std::size_t(k)]))
                out.push_back(k);
    return out;
}

double DopeSheet::xOfSeconds(double seconds) const { return m_ruler->xOfFrame(m_ruler->frameOfSeconds(seconds)); }

QRectF DopeSheet::rowRect(int row) const {
    return {0.0, kSheetTop + kSheetRowHeight * (row - m_firstRow), double(width()), kSheetRowHeight};
}

int DopeSheet::visibleRows() const { return std::max(1, int((height() - 2 * kSheetTop) / kSheetRowHeight)); }

void DopeSheet::clampScroll() { m_firstRow = std::clamp(m_firstRow, 0, std::max(0, int(m_rows.size()) - visibleRows())); }

void DopeSheet::wheelEvent(QWheelEvent* event) {
    const int before = m_firstRow;
    m_firstRow += event->angleDelta().y() < 0 ? 1 : event->angleDelta().y() > 0 ? -1 : 0;
    clampScroll();
    if (m_firstRow != before)
        update();
    event->setAccepted(m_firstRow != before);  // at either end the panel around it scrolls instead
}

void DopeSheet::resizeEvent(QResizeEvent* event) {
    clampScroll();
    QWidget::resizeEvent(event);
}

QPointF DopeSheet::keyPoint(int row, int key) const {
    return {xOfSeconds(m_rows[std::size_t(row)].keys[std::size_t(key)]), rowRect(row).center().y()};
}

QRectF DopeSheet::clipBar(int row) const {
    const Row& r = m_rows[std::size_t(row)];
    const QRectF band = rowRect(row);
    const double a = xOfSeconds(r.fromSeconds), b = std::max(xOfSeconds(r.toSeconds), a + 4.0);
    return {a, band.top() + 3, b - a, band.height() - 6};
}

int DopeSheet::rowAt(double y) const {
    const int row = m_firstRow + int(std::floor((y - kSheetTop) / kSheetRowHeight));
    return row >= 0 && row < int(m_rows.size()) ? row : -1;
}

int DopeSheet::keyAt(int row, const QPointF& pos) const {
    int best = -1;
    double bestDistance = kSheetKeyGrab;
    for (int k = 0; row >= 0 && k < int(m_rows[std::size_t(row)].keys.size()); ++k) {
        const double d = std::abs(pos.x() - keyPoint(row, k).x());
        if (d <= bestDistance) {
            bestDistance = d;
            best = k;
        }
    }
    return best;
}

int DopeSheet::currentRow() const {
    for (int r = 0; r < int(m_rows.size()); ++r)
        if (m_rows[std::size_t(r)].current)
            return r;
    return -1;
}

bool DopeSheet::isSelected(double seconds) const {
    return std::any_of(m_selected.begin(), m_selected.end(), [seconds](double s) { return std::abs(s - seconds) < 1e-9; });
}

void DopeSheet::select(const QList<int>& keys) {
    m_selected.clear();
    if (const int row = currentRow(); row >= 0)
        for (int k : keys)
            m_selected.push_back(m_rows[std::size_t(row)].keys[std::size_t(k)]);
    update();
}

void DopeSheet::paintEvent(QPaintEvent*) {
    QPainter painter(this);
    painter.setRenderHint(QPainter::Antialiasing);
    painter.fillRect(rect(), palette().base());
    const double left = m_ruler->xOfFrame(0), right = m_ruler->xOfFrame(m_ruler->lastFrame());
    for (int r = m_firstRow; r < int(m_rows.size()) && r < m_firstRow + visibleRows() + 1; ++r) {
        const Row& row = m_rows[std::size_t(r)];
        const QRectF band = rowRect(r);
        painter.fillRect(band, row.current ? QColor(255, 190, 90, 45) : r % 2 ? palette().alternateBase() : palette().base());
        if (row.clip >= 0) {
            // The stretch of key time the clip plays, clipped to the ruler's span; ↻ marks a loop.
            const QRectF bar = clipBar(r).intersected(QRectF(left, band.top(), right - left, band.height()));
            painter.setPen(QPen(QColor(40, 90, 180), 1.2));
            painter.setBrush(QColor(90, 150, 230, 110));
            if (bar.width() > 0)
                painter.drawRoundedRect(bar, 3, 3);
        }
        // The row's name in the ruler's gutter, elided to fit; a clip's loop on its bar.
        const QRectF name(4, band.top(), m_ruler->gutter() - 6, band.height());
        painter.fillRect(QRectF(0, band.top(), m_ruler->gutter(), band.height()), row.current ? QColor(255, 190, 90, 90) : palette().window());
        painter.setPen(palette().color(row.current ? QPalette::Text : QPalette::PlaceholderText));
        painter.drawText(name, Qt::AlignLeft | Qt::AlignVCenter, painter.fontMetrics().elidedText(row.label, Qt::ElideRight, int(name.width())));
        if (row.clip >= 0 && row.loop) {
            painter.setPen(palette().color(QPalette::Text));
            painter.drawText(clipBar(r).adjusted(4, 0, -4, 0), Qt::AlignLeft | Qt::AlignVCenter, tr("↻ loop"));
        }
        // Keys: the current object's are edited here, a dragged selection drawn where it would land.
        for (int k = 0; k < int(row.keys.size()); ++k) {
            const bool selected = row.current && isSelected(row.keys[std::size_t(k)]);
            QPointF p = keyPoint(r, k);
            if (selected && m_drag == Drag::Keys)
                p.setX(m_ruler->xOfFrame(m_ruler->frameOfSeconds(row.keys[std::size_t(k)]) + m_dragFrames));
            drawKeyGlyph(painter, p, row.interpolation[std::size_t(k)], selected, row.current);
        }
    }
    if (const int hidden = int(m_rows.size()) - m_firstRow - visibleRows(); hidden > 0 || m_firstRow > 0) {
        // Rows out of sight: how many, and that the wheel brings them.
        const QString note = tr("%1 more (wheel)").arg(std::max(0, hidden) + m_firstRow);
        const QRectF box(width() - 110, height() - 15, 106, 14);
        painter.fillRect(box, palette().window());
        painter.setPen(palette().color(QPalette::PlaceholderText));
        painter.drawText(box, Qt::AlignRight | Qt::AlignVCenter, note);
    }
    if (m_box) {
        painter.setPen(QPen(QColor(40, 90, 180), 1, Qt::DashLine));
        painter.setBrush(QColor(90, 150, 230, 40));
        painter.drawRect(m_box->normalized());
    }
    const double x = m_ruler->xOfFrame(m_ruler->frame());
    painter.setPen(QPen(QColor(220, 40, 40), 2));
    painter.drawLine(QPointF(x, 0), QPointF(x, height()));
}

void DopeSheet::mousePressEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton)
        return;
    const QPointF pos = event->position();
    const int row = rowAt(pos.y());
    if (row < 0)
        return;
    const Row& r = m_rows[std::size_t(row)];
    if (r.object >= 0 && !r.current) {
        emit objectChosen(r.object);
        return;
    }
    if (r.clip >= 0) {
        if (clipBar(row).contains(pos))
            emit clipChosen(r.clip);
        return;
    }
    const bool extend = event->modifiers() & Qt::ShiftModifier;
    m_pressAt = pos;
    if (const int k = keyAt(row, pos); k >= 0) {
        const double at = r.keys[std::size_t(k)];
        if (extend && isSelected(at)) {
            std::erase_if(m_selected, [at](double s) { return std::abs(s - at) < 1e-9; });
            update();
            return;
        }
        if (!extend && !isSelected(at))
            m_selected.clear();
        if (!isSelected(at))
            m_selected.push_back(at);
        m_drag = Drag::Keys;
        m_copy = event->modifiers() & Qt::ControlModifier;
        m_dragFrames = 0;
        emit keySelected(k);
    } else {
        if (!extend)
            m_selected.clear();
        m_drag = Drag::Box;
        m_box = QRectF(pos, pos);
    }
    update();
}

void DopeSheet::mouseMoveEvent(QMouseEvent* event) {
    const QPointF pos = event->position();
    if (m_drag == Drag::Keys) {
        m_dragFrames = m_ruler->frameAt(pos.x()) - m_ruler->frameAt(m_pressAt.x());
        update();
    } else if (m_drag == Drag::Box) {
        m_box->setBottomRight(pos);
        update();
    }
}

void DopeSheet::mouseReleaseEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton)
        return;
    const int row = currentRow();
    if (m_drag == Drag::Keys && m_dragFrames != 0) {
        const QList<int> keys = selectedKeys();
        const double seconds = m_dragFrames / m_ruler->fps();
        if (!m_copy)
            for (double& s : m_selected)  // the moved keys stay selected where they land
                s += seconds;
        emit keysMoved(keys, seconds, m_copy);
    } else if (m_drag == Drag::Box && row >= 0) {
        const QRectF box = m_box->normalized();
        for (int k = 0; k < int(m_rows[std::size_t(row)].keys.size()); ++k)
            if (box.contains(keyPoint(row, k)) && !isSelected(m_rows[std::size_t(row)].keys[std::size_t(k)]))
                m_selected.push_back(m_rows[std::size_t(row)].keys[std::size_t(k)]);
    }
    m_drag = Drag::None;
    m_box.reset();
    m_dragFrames = 0;
    update();
}

void DopeSheet::keyPressEvent(QKeyEvent* event) {
    if ((event->key() == Qt::Key_Delete || event->key() == Qt::Key_Backspace) && !selectedKeys().isEmpty()) {
        const QList<int> keys = selectedKeys();
        m_selected.clear();
        emit keysDeleted(keys);
        return;
    }
    if (event->key() == Qt::Key_A && event->modifiers() == Qt::ControlModifier && currentRow() >= 0) {
        m_selected = m_rows[std::size_t(currentRow())].keys;
        update();
        return;
    }
    QWidget::keyPressEvent(event);
}

void DopeSheet::contextMenuEvent(QContextMenuEvent* event) {
    const int row = rowAt(event->pos().y());
    if (row < 0)
        return;
    const Row& r = m_rows[std::size_t(row)];
    QMenu menu(this);
    if (r.clip >= 0 && clipBar(row).contains(event->pos())) {
        menu.setObjectName("clipRowMenu");
        const int clip = r.clip;
        QAction* loop = menu.addAction(tr("Loop"));
        loop->setCheckable(true);
        loop->setChecked(r.loop);
        connect(loop, &QAction::triggered, this, [this, clip](bool on) { emit clipLoopChosen(clip, on); });
        connect(menu.addAction(tr("Show clip")), &QAction::triggered, this, [this, clip] { emit clipChosen(clip); });
        menu.exec(event->globalPos());
        return;
    }
    const int k = r.current ? keyAt(row, event->pos()) : -1;
    if (k < 0)
        return;
    if (!isSelected(r.keys[std::size_t(k)]))
        select({k});
    const QList<int> keys = selectedKeys();
    menu.setObjectName("keysMenu");
    auto* group = new QActionGroup(&menu);
    for (KeyInterpolation how : {KeyInterpolation::Smooth, KeyInterpolation::Linear, KeyInterpolation::Constant}) {
        QAction* action = menu.addAction(keyInterpolationLabel(how));
        action->setCheckable(true);
        action->setChecked(std::all_of(keys.begin(), keys.end(), [&](int i) { return r.interpolation[std::size_t(i)] == how; }));
        action->setActionGroup(group);
        connect(action, &QAction::triggered, this, [this, keys, how] { emit keysInterpolationChosen(keys, how); });
    }
    menu.addSeparator();
    connect(menu.addAction(keys.size() > 1 ? tr("Delete %1 keys").arg(keys.size()) : tr("Delete key")), &QAction::triggered,
            this, [this, keys] {
                m_selected.clear();
                emit keysDeleted(keys);
            });
    menu.exec(event->globalPos());
}

}  // namespace softtouch::ui

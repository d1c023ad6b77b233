#include "ui/take_dialog.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QStandardItemModel>

#include <algorithm>
#include <set>
#include <string>

namespace softtouch::ui {

namespace {

/// The shortest part of a take the dialog lets through: a few samples at the default rate.
constexpr double kShortestRange = 0.05;

}  // namespace

TakeDialog::TakeDialog(io::TakeList takes, const QString& fileName, QWidget* parent)
    : QDialog(parent), m_takes(std::move(takes)) {
    setWindowTitle(tr("Import %1").arg(fileName));
    auto* form = new QFormLayout(this);
    m_take = new QComboBox;
    m_take->setObjectName("animationTake");
    // A take is chosen by its name (a project stores the name): an unnamed take after the first, or a name
    // already used by an earlier take, cannot be reached, so it is listed but cannot be picked.
    auto* items = qobject_cast<QStandardItemModel*>(m_take->model());
    std::set<std::string> seen;
    for (std::size_t t = 0; t < m_takes.size(); ++t) {
        const auto& [name, seconds] = m_takes[t];
        m_take->addItem(tr("%1 (%2 s)").arg(name.empty() ? tr("unnamed") : QString::fromStdString(name)).arg(seconds, 0, 'g', 4));
        const bool reachable = seen.insert(name).second && (!name.empty() || t == 0);
        if (!reachable && items) {
            QStandardItem* item = items->item(int(t));
            item->setEnabled(false);
            item->setToolTip(name.empty() ? tr("This take has no name, so neither this dialog nor a project can choose it "
                                               "(an unnamed take is the file's first only)")
                                          : tr("An earlier take has the same name, which a project would choose instead"));
        }
    }
    form->addRow(tr("Take"), m_take);
    m_start = new QDoubleSpinBox;
    m_start->setObjectName("animationStart");
    m_end = new QDoubleSpinBox;
    m_end->setObjectName("animationEnd");
    for (QDoubleSpinBox* box : {m_start, m_end}) {
        box->setDecimals(3);
        box->setSingleStep(0.1);
        box->setSuffix(tr(" s"));
    }
    form->addRow(tr("From"), m_start);
    form->addRow(tr("To"), m_end);
    m_loop = new QCheckBox(tr("Loops (the end runs on into the start)"));
    m_loop->setObjectName("animationLoop");
    m_loop->setChecked(true);
    form->addRow(m_loop);
    // The range stays a range: each end keeps the other inside the take and at least kShortestRange away.
    connect(m_start, &QDoubleSpinBox::valueChanged, this, [this](double start) { m_end->setMinimum(start + kShortestRange); });
    connect(m_end, &QDoubleSpinBox::valueChanged, this, [this](double end) { m_start->setMaximum(std::max(0.0, end - kShortestRange)); });
    connect(m_take, &QComboBox::currentIndexChanged, this, &TakeDialog::takeChosen);
    takeChosen(0);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
    connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    form->addRow(buttons);
}

void TakeDialog::takeChosen(int index) {
    if (index < 0 || std::size_t(index) >= m_takes.size())
        return;
    const double length = m_takes[std::size_t(index)].second;
    // The whole take, first the limits wide open so neither value is clamped by the other take's.
    m_start->setRange(0.0, length);
    m_end->setRange(0.0, length);
    m_start->setValue(0.0);
    m_end->setValue(length);
    m_start->setMaximum(std::max(0.0, length - kShortestRange));
    m_end->setMinimum(std::min(length, kShortestRange));
}

io::AnimationRequest TakeDialog::request() const {
    io::AnimationRequest request;
    const int index = m_take->currentIndex();
    if (index >= 0 && std::size_t(index) < m_takes.size()) {
        request.take = m_takes[std::size_t(index)].first;
        request.start = m_start->value();
        // The whole take when the end is at its end: the take's own length, not the spin box's rounding.
        const double length = m_takes[std::size_t(index)].second;
        request.end = m_end->value() >= length - 5e-4 ? -1.0 : m_end->value();
    }
    request.loop = m_loop->isChecked();
    return request;
}

}  // namespace softtouch::ui

#include "ui/timeline_panel.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QSlider>
#include <QVBoxLayout>

#include <cmath>

namespace softtouch::ui {

TimelinePanel::TimelinePanel(Document* document, SimulationController* simulation, QWidget* parent)
    : QWidget(parent), m_document(document), m_simulation(simulation) {
    auto* layout = new QHBoxLayout(this);
    auto* left = new QVBoxLayout;
    m_record = new QPushButton(tr("● Record"));
    m_record->setObjectName("recordButton");
    m_record->setCheckable(true);
    m_record->setToolTip(tr("Record a take: every grab and drag, step by step, so it replays exactly."));
    left->addWidget(m_record);
    m_list = new QListWidget;
    m_list->setObjectName("takes");
    m_list->setMaximumWidth(220);
    left->addWidget(m_list);
    layout->addLayout(left);
    auto* right = new QVBoxLayout;
    m_slider = new QSlider(Qt::Horizontal);
    m_slider->setObjectName("scrubber");
    m_slider->setEnabled(false);
    right->addWidget(m_slider);
    m_time = new QLabel(tr("Record a take, then scrub it here."));
    right->addWidget(m_time);
    right->addStretch();
    layout->addLayout(right, 1);

    connect(m_record, &QPushButton::clicked, this, &TimelinePanel::toggleRecording);
    connect(simulation, &SimulationController::recordingChanged, this, [this](bool on) {
        m_record->setChecked(on);
        m_record->setText(on ? tr("■ Stop") : tr("● Record"));
    });
    connect(simulation, &SimulationController::sessionRecorded, this, [this](const Session& session) {
        m_sessions.push_back(session);
        refreshList();
        m_list->setCurrentRow(int(m_sessions.size()) - 1);
    });
    connect(m_list, &QListWidget::currentRowChanged, this, [this](int row) {
        m_slider->setEnabled(row >= 0);
        if (row < 0)
            return;
        const Session& s = m_sessions[std::size_t(row)];
        const QSignalBlocker block(m_slider);
        m_slider->setRange(0, int(std::floor((s.endSeconds() - s.startSeconds()) * fps() + 1e-9)));
        m_slider->setValue(0);
    });
    connect(m_slider, &QSlider::valueChanged, this, [this](int frame) { scrubTo(m_list->currentRow(), frame); });
    connect(document, &Document::sceneReplaced, this, [this] {
        m_sessions.clear();  // takes replay only on the scene they were recorded on
        refreshList();
    });
}

double TimelinePanel::fps() const { return m_document->scene().world.fps; }

void TimelinePanel::toggleRecording() {
    if (m_simulation->isRecording()) {
        m_simulation->stopRecording();
    } else {
        m_simulation->startRecording();
        m_simulation->play();
    }
}

void TimelinePanel::scrubTo(int index, int frame) {
    if (index < 0 || std::size_t(index) >= m_sessions.size())
        return;
    const double seconds = frame / fps();
    if (Status s = m_simulation->scrub(m_sessions[std::size_t(index)], seconds); !s)
        m_time->setText(QString::fromStdString(s.message()));
    else
        m_time->setText(tr("Take %1 · frame %2 · %3 s").arg(index + 1).arg(frame).arg(seconds, 0, 'f', 3));
}

void TimelinePanel::refreshList() {
    m_list->clear();
    for (std::size_t i = 0; i < m_sessions.size(); ++i) {
        const Session& s = m_sessions[i];
        m_list->addItem(tr("Take %1 · %2 s").arg(i + 1).arg(s.endSeconds() - s.startSeconds(), 0, 'f', 2));
    }
}

}  // namespace softtouch::ui

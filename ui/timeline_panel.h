#pragma once
/// The timeline dock: record a session (everything that drives the body, so it replays exactly),
/// list the recorded takes, and scrub through one (the scene shows the replayed state).

#include "ui/simulation_controller.h"

#include <QWidget>

class QListWidget;
class QSlider;
class QLabel;
class QPushButton;

namespace softtouch::ui {

/// Recorded sessions of the open document.
class TimelinePanel : public QWidget {
    Q_OBJECT
public:
    TimelinePanel(Document* document, SimulationController* simulation, QWidget* parent = nullptr);

    /// The recorded takes, oldest first.
    const std::vector<Session>& sessions() const { return m_sessions; }
    /// Frames per second of the scrub slider (the scene's clip rate).
    double fps() const;

public slots:
    void toggleRecording();
    /// Shows take `index` at `frame`.
    void scrubTo(int index, int frame);

private:
    void refreshList();

    Document* m_document;
    SimulationController* m_simulation;
    std::vector<Session> m_sessions;
    QPushButton* m_record = nullptr;
    QListWidget* m_list = nullptr;
    QSlider* m_slider = nullptr;
    QLabel* m_time = nullptr;
};

}  // namespace softtouch::ui

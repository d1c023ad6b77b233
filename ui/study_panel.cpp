#include "ui/study_panel.h"

#include "bench/study_plot.h"
#include "ui/edit_commands.h"

#include <QDoubleSpinBox>
#include <QFile>
#include <QFormLayout>
#include <QLabel>
#include <QPushButton>
#include <QTimer>
#include <QVBoxLayout>

#include <cmath>

namespace softtouch::ui {

std::string studyResolutionName(const Lattice& lattice) {
    return std::to_string(lattice.count(0)) + "x" + std::to_string(lattice.count(1)) + "x" + std::to_string(lattice.count(2)) +
           (lattice.shape().kind == LatticeKind::Bezier ? " bezier" : " bspline");
}

StudyPanel::StudyPanel(Document* document, const QString& csvPath, QWidget* parent) : QWidget(parent), m_document(document) {
    auto* layout = new QVBoxLayout(this);
    m_plot = new QLabel;
    m_plot->setMinimumSize(320, 220);
    // The pixmap follows the label's size, never the other way round (that would grow the dock).
    m_plot->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
    m_plot->setAlignment(Qt::AlignCenter);
    layout->addWidget(m_plot, 1);
    m_text = new QLabel;
    m_text->setWordWrap(true);
    m_text->setObjectName("studyText");
    layout->addWidget(m_text);
    auto* form = new QFormLayout;
    m_target = new QDoubleSpinBox;
    m_target->setRange(0.01, 50.0);
    m_target->setDecimals(2);
    m_target->setSuffix(tr(" % of the diagonal"));
    m_target->setValue(0.5);
    form->addRow(tr("Error target"), m_target);
    m_apply = new QPushButton(tr("Use the cheapest setting within the target"));
    form->addRow(m_apply);
    layout->addLayout(form);

    QFile file(csvPath);
    if (!file.open(QIODevice::ReadOnly)) {
        m_problem = tr("No study at %1: run softtouch-cli study SCENE --out docs.").arg(csvPath);
    } else if (auto parsed = bench::parseStudyCsv(file.readAll().toStdString())) {
        m_study = std::move(parsed.value());
    } else {
        m_problem = tr("%1: %2").arg(csvPath, QString::fromStdString(parsed.message()));
    }
    connect(document, &Document::worldChanged, this, &StudyPanel::refresh);
    connect(document, &Document::latticeChanged, this, &StudyPanel::refresh);
    connect(document, &Document::sceneReplaced, this, &StudyPanel::refresh);
    connect(m_target, &QDoubleSpinBox::valueChanged, this, &StudyPanel::refresh);
    connect(m_apply, &QPushButton::clicked, this, &StudyPanel::applySuggestion);
    refresh();
}

const bench::StudyRow* StudyPanel::currentRow() const {
    const Scene& scene = m_document->scene();
    if (scene.objects.empty())
        return nullptr;
    return bench::nearestRow(m_study, scene.world.simulation.integrator, scene.world.simulation.dt,
                             studyResolutionName(scene.objects.front().lattice));
}

const bench::StudyRow* StudyPanel::suggestion() const {
    // Only settings of the current lattice: changing the resolution changes the model, not just its accuracy.
    const Scene& scene = m_document->scene();
    if (scene.objects.empty())
        return nullptr;
    const std::string resolution = studyResolutionName(scene.objects.front().lattice);
    const bench::StudyRow* best = nullptr;
    for (const bench::StudyRow& r : m_study.rows) {
        if (r.resolution == resolution && r.finite && r.timeError <= m_target->value() / 100.0 &&
            (!best || r.costPerSecond < best->costPerSecond))
            best = &r;
    }
    return best;
}

void StudyPanel::refresh() {
    if (!hasStudy()) {
        m_plot->setText(m_problem);
        m_apply->setEnabled(false);
        return;
    }
    const bench::StudyRow* current = currentRow();
    std::optional<bench::PlotMarker> marker;
    const Scene& scene = m_document->scene();
    const QString settings = scene.objects.empty()
                                 ? QString()
                                 : tr("%1, 1/%2 s, %3")
                                       .arg(QString::fromLatin1(integratorName(scene.world.simulation.integrator).data()))
                                       .arg(std::lround(1.0 / scene.world.simulation.dt))
                                       .arg(QString::fromStdString(studyResolutionName(scene.objects.front().lattice)));
    if (current)
        marker = bench::PlotMarker{current->costPerSecond, current->rmsError, "current"};
    const QImage image = bench::renderStudyPlot(m_study, std::max(m_plot->width(), 320) * 2, std::max(m_plot->height(), 220) * 2, marker);
    m_plot->setPixmap(QPixmap::fromImage(image).scaled(m_plot->size(), Qt::KeepAspectRatio, Qt::SmoothTransformation));
    QString text = current ? tr("Current (%1): %2 s of physics per simulated second, RMS error %3 % of the diagonal, "
                                "of which %4 % from the time step.")
                                 .arg(settings)
                                 .arg(current->costPerSecond, 0, 'g', 3)
                                 .arg(100.0 * current->rmsError, 0, 'g', 3)
                                 .arg(100.0 * current->timeError, 0, 'g', 3)
                           : tr("The study did not measure the current settings (%1).").arg(settings);
    const bench::StudyRow* suggested = suggestion();
    if (suggested)
        text += tr("\nCheapest on this lattice within %1 % time error: %2 at 1/%3 s (%4 s per simulated second).")
                    .arg(m_target->value())
                    .arg(QString::fromLatin1(integratorName(suggested->integrator).data()))
                    .arg(std::lround(1.0 / suggested->dt))
                    .arg(suggested->costPerSecond, 0, 'g', 3);
    m_text->setText(text + tr("\nMeasured on the angelfish by softtouch-cli study (docs/study.md)."));
    m_apply->setEnabled(suggested != nullptr);
}

void StudyPanel::applySuggestion() {
    const bench::StudyRow* s = suggestion();
    if (!s)
        return;
    WorldSettings before = m_document->scene().world;
    WorldSettings after = before;
    after.simulation.integrator = s->integrator;
    after.simulation.dt = s->dt;
    m_document->undoStack()->push(new WorldEditCommand(m_document, std::move(before), std::move(after),
                                                       tr("Use the cheapest setting within the error target")));
}

void StudyPanel::resizeEvent(QResizeEvent* event) {
    QWidget::resizeEvent(event);
    // Redraw once the layout has given the plot label its new size.
    QTimer::singleShot(0, this, &StudyPanel::refresh);
}

}  // namespace softtouch::ui

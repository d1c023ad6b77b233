#include "ui/study_panel.h"

#include "ui/edit_commands.h"
#include "ui/study_chart_view.h"

#include "core/modes/solid_modes.h"
#include "io/pipeline/reference_cache.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QEvent>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QStackedWidget>
#include <QToolTip>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace softtouch::ui {
namespace {

/// "0.42 %", never broken across lines.
QString percent(double fraction) { return QString::number(100.0 * fraction, 'g', 2) + QChar(0x00A0) + QLatin1Char('%'); }

QString cost(double secondsPerSecond) {
    return QObject::tr("%1 ms per second of clip").arg(QString::number(1000.0 * secondsPerSecond, 'g', 3));
}

/// "verlet, 1/240 s, 4x4x4 bezier".
QString settingName(const analysis::StudySetting& setting) {
    return QObject::tr("%1, 1/%2 s, %3")
        .arg(QString::fromLatin1(integratorName(setting.integrator).data()))
        .arg(std::lround(1.0 / setting.dt))
        .arg(QString::fromStdString(analysis::studyModelName(setting.lattice, setting.element)));
}

QString errorName(analysis::StudyError kind) { return QString::fromLatin1(analysis::studyErrorName(kind).data()); }

}  // namespace

StudyPanel::StudyPanel(Document* document, QWidget* parent) : QWidget(parent), m_document(document) {
    auto* layout = new QVBoxLayout(this);
    // The chart once measured; before that, what will appear there and how.
    m_plotStack = new QStackedWidget;
    m_plotNote = new QLabel;
    m_plotNote->setObjectName("studyPlotNote");
    m_plotNote->setAlignment(Qt::AlignCenter);
    m_plotNote->setWordWrap(true);
    m_plot = new StudyChartView;
    m_plot->setObjectName("studyPlot");
    m_plotStack->addWidget(m_plotNote);
    m_plotStack->addWidget(m_plot);
    m_plotStack->setMinimumSize(320, 300);
    // The chart follows the dock's size, never the other way round (that would grow the dock).
    m_plotStack->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Ignored);
    layout->addWidget(m_plotStack, 1);
    m_pointer = new QLabel;
    m_pointer->setObjectName("studyPointer");
    m_pointer->setWordWrap(true);
    m_pointer->setTextFormat(Qt::RichText);
    layout->addWidget(m_pointer);

    m_text = new QLabel;
    m_text->setObjectName("studyText");
    m_text->setWordWrap(true);
    m_text->setTextFormat(Qt::RichText);
    layout->addWidget(m_text);

    auto* form = new QFormLayout;
    m_target = new QDoubleSpinBox;
    m_target->setObjectName("studyTarget");
    m_target->setRange(0.01, 50.0);
    m_target->setDecimals(2);
    m_target->setSingleStep(0.1);
    m_target->setSuffix(tr(" % of the diagonal"));
    m_target->setValue(0.5);
    m_target->setToolTip(tr("Largest RMS vertex error over the clip, in % of the object's box diagonal."));
    form->addRow(tr("Error target"), m_target);
    m_errorKind = new QComboBox;
    m_errorKind->setObjectName("studyErrorKind");
    m_errorKind->addItem(tr("total"), int(analysis::StudyError::Total));
    m_errorKind->addItem(tr("integration"), int(analysis::StudyError::Integration));
    m_errorKind->addItem(tr("model"), int(analysis::StudyError::Model));
    m_errorKind->setToolTip(tr("total: against the finest lattice converged in time (what you see);\n"
                               "integration: what the integrator and time step cost on this lattice;\n"
                               "model: what the lattice resolution costs, the step aside."));
    form->addRow(tr("Error used"), m_errorKind);
    layout->addLayout(form);

    auto* run = new QHBoxLayout;
    m_measure = new QPushButton(tr("Measure this scene"));
    m_measure->setObjectName("studyMeasure");
    m_cancelButton = new QPushButton(tr("Cancel"));
    m_cancelButton->setObjectName("studyCancel");
    run->addWidget(m_measure, 1);
    run->addWidget(m_cancelButton);
    layout->addLayout(run);
    m_progress = new QProgressBar;
    m_progress->setObjectName("studyProgress");
    m_progress->hide();
    layout->addWidget(m_progress);
    m_apply = new QPushButton(tr("Use the cheapest setting within the target"));
    m_apply->setObjectName("studyApply");
    layout->addWidget(m_apply);
    m_check = new QLabel;
    m_check->setObjectName("studyCheck");
    m_check->setWordWrap(true);
    m_check->setTextFormat(Qt::RichText);
    layout->addWidget(m_check);

    // Every object is measured (analysis::runStudy), on the clip a bake plays: any of their edits, or the
    // clips', makes the study out of date.
    connect(document, &Document::worldChanged, this, &StudyPanel::sceneChanged);
    connect(document, &Document::sceneReplaced, this, &StudyPanel::sceneChanged);
    connect(document, &Document::latticeChanged, this, &StudyPanel::sceneChanged);
    connect(document, &Document::materialChanged, this, &StudyPanel::sceneChanged);
    connect(document, &Document::clipsChanged, this, &StudyPanel::sceneChanged);
    connect(m_target, &QDoubleSpinBox::valueChanged, this, &StudyPanel::refresh);
    connect(m_errorKind, &QComboBox::currentIndexChanged, this, [this] {
        // The pick, the plot's axis and its front follow the chosen kind (cheapestWithin and the plot read it).
        m_study.error = analysis::StudyError(m_errorKind->currentData().toInt());
        analysis::markPareto(m_study);
        refreshPlot();
        refresh();
    });
    connect(m_measure, &QPushButton::clicked, this, &StudyPanel::measure);
    connect(m_cancelButton, &QPushButton::clicked, this, &StudyPanel::cancel);
    connect(m_apply, &QPushButton::clicked, this, &StudyPanel::applySuggestion);
    connect(m_plot, &StudyChartView::hovered, this, &StudyPanel::showPointer);
    connect(m_plot, &StudyChartView::clicked, this, [this](int row) { applyRow(row); });
    refreshPlot();
    refresh();
}

StudyPanel::~StudyPanel() {
    // The worker reads a copy of the scene but posts to this panel: it must end before the panel does.
    // Its posted calls not yet run are dropped with the panel (~QObject removes them).
    m_cancel = true;
    if (m_worker.joinable())
        m_worker.join();
}

const analysis::StudyRow* StudyPanel::currentRow() const {
    const auto it = std::find_if(m_study.rows.begin(), m_study.rows.end(), [](const analysis::StudyRow& r) { return r.current; });
    return it == m_study.rows.end() ? nullptr : &*it;
}

const analysis::StudyRow* StudyPanel::suggestion() const { return analysis::cheapestWithin(m_study, target()); }

double StudyPanel::target() const { return m_target->value() / 100.0; }

void StudyPanel::startWorker(std::function<void()> job) {
    m_cancel = false;
    m_runEdits = m_edits;
    m_notice.clear();
    m_worker = std::thread(std::move(job));
    refresh();
}

void StudyPanel::post(std::function<void()> call) {
    QMetaObject::invokeMethod(this, std::move(call), Qt::QueuedConnection);
}

void StudyPanel::measure() {
    if (isMeasuring() || m_document->scene().objects.empty())
        return;
    m_remeasuring = false;
    m_progress->setRange(0, 0);  // busy until the reference runs are done and the grid starts
    m_progress->setFormat(tr("Measuring… %p%"));
    // The clip Export… would write (the one selected in the timeline) when the study can play it on other lattices.
    std::string clipName = m_clipSource ? m_clipSource() : std::string();
    const auto& library = m_document->project().clips.clips;
    const auto named = std::find_if(library.begin(), library.end(), [&](const Clip& c) { return c.name == clipName; });
    if (named == library.end() || named->source != ClipSource::Drivers)
        clipName.clear();
    startWorker([this, project = m_document->project(), clipName] {
        const Scene& scene = project.scene;
        const ClipLibrary& clips = project.clips;
        analysis::StudyOptions options;
        options.clip = clipName;
        options.quick = true;
        options.error = analysis::StudyError::Total;  // the plot's axis; picks follow the dock's choice
        options.reference = analysis::quickReference();  // its larger uncertainty is shown and enforced
        // The converged solid is kept by content, as `softtouch-cli study` keeps it: a full study's reference of
        // this very scene and clip certifies lower targets than the quick one, which is made only when neither
        // is kept, and then kept for the next measurement.
        const std::filesystem::path folder = io::referenceCacheFolder();
        const analysis::ReferenceOptions ladders[] = {analysis::ReferenceOptions{}, analysis::quickReference()};
        const io::KeptReference kept = io::findKeptReference(folder, project, clipName, ladders);
        options.given = kept.reference;
        options.progress = [this](double fraction) {
            post([this, fraction] {
                m_progress->setRange(0, 1000);
                m_progress->setValue(int(std::lround(1000.0 * fraction)));
            });
            return !m_cancel.load();
        };
        std::ostringstream log;  // the dock shows the result; the CLI's study prints this log
        analysis::StudyResult result = analysis::runStudy(scene, clips, options, log);
        if (!options.given && result.reference && !result.cancelled && !kept.key.empty())  // the quick ladder's key
            (void)io::writeCachedReference(folder, kept.key, *result.reference);  // not kept: measured again next time
        post([this, result = std::move(result)]() mutable { studyDone(std::move(result)); });
    });
}

void StudyPanel::cancel() {
    if (!isMeasuring() || m_remeasuring)
        return;
    m_cancel = true;
    m_cancelButton->setEnabled(false);
    m_progress->setFormat(tr("Cancelling after the current run…"));
}

void StudyPanel::studyDone(analysis::StudyResult result) {
    m_worker.join();  // it has posted this as its last act
    if (result.cancelled) {
        m_notice = hasStudy() ? tr("Measurement cancelled: the previous measurement is still shown.")
                              : tr("Measurement cancelled: nothing was kept. Press <i>Measure this scene</i> to start again.");
    } else if (!result.failure.empty()) {
        m_notice = tr("The measurement gave no result: %1").arg(QString::fromStdString(result.failure).toHtmlEscaped());
    } else if (result.rows.empty()) {
        m_notice = tr("The measurement gave no result: check that the scene plays (press Play) and measure again.");
    } else {
        m_study = std::move(result);
        m_study.error = analysis::StudyError(m_errorKind->currentData().toInt());
        analysis::markPareto(m_study);
        m_studyEdits = m_runEdits;
        m_remeasured.reset();
        markCurrent();  // the scene may have changed while it ran
    }
    refresh();
    emit finished();
}

void StudyPanel::applySuggestion() {
    if (!applyBlocker().isEmpty())
        return;
    applyRow(int(suggestion() - m_study.rows.data()));
}

bool StudyPanel::applyRow(int row) {
    if (row < 0 || row >= int(m_study.rows.size()) || !rowBlocker(row).isEmpty())
        return false;
    const analysis::StudyRow* pick = &m_study.rows[std::size_t(row)];
    const Scene& scene = m_document->scene();
    auto next = analysis::applySetting(scene, pick->setting());
    if (!next) {
        m_check->setText(tr("Not applied: %1").arg(QString::fromStdString(next.message()).toHtmlEscaped()));
        return false;
    }
    // Copies: each command's redo() changes the scene these would otherwise point into.
    const WorldSettings worldBefore = scene.world;
    const bool newStep = worldBefore.simulation.integrator != pick->integrator || worldBefore.simulation.dt != pick->dt;
    std::vector<std::pair<Lattice, LatticeMaterial>> before;
    for (const SceneObject& object : scene.objects)
        before.emplace_back(object.lattice, object.material);

    m_applying = true;
    QUndoStack* undo = m_document->undoStack();
    undo->beginMacro(pick == suggestion() ? tr("Use the cheapest setting within the error target")
                                          : tr("Use %1 (picked on the study's chart)").arg(settingName(pick->setting())));
    if (newStep)
        undo->push(new WorldEditCommand(m_document, worldBefore, next->world, tr("Integrator and time step")));
    for (std::size_t i = 0; i < before.size(); ++i) {
        // Every object moves to the pick's lattice and element (the study measured them all on it).
        const LatticeShape shape = before[i].first.shape();
        if (shape.kind != pick->lattice.kind || shape.nodes != pick->lattice.nodes ||
            before[i].second.element != pick->element)
            undo->push(new LatticeEditCommand(m_document, int(i), before[i].first, before[i].second, next->objects[i].lattice,
                                              next->objects[i].material,
                                              before[i].second.element != pick->element ? tr("Lattice and element")
                                                                                         : tr("Lattice resolution")));
    }
    undo->endMacro();
    m_applying = false;

    // The must-show: the scene as it now stands, run again against the study's reference.
    m_remeasuring = true;
    m_remeasured.reset();
    m_progress->setRange(0, 0);
    m_progress->setFormat(tr("Re-measuring…"));
    startWorker([this, scene = m_document->scene(), clips = m_document->project().clips, study = m_study] {
        Result<analysis::Remeasured> result = analysis::remeasure(scene, clips, study);
        post([this, result = std::move(result)] { remeasureDone(result); });
    });
    return true;
}

void StudyPanel::remeasureDone(Result<analysis::Remeasured> result) {
    m_worker.join();  // it has posted this as its last act
    m_remeasuring = false;
    if (result) {
        m_remeasured = result.value();
        m_remeasuredEdits = m_runEdits;
    } else {
        m_notice = tr("Re-measuring failed: %1").arg(QString::fromStdString(result.message()).toHtmlEscaped());
    }
    refresh();
    emit finished();
}

void StudyPanel::sceneChanged() {
    markCurrent();
    if (!m_applying)
        ++m_edits;
    refresh();
}

void StudyPanel::markCurrent() {
    // The mark follows the scene's setting (after a pick, after undo); isOutOfDate() says whether the
    // numbers still describe the scene.
    const Scene& scene = m_document->scene();
    for (analysis::StudyRow& r : m_study.rows)
        r.current = !scene.objects.empty() && analysis::sameSetting(r.setting(), analysis::sceneSetting(scene));
    refreshPlot();  // the mark moved (or a new study came)
}

QString StudyPanel::rowBlocker(int row) const {
    if (isMeasuring())
        return m_remeasuring ? tr("Re-measuring the scene with the new setting…") : tr("Wait for the measurement to finish.");
    if (!hasStudy())
        return tr("Measure this scene first.");
    if (isOutOfDate())
        return tr("The scene changed since it was measured: press <i>Measure again</i> first.");
    if (row >= 0 && !m_study.rows[std::size_t(row)].finite)
        return tr("This setting blew up on this scene.");
    if (row >= 0 && m_study.rows[std::size_t(row)].current)
        return tr("This is the current setting.");
    return {};
}

QString StudyPanel::applyBlocker() const {
    if (const QString blocked = rowBlocker(-1); !blocked.isEmpty())
        return blocked;
    if (const std::string refusal = analysis::refusalOfTarget(m_study, target()); !refusal.empty())
        return tr("This target cannot be certified: %1.").arg(QString::fromStdString(refusal).toHtmlEscaped());
    const analysis::StudyRow* pick = suggestion();
    if (!pick)
        return tr("No measured setting is within the target: raise the target or choose another error.");
    if (pick->current)
        return tr("The current setting is already the cheapest within the target.");
    return {};
}

void StudyPanel::showPointer(int row) {
    if (row < 0 || row >= int(m_study.rows.size())) {
        m_pointer->setText(hasStudy() ? tr("Ringed dots are the Pareto front (nothing measured is both cheaper and more "
                                           "accurate). Point at a dot to read its setting; click it to use that setting.")
                                      : QString());
        QToolTip::hideText();
        return;
    }
    const analysis::StudyRow& r = m_study.rows[std::size_t(row)];
    const QString blocker = rowBlocker(row);
    // The lattice against the solid it stands for (docs/design/lattice.md), where that solid converges.
    const QString solid = r.solidModeError.empty()
                              ? QString()
                              : tr(" Its lattice's modes are %1 from the solid.")
                                    .arg(QString::fromStdString(describeModeErrors(r.solidModeError)));
    const QString text = tr("<b>%1</b>: error %2 total, %3 integration, %4 model; %5.%6 %7")
                             .arg(settingName(r.setting()), percent(r.rmsError), percent(r.timeError), percent(r.modelError),
                                  cost(r.costPerSecond), solid, blocker.isEmpty() ? tr("Click to use it.") : blocker);
    m_pointer->setText(text);
    QToolTip::showText(m_plot->mapToGlobal(m_plot->viewportPositionOf(row)), text, m_plot);
}

void StudyPanel::refresh() {
    const Scene& scene = m_document->scene();
    const bool busy = isMeasuring();
    m_measure->setEnabled(!busy && !scene.objects.empty());
    m_measure->setText(hasStudy() ? tr("Measure again") : tr("Measure this scene"));
    m_cancelButton->setVisible(busy);
    m_cancelButton->setEnabled(busy && !m_remeasuring && !m_cancel);
    m_progress->setVisible(busy);

    QStringList text;
    if (scene.objects.empty()) {
        text << tr("Open or import a scene to measure it.");
    } else if (!hasStudy()) {
        text << (busy ? tr("<b>Measuring this scene</b>: its clip with every integrator × time step × lattice of a quick grid "
                           "(seconds to a minute).")
                      : tr("<b>Not measured yet.</b> The study plays the scene's clip with every integrator × time "
                           "step × lattice of a quick grid (seconds to a minute) and finds the cheapest setting within "
                           "your error target."));
    }
    if (!m_notice.isEmpty())
        text << m_notice;
    if (hasStudy()) {
        if (isOutOfDate())
            text << tr("<b style='color:#b00000'>Out of date:</b> the scene changed since it was measured. Press "
                       "<i>Measure again</i>.");
        text << tr("Errors are RMS vertex distances over the %1 s clip '%2', in % of the mesh's diagonal, against the "
                   "converged solid (itself within %3); the worst object counts. The mesh moves up to %4; doing nothing "
                   "(the bodies at rest) would score %5.")
                    .arg(m_study.clip.seconds(), 0, 'g', 3)
                    .arg(QString::fromStdString(m_study.clip.name).toHtmlEscaped(), percent(m_study.referenceUncertainty()),
                         percent(m_study.motionAmplitude), percent(m_study.restError));
        if (const analysis::StudyRow* current = currentRow())
            text << tr("<b>Current</b> (%1): %2; error %3 total, %4 integration, %5 model.")
                        .arg(settingName(current->setting()), cost(current->costPerSecond), percent(current->rmsError),
                             percent(current->timeError), percent(current->modelError));
        else if (!scene.objects.empty())
            text << tr("<b>Current</b> (%1): not measured; press <i>Measure again</i>.").arg(settingName(analysis::sceneSetting(scene)));
        const QString within = tr("within %1 (%2 error)").arg(percent(target()), errorName(m_study.error));
        const analysis::StudyRow* pick = suggestion();
        if (pick && pick->current) {
            text << tr("<b>Cheapest %1</b>: the current setting.").arg(within);
        } else if (pick) {
            const analysis::StudyRow* current = currentRow();
            const double faster = current ? current->costPerSecond / pick->costPerSecond : 1.0;
            text << tr("<b>Cheapest %1</b>: %2; error %3, %4%5.")
                        .arg(within, settingName(pick->setting()), percent(pick->error(m_study.error)), cost(pick->costPerSecond),
                             faster >= 1.1 ? tr(" (%1× cheaper than the current one)").arg(QString::number(faster, 'g', 2))
                                           : QString());
        } else {
            // The lowest error measured, so the person knows how far to raise the target.
            const analysis::StudyRow* best = nullptr;
            for (const analysis::StudyRow& r : m_study.rows)
                if (r.finite && (!best || r.error(m_study.error) < best->error(m_study.error)))
                    best = &r;
            text << (best ? tr("<b>No measured setting is %1</b>: the lowest is %2 (%3).")
                                .arg(within, percent(best->error(m_study.error)), settingName(best->setting()))
                          : tr("<b>No measured setting ran without blowing up.</b>"));
        }
    }
    m_text->setText(text.join(QStringLiteral("<br><br>")));

    const QString blocker = applyBlocker();
    m_apply->setEnabled(blocker.isEmpty());
    m_apply->setToolTip(blocker);
    if (m_remeasured && !busy && m_remeasuredEdits == m_edits) {
        const double error = m_remeasured->error(m_study.error);
        m_check->setText(tr("<b>Re-measured</b> as the scene now stands: %1 of the diagonal (target %2, %3 error)%4.")
                             .arg(percent(error), percent(target()), errorName(m_study.error),
                                  error <= target() ? QString() : tr(": <b>above the target</b>, measure again")));
    } else {
        // Never greyed out without saying why and what to do.
        m_check->setText(blocker);
    }
    updateMinimumHeight();  // the text's height for the panel's width changed with it
    showPointer(m_plot->hoveredRow());  // what a click on the dot under the pointer would do now
}

void StudyPanel::refreshPlot() {
    std::optional<PlotMarker> marker;
    if (const analysis::StudyRow* current = currentRow())
        marker = PlotMarker{current->costPerSecond, current->error(m_study.error), "current"};
    m_plot->setStudy(m_study, marker);
    if (!hasStudy())
        m_plotNote->setText(tr("Error against cost, with the current setting marked, appears here once the scene is measured."));
    else if (!m_plot->studyChart()->hasPoints())
        m_plotNote->setText(tr("Nothing to plot: no measured setting ran without blowing up."));
    m_plotStack->setCurrentWidget(m_plot->studyChart()->hasPoints() ? static_cast<QWidget*>(m_plot) : m_plotNote);
}

void StudyPanel::resizeEvent(QResizeEvent* event) {
    QWidget::resizeEvent(event);
    updateMinimumHeight();
}

void StudyPanel::updateMinimumHeight() {
    // Each item at least its minimum, a wrapped label its height for this width (QLayout's own totals
    // leave the plot's minimum out: its size policy is Ignored).
    QLayout* box = layout();
    const QMargins margins = box->contentsMargins();
    const int inner = width() - margins.left() - margins.right();
    int needed = margins.top() + margins.bottom(), shown = 0;
    for (int i = 0; i < box->count(); ++i) {
        QLayoutItem* item = box->itemAt(i);
        if (item->isEmpty())
            continue;
        needed += std::max(item->minimumSize().height(), item->hasHeightForWidth() ? item->heightForWidth(inner) : 0);
        ++shown;
    }
    needed += std::max(0, shown - 1) * box->spacing();
    if (needed != minimumHeight())
        setMinimumHeight(needed);
}

}  // namespace softtouch::ui

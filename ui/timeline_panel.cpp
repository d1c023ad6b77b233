#include "ui/timeline_panel.h"

#include "io/pipeline/bake.h"
#include "render/preview_page.h"
#include "render/video_render.h"
#include "ui/dope_sheet.h"
#include "ui/edit_commands.h"
#include "ui/frame_ruler.h"
#include "ui/keyframe_panel.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDesktopServices>
#include <QDialog>
#include <QDialogButtonBox>
#include <QFormLayout>
#include <QInputDialog>
#include <QKeyEvent>
#include <QMenu>
#include <QMouseEvent>
#include <QRegularExpression>
#include <QTimer>
#include <algorithm>

#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QVBoxLayout>

#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <thread>

namespace softtouch::ui {

namespace {

/// The timeline's line when no clip or take is on show.
QString idleText() { return TimelinePanel::tr("Record a take, then scrub it here; make a clip of it and export it."); }

/// The loop closure window a clip made a cycle gets: a quarter second, at most half the clip.
int loopBlendFrames(const Clip& clip) { return std::min(clip.frames / 2, int(std::lround(0.25 * clip.fps))); }

/// Export from a file name: by its extension; a path without one is the base path of an export that
/// has none when it ends with "_NAME" or ".NAME" (…_vat, …_lattice); PC2 otherwise.
const io::ExportFormat& formatFor(const QString& path) {
    if (const io::ExportFormat* f = io::exportFormatForPath(path.toStdString()))
        return *f;
    for (const io::ExportFormat& f : io::exportFormats()) {
        const QString name = QString::fromUtf8(f.name.data(), qsizetype(f.name.size()));
        if (f.extensions.empty() && (path.endsWith("_" + name) || path.endsWith("." + name)))
            return f;
    }
    return *io::findExportFormat("pc2");
}

}  // namespace

TimelinePanel::TimelinePanel(Document* document, SimulationController* simulation, QWidget* parent)
    : QWidget(parent), m_document(document), m_simulation(simulation) {
    auto* layout = new QHBoxLayout(this);
    auto* left = new QVBoxLayout;
    m_record = new QPushButton(tr("● Record take"));
    m_record->setObjectName("recordButton");
    m_record->setCheckable(true);
    m_record->setToolTip(tr("Record a take: every grab and drag, step by step, so it replays exactly."));
    left->addWidget(m_record);
    m_takes = new QListWidget;
    m_takes->setObjectName("takes");
    left->addWidget(m_takes);
    layout->addLayout(left);

    auto* middle = new QVBoxLayout;
    auto* clipsLabel = new QLabel(tr("Clips"));
    middle->addWidget(clipsLabel);
    m_clips = new QListWidget;
    m_clips->setObjectName("clips");
    middle->addWidget(m_clips);
    layout->addLayout(middle);

    auto* right = new QVBoxLayout;
    // Transport: first frame, a frame back, play/pause, a frame on, loop; then the ruler.
    auto* transport = new QHBoxLayout;
    const auto button = [&](const QString& text, const char* name, const QString& tip) {
        auto* b = new QPushButton(text);
        b->setObjectName(name);
        b->setToolTip(tip);
        b->setMaximumWidth(44);
        transport->addWidget(b);
        return b;
    };
    QPushButton* first = button(tr("|◀"), "firstFrame", tr("First frame"));
    QPushButton* back = button(tr("◀"), "stepBack", tr("One frame back"));
    m_play = button(tr("▶"), "playClip", tr("Play the selected clip or take (the simulation's Play runs physics live)"));
    QPushButton* forward = button(tr("▶|"), "stepForward", tr("One frame on"));
    m_loopPlayback = new QCheckBox(tr("Loop playback"));
    m_loopPlayback->setObjectName("loopPlayback");
    m_loopPlayback->setChecked(true);
    transport->addWidget(m_loopPlayback);
    transport->addStretch();
    right->addLayout(transport);
    m_ruler = new FrameRuler;
    right->addWidget(m_ruler);
    m_ruler->setGutter(72);  // the dope sheet's row names, left of the frames
    m_dopeSheet = new DopeSheet(m_ruler);
    right->addWidget(m_dopeSheet);
    m_playTimer = new QTimer(this);
    m_playTimer->setInterval(15);
    connect(first, &QPushButton::clicked, this, [this] { showFrame(0); });
    connect(back, &QPushButton::clicked, this, [this] { stepFrame(-1); });
    connect(forward, &QPushButton::clicked, this, [this] { stepFrame(1); });
    connect(m_play, &QPushButton::clicked, this, &TimelinePanel::togglePlayback);
    connect(m_playTimer, &QTimer::timeout, this, [this] {
        advancePlayback(m_playTimer->interval() * 1e-3);
    });
    m_time = new QLabel(idleText());
    m_time->setWordWrap(true);
    right->addWidget(m_time);
    m_baseRange = new QLabel;  // the base animations the scene's objects follow (core/animation/base_motion.h)
    m_baseRange->setObjectName("baseAnimationRange");
    m_baseRange->setWordWrap(true);
    right->addWidget(m_baseRange);
    auto* buttons = new QHBoxLayout;
    auto* makeClipButton = new QPushButton(tr("Clip from take"));
    makeClipButton->setToolTip(tr("Make a clip of the take's in/out range (drag the blue range's ends on the ruler)."));
    m_loop = new QCheckBox(tr("Loop"));
    m_loop->setObjectName("clipLoop");
    auto* exportButton = new QPushButton(tr("Export…"));
    exportButton->setToolTip(tr("Export the selected clip (or the drivers from frame 0) as PC2, MDD, OBJ, glTF/GLB, "
                                "VAT or lattice cache."));
    auto* renderButton = new QPushButton(tr("Render video…"));
    renderButton->setToolTip(tr("Render the selected clip (or the drivers) as MP4/H.264, GIF or PNG frames, "
                                "drawn headless on the GPU: the same code as softtouch-cli render."));
    buttons->addWidget(makeClipButton);
    buttons->addWidget(m_loop);
    buttons->addWidget(exportButton);
    buttons->addWidget(renderButton);
    buttons->addStretch();
    right->addLayout(buttons);
    right->addStretch();
    layout->addLayout(right, 1);

    connect(m_record, &QPushButton::clicked, this, &TimelinePanel::toggleRecording);
    connect(simulation, &SimulationController::recordingChanged, this, [this](bool on) {
        m_record->setChecked(on);
        m_record->setText(on ? tr("■ Stop") : tr("● Record take"));
    });
    // A finished recording becomes a take of the project (undoable, saved with it).
    connect(simulation, &SimulationController::sessionRecorded, this, [this](const Session& session) {
        ClipLibrary after = m_document->project().clips;
        int n = int(after.sessions.size()) + 1;
        while (after.findSession("take " + std::to_string(n)))
            ++n;
        after.sessions.push_back(NamedSession{"take " + std::to_string(n), session});
        m_document->undoStack()->push(new ClipsEditCommand(m_document, m_document->project().clips, std::move(after),
                                                           tr("Record take %1").arg(n)));
        m_takes->setCurrentRow(takeCount() - 1);
    });
    connect(m_takes, &QListWidget::currentRowChanged, this, &TimelinePanel::selectTake);
    connect(m_clips, &QListWidget::currentRowChanged, this, &TimelinePanel::selectClip);
    connect(m_ruler, &FrameRuler::frameChanged, this, &TimelinePanel::showFrame);
    connect(makeClipButton, &QPushButton::clicked, this, [this] {
        const auto range = m_ruler->inOut();
        if (range)
            makeClip(m_takes->currentRow(), m_loop->isChecked(), range->first, range->second);
    });
    connect(m_loop, &QCheckBox::toggled, this, [this](bool checked) {
        if (const int row = m_clips->currentRow(); row >= 0) {
            if (!setClipLoop(row, checked))
                showLoopState();
        } else {
            m_loopForCut = checked;
        }
    });
    // The clips' own menu: play, rename (or double-click), duplicate, frame rate, loop, delete (or Delete).
    m_clips->setContextMenuPolicy(Qt::CustomContextMenu);
    connect(m_clips, &QListWidget::customContextMenuRequested, this, &TimelinePanel::showClipMenu);
    connect(m_clips, &QListWidget::itemDoubleClicked, this, [this] { askToRenameClip(m_clips->currentRow()); });
    m_clips->installEventFilter(this);
    m_clips->viewport()->installEventFilter(this);
    m_takes->viewport()->installEventFilter(this);
    connect(exportButton, &QPushButton::clicked, this, [this] { exportClip(m_clips->currentRow()); });
    connect(renderButton, &QPushButton::clicked, this, [this] { renderClip(m_clips->currentRow()); });
    connect(document, &Document::clipsChanged, this, &TimelinePanel::refreshLists);
    connect(document, &Document::clipsChanged, this, &TimelinePanel::refreshDopeSheet);
    connect(document, &Document::sceneReplaced, this, &TimelinePanel::refreshDopeSheet);
    connect(document, &Document::latticeChanged, this, &TimelinePanel::refreshDopeSheet);
    connect(m_dopeSheet, &DopeSheet::clipChosen, this, [this](int clip) { m_clips->setCurrentRow(clip); });
    connect(m_dopeSheet, &DopeSheet::clipLoopChosen, this, [this](int clip, bool loop) {
        setClipLoop(clip, loop);
        showLoopState();
    });
    connect(document, &Document::sceneReplaced, this, [this] {
        // Another project: nothing of the old one's clips, takes or exports is on show any more.
        m_time->setText(idleText());
        refreshLists();
    });
    // A clip on show while paused is evaluated again after an edit it depends on (material, lattice,
    // world): what the viewport shows is the clip as it now bakes. Once the simulation has rebuilt, so
    // the rebuild does not replace the pose.
    connect(simulation, &SimulationController::rebuilt, this, [this, simulation] {
        const int clip = m_clips->currentRow();
        if (clip >= 0 && clip == m_clipShown && m_clipRevision != m_document->revision() && !simulation->isPlaying())
            showClipFrame(clip, m_ruler->frame());
    });
    refreshLists();
}

double TimelinePanel::fps() const { return m_document->scene().world.fps; }

void TimelinePanel::refreshDopeSheet() {
    const Scene& scene = m_document->scene();
    const ClipLibrary& library = m_document->project().clips;
    const std::string set = m_keySet ? m_keySet() : std::string(KeyframePanel::kDefaultSet);
    const NamedKeyframes* keys = library.findKeyframes(set);
    const int current = m_currentObject ? m_currentObject() : 0;
    std::vector<DopeSheet::Row> rows;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        DopeSheet::Row row;
        row.label = QString::fromStdString(scene.objects[i].name);
        row.object = int(i);
        row.current = int(i) == current;
        if (keys && i < keys->objects.size())
            for (const LatticeKey& k : keys->objects[i].keys()) {
                row.keys.push_back(k.seconds);
                row.interpolation.push_back(k.interpolation);
            }
        rows.push_back(std::move(row));
    }
    // The clips of those keys, as the stretch of key time each plays.
    for (std::size_t c = 0; c < library.clips.size(); ++c) {
        const Clip& clip = library.clips[c];
        if (clip.source != ClipSource::Keyframes || clip.sourceName != set)
            continue;
        DopeSheet::Row row;
        row.label = QString::fromStdString(clip.name);
        row.clip = int(c);
        row.fromSeconds = clip.startSeconds;
        row.toSeconds = clip.startSeconds + clip.frames / clip.fps;
        row.loop = clip.loop;
        rows.push_back(std::move(row));
    }
    m_dopeSheet->setRows(std::move(rows));
}

int TimelinePanel::takeCount() const { return int(m_document->project().clips.sessions.size()); }

void TimelinePanel::toggleRecording() {
    if (m_simulation->isRecording()) {
        m_simulation->stopRecording();
    } else {
        m_simulation->startRecording();
        m_simulation->play();
    }
}

void TimelinePanel::selectTake(int row) {
    if (row < 0)
        return;
    {
        const QSignalBlocker block(m_clips);
        m_clips->setCurrentRow(-1);
    }
    const Session& s = m_document->project().clips.sessions[std::size_t(row)].session;
    const int last = int(std::floor((s.endSeconds() - s.startSeconds()) * fps() + 1e-9));
    m_ruler->setSpan(last, fps());
    m_ruler->setInOut(std::pair(0, last));  // what "Clip from take" cuts: all of it until trimmed
    showRanges();
    showLoopState();
}

void TimelinePanel::showLoopState() {
    const QSignalBlocker block(m_loop);
    const int row = m_clips->currentRow();
    const auto& clips = m_document->project().clips.clips;
    if (row >= 0 && std::size_t(row) < clips.size()) {
        m_loop->setChecked(clips[std::size_t(row)].loop);
        m_loop->setToolTip(tr("This clip is a cycle: its last frame leads into the first, closed over a quarter second."));
    } else {
        m_loop->setChecked(m_loopForCut);
        m_loop->setToolTip(tr("Clip from take makes a cycle: the last frame leads into the first (closed over a quarter "
                              "second)."));
    }
}

void TimelinePanel::showRanges() {
    // On a take: the clips cut from it. Always: each base animation's stretch, as the scene's time runs.
    std::vector<FrameRuler::Range> ranges;
    const ClipLibrary& library = m_document->project().clips;
    const int take = m_takes->currentRow();
    if (take >= 0 && std::size_t(take) < library.sessions.size())
        for (const Clip& c : library.clips)
            if (c.source == ClipSource::Session && c.sourceName == library.sessions[std::size_t(take)].name)
                ranges.push_back({QString::fromStdString(c.name), c.startSeconds, c.startSeconds + c.seconds()});
    // A looping base animation repeats: each cycle is a range, so its loop points show (at most 200 drawn).
    const double from = m_ruler->originSeconds(), to = from + m_ruler->lastFrame() / m_ruler->fps();
    for (const SceneObject& o : m_document->scene().objects) {
        if (!o.baseAnimation || !(o.baseAnimation->duration() > 0.0))
            continue;
        const double d = o.baseAnimation->duration();
        const QString label = tr("base: %1").arg(QString::fromStdString(o.baseAnimation->take));
        const double firstCycle = o.baseAnimation->loop ? std::floor(from / d) : 0.0;
        const double lastCycle = o.baseAnimation->loop ? std::min(std::floor(to / d), firstCycle + 199.0) : 0.0;
        for (double k = firstCycle; k <= lastCycle; k += 1.0)
            ranges.push_back({label, k * d, (k + 1.0) * d});
    }
    m_ruler->setRanges(std::move(ranges));
}

std::string TimelinePanel::exportedClipName() const {
    const int row = m_clips->currentRow();
    const auto& clips = m_document->project().clips.clips;
    return row >= 0 && std::size_t(row) < clips.size() ? clips[std::size_t(row)].name : std::string();
}

void TimelinePanel::selectClip(int row) {
    if (row < 0)
        return;
    {
        const QSignalBlocker block(m_takes);
        m_takes->setCurrentRow(-1);
    }
    const Clip& clip = m_document->project().clips.clips[std::size_t(row)];
    m_ruler->setSpan(clip.frames - 1, clip.fps, clip.startSeconds);
    showRanges();
    showClipFrame(row, 0);
    showLoopState();
    if (clip.source == ClipSource::Keyframes)
        emit keyedClipChosen(clip.sourceName);
}

void TimelinePanel::showFrame(int frame) {
    m_ruler->setFrame(frame);
    m_playPosition = m_ruler->frame();
    if (m_clips->currentRow() >= 0)
        showClipFrame(m_clips->currentRow(), m_ruler->frame());
    else
        scrubTo(m_takes->currentRow(), m_ruler->frame());
}

bool TimelinePanel::isPlaying() const { return m_playTimer->isActive(); }

bool TimelinePanel::showsClipOrTake() const { return m_clips->currentRow() >= 0 || m_takes->currentRow() >= 0; }

QString TimelinePanel::shownName() const {
    const ClipLibrary& library = m_document->project().clips;
    if (const int row = m_clips->currentRow(); row >= 0 && std::size_t(row) < library.clips.size())
        return tr("clip %1").arg(QString::fromStdString(library.clips[std::size_t(row)].name));
    if (const int row = m_takes->currentRow(); row >= 0 && std::size_t(row) < library.sessions.size())
        return QString::fromStdString(library.sessions[std::size_t(row)].name);
    return {};
}

void TimelinePanel::showNothing() {
    if (m_playTimer->isActive())
        togglePlayback();
    m_time->setText(idleText());
    m_ruler->setSpan(std::max(1, m_document->scene().world.frames) - 1, fps());
}

void TimelinePanel::goToEnd(bool last) {
    if (showsClipOrTake())
        showFrame(last ? m_ruler->lastFrame() : 0);
}

void TimelinePanel::togglePlayback() {
    if (m_playTimer->isActive()) {
        m_playTimer->stop();
    } else if (m_clips->currentRow() >= 0 || m_takes->currentRow() >= 0) {
        m_simulation->pause();  // the simulation does not run under a clip being played
        if (m_ruler->frame() >= m_ruler->lastFrame() && !m_loopPlayback->isChecked())
            showFrame(0);
        m_playPosition = m_ruler->frame();
        m_playTimer->start();
    }
    // Two heavy bars, not ⏸ (U+23F8), which DejaVu Sans, the font Debian's desktop falls back to, does not have.
    m_play->setText(m_playTimer->isActive() ? tr("❚❚") : tr("▶"));
}

void TimelinePanel::advancePlayback(double seconds) {
    if (m_clips->currentRow() < 0 && m_takes->currentRow() < 0)
        return;
    const int frames = m_ruler->lastFrame() + 1;
    m_playPosition += seconds * m_ruler->fps();
    if (m_playPosition >= frames) {
        if (m_loopPlayback->isChecked()) {
            m_playPosition = std::fmod(m_playPosition, double(frames));
        } else {
            m_playPosition = m_ruler->lastFrame();
            if (m_playTimer->isActive())
                togglePlayback();
        }
    }
    const int frame = int(std::floor(m_playPosition));
    if (frame != m_ruler->frame()) {
        const double position = m_playPosition;
        showFrame(frame);
        m_playPosition = position;  // keep the fraction between ticks
    }
}

void TimelinePanel::stepFrame(int delta) {
    if (m_clips->currentRow() < 0 && m_takes->currentRow() < 0)
        return;
    const int frames = m_ruler->lastFrame() + 1;
    int frame = m_ruler->frame() + delta;
    frame = m_loopPlayback->isChecked() ? (frame % frames + frames) % frames : std::clamp(frame, 0, frames - 1);
    showFrame(frame);
}

void TimelinePanel::scrubTo(int index, int frame) {
    const auto& sessions = m_document->project().clips.sessions;
    if (index < 0 || std::size_t(index) >= sessions.size())
        return;
    const double seconds = frame / fps();
    if (Status s = m_simulation->scrub(sessions[std::size_t(index)].session, seconds); !s)
        m_time->setText(QString::fromStdString(s.message()));
    else
        m_time->setText(tr("%1 · frame %2 · %3 s")
                            .arg(QString::fromStdString(sessions[std::size_t(index)].name))
                            .arg(frame)
                            .arg(seconds, 0, 'f', 3));
}

void TimelinePanel::showClipFrame(int index, int frame) {
    const ClipLibrary& library = m_document->project().clips;
    if (index < 0 || std::size_t(index) >= library.clips.size())
        return;
    const Clip& clip = library.clips[std::size_t(index)];
    if (m_clipShown != index || m_clipRevision != m_document->revision()) {
        auto frames = evaluateClip(m_document->scene(), library, clip);
        if (!frames) {
            m_time->setText(QString::fromStdString(frames.message()));
            return;
        }
        m_clipFrames = std::move(frames.value());
        m_clipShown = index;
        m_clipRevision = m_document->revision();
    }
    if (m_clipFrames.nodes.empty())
        return;
    const int f = std::clamp(frame, 0, int(m_clipFrames.nodes.size()) - 1);
    m_simulation->showPose(m_clipFrames.nodes[std::size_t(f)], clip.startSeconds + double(f) / clip.fps);
    m_time->setText(tr("clip %1 · frame %2 of %3 at %4 fps%5")
                        .arg(QString::fromStdString(clip.name))
                        .arg(f)
                        .arg(clip.frames)
                        .arg(clip.fps)
                        .arg(clip.loop ? tr(" · loop") : QString()));
}

bool TimelinePanel::makeClip(int index, bool loop) {
    const ClipLibrary& library = m_document->project().clips;
    if (index < 0 || std::size_t(index) >= library.sessions.size())
        return false;
    const Session& take = library.sessions[std::size_t(index)].session;
    return makeClip(index, loop, 0, int(std::floor((take.endSeconds() - take.startSeconds()) * fps() + 1e-9)));
}

bool TimelinePanel::makeClip(int index, bool loop, int in, int out) {
    const ClipLibrary& library = m_document->project().clips;
    if (index < 0 || std::size_t(index) >= library.sessions.size())
        return false;
    const NamedSession& take = library.sessions[std::size_t(index)];
    Clip clip;
    clip.source = ClipSource::Session;
    clip.sourceName = take.name;
    clip.fps = fps();
    clip.startSeconds = std::max(0, in) / clip.fps;
    clip.frames = std::max(1, out - std::max(0, in));
    clip.loop = loop;
    clip.blendFrames = loop ? loopBlendFrames(clip) : 0;
    int n = 1;
    while (library.findClip(take.name + " clip" + (n > 1 ? " " + std::to_string(n) : "")))
        ++n;
    clip.name = take.name + " clip" + (n > 1 ? " " + std::to_string(n) : "");
    ClipLibrary after = library;
    after.clips.push_back(clip);
    if (Status s = after.validate(m_document->scene()); !s) {
        m_time->setText(QString::fromStdString(s.message()));
        return false;
    }
    m_document->undoStack()->push(new ClipsEditCommand(m_document, library, std::move(after),
                                                       tr("Make clip %1").arg(QString::fromStdString(clip.name))));
    m_clips->setCurrentRow(m_clips->count() - 1);
    return true;
}

QString TimelinePanel::suggestedOutputPath(int index, const QString& suffix) const {
    const QFileInfo project(m_document->filePath());
    const QString folder = m_document->filePath().isEmpty() ? QDir::homePath() : project.absolutePath();
    QString name = m_document->filePath().isEmpty() ? QStringLiteral("untitled") : project.completeBaseName();
    const ClipLibrary& library = m_document->project().clips;
    name += "-" + (index >= 0 && std::size_t(index) < library.clips.size()
                       ? QString::fromStdString(library.clips[std::size_t(index)].name)
                       : QStringLiteral("drivers"));
    // A name a shell, a build script and an engine's importer take as one word: "take 1 clip" becomes take-1-clip.
    name.replace(QRegularExpression("[^A-Za-z0-9._-]+"), "-");
    return QDir(folder).filePath(name + "." + suffix);
}

QString TimelinePanel::statusText() const { return m_time->text(); }

QStringList TimelinePanel::exportFilters() {
    QStringList filters;
    for (const io::ExportFormat& f : io::exportFormats()) {
        const QString label = QString::fromUtf8(f.label.data(), qsizetype(f.label.size()));
        QStringList patterns;
        for (std::string_view e : io::extensionsOf(f))
            patterns << "*" + QString::fromUtf8(e.data(), qsizetype(e.size()));
        filters << (patterns.isEmpty() ? tr("%1 (base name) (*)").arg(label)
                                       : QStringLiteral("%1 (%2)").arg(label, patterns.join(' ')));
    }
    return filters;
}

void TimelinePanel::exportClip(int index) {
    // The file type chosen in the dialog decides the export (several are .glb files).
    const QStringList filters = exportFilters();
    QString selected = filters.front();
    const QString path = QFileDialog::getSaveFileName(this, tr("Export Clip"), suggestedOutputPath(index, "pc2"),
                                                      filters.join(";;"), &selected);
    if (path.isEmpty())
        return;
    const qsizetype chosen = filters.indexOf(selected);
    const io::ExportFormat& format = chosen < 0 ? formatFor(path) : io::exportFormats()[std::size_t(chosen)];
    // Several objects: all in one file, the current one, or each in its own; OBJ groups on request. A GLB
    // for a game: packed for shipping on request.
    ExportChoices choices;
    const Scene& scene = m_document->scene();
    const bool packable = format.takesCompress && !io::writesGltfJson(path.toStdString());
    const bool rigged = format.takesBones && std::any_of(scene.objects.begin(), scene.objects.end(),
                                                         [](const SceneObject& o) { return o.baseAnimation != nullptr; });
    const bool previewable = !m_previewAssets.webRoot.empty() && io::previewPlays(format.name);
    if (scene.objects.size() > 1 || packable || rigged || previewable) {
        QDialog ask(this);
        ask.setWindowTitle(tr("Export Options"));
        auto* form = new QFormLayout(&ask);
        QComboBox* which = nullptr;
        QCheckBox* groups = nullptr;
        QCheckBox* compress = nullptr;
        QComboBox* bones = nullptr;
        const auto addCheck = [form](const char* name, const QString& text, const QString& tip) {
            auto* box = new QCheckBox(text);
            box->setObjectName(name);
            box->setToolTip(tip);
            form->addRow(box);
            return box;
        };
        QString currentName;
        if (scene.objects.size() > 1) {
            which = new QComboBox;
            which->setObjectName("exportObjects");
            which->addItem(tr("All %1 objects in one file").arg(scene.objects.size()));
            const int current = m_currentObject ? m_currentObject() : 0;
            currentName = QString::fromStdString(scene.objects[std::size_t(std::clamp(current, 0, int(scene.objects.size()) - 1))].name);
            which->addItem(tr("Only %1 (the current object)").arg(currentName));
            which->addItem(tr("Each object in its own file (name-OBJECT)"));
            form->addRow(tr("Objects"), which);
            groups = addCheck("exportGroups", tr("Name each object's faces in OBJ files (g OBJECT)"),
                              tr("A DCC then imports one part per object; some importers reorder vertices when they split "
                                 "groups, which PC2 and MDD caches rely on."));
        }
        if (packable) {
            compress = addCheck("exportCompress", tr("Pack for shipping (EXT_meshopt_compression)"),
                                tr("About a third of the size, as games ship glTF: every buffer packed losslessly, normals "
                                   "as 16-bit octahedral vectors, skin weights in 8 bits. three.js, Babylon.js and Unity's "
                                   "glTFast read it; Blender, assimp and Godot 4 do not, so keep an unpacked file for a DCC."));
        }
        if (rigged) {
            bones = new QComboBox;
            bones->setObjectName("exportBones");
            bones->addItem(tr("The mesh file's own rig, plus helper bones for the wobble"));
            bones->addItem(tr("Bones fitted to the clip alone"));
            bones->setToolTip(tr("On its own rig the file keeps the skeleton the mesh came with (joint names, hierarchy, "
                                 "bind pose and animation), so it goes back onto your character with its other "
                                 "animations; a few helper bones under its joints carry the wobble. Fitted bones replace "
                                 "the skeleton."));
            form->addRow(tr("Bones"), bones);
        }
        QCheckBox* preview = nullptr;
        if (previewable) {
            preview = addCheck("exportPreview", tr("Open a preview page (the clip played by three.js in your web browser)"),
                               tr("Writes a page beside the export (NAME-preview/index.html) that plays it the way a game "
                                  "engine does, from disk, with no server; the same page as softtouch-cli preview. Not "
                                  "for one file per object."));
        }
        auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
        connect(buttons, &QDialogButtonBox::accepted, &ask, &QDialog::accept);
        connect(buttons, &QDialogButtonBox::rejected, &ask, &QDialog::reject);
        form->addRow(buttons);
        if (ask.exec() != QDialog::Accepted)
            return;
        if (which && which->currentIndex() == 1)
            choices.only = {currentName.toStdString()};
        choices.each = which && which->currentIndex() == 2;
        choices.groups = groups && groups->isChecked();
        choices.compress = compress && compress->isChecked();
        choices.fittedBones = bones && bones->currentIndex() == 1;
        choices.preview = preview && preview->isChecked() && !choices.each;
    }
    const Status s = exportClipTo(index, path, format, choices);
    if (!s && !s.wasCancelled())  // a cancel is the user's choice, not an error (the message said so, and
        QMessageBox::critical(this, tr("Export failed"), QString::fromStdString(s.message()));  // never matched)
    if (s && choices.preview)
        previewExport(path);
}

void TimelinePanel::previewExport(const QString& path) {
    // Beside the export, named after it: "fish-swim.glb" -> "fish-swim-preview/index.html" (a VAT's or a lattice
    // cache's base path likewise).
    const QFileInfo exported(path);
    const QString base = exported.suffix() == "glb" || exported.suffix() == "gltf" ? exported.completeBaseName() : exported.fileName();
    const QString folder = exported.dir().filePath(base + "-preview");
    const QString exportedText = m_time->text();
    auto page = render::writePreviewPage(path.toStdString(), folder.toStdString(), 960, 540, m_previewAssets);
    if (!page) {
        QMessageBox::warning(this, tr("Preview page"),
                             tr("The clip was exported, but its preview page was not written: %1").arg(QString::fromStdString(page.message())));
        return;
    }
    const QString index = QString::fromStdString(page->index.string());
    m_time->setText(tr("%1; preview page %2").arg(exportedText, index));
    QDesktopServices::openUrl(QUrl::fromLocalFile(index));
}

Status TimelinePanel::exportClipTo(int index, const QString& path) { return exportClipTo(index, path, formatFor(path)); }

Status TimelinePanel::exportClipTo(int index, const QString& path, const io::ExportFormat& format) {
    return exportClipTo(index, path, format, ExportChoices{});
}

Status TimelinePanel::exportClipTo(int index, const QString& path, const io::ExportFormat& format, const ExportChoices& choices) {
    const ClipLibrary& library = m_document->project().clips;
    io::BakeOptions options;
    options.objects = choices.only;
    options.objectGroups = choices.groups;
    options.output = path.toStdString();
    options.format = &format;
    io::ExportSettings settings;
    settings.compress = choices.compress;
    if (format.takesBones)
        settings.rig = choices.fittedBones ? io::ClipExportOptions::SkinRig::Fitted : io::ClipExportOptions::SkinRig::Auto;
    auto exportOptions = io::exportOptions(format, settings);  // the defaults, packed or not
    if (!exportOptions) {
        m_time->setText(QString::fromStdString(exportOptions.message()));
        return exportOptions.status();
    }
    options.exportOptions = exportOptions.value();
    options.clips = &library;
    options.meshSources = io::meshSources(m_document->project());
    if (index >= 0 && std::size_t(index) < library.clips.size())
        options.clip = library.clips[std::size_t(index)].name;
    QProgressDialog progress(tr("Exporting %1…").arg(path), tr("Cancel"), 0, 100, this);
    progress.setWindowModality(Qt::WindowModal);
    progress.setMinimumDuration(300);
    options.progress = [&progress](int done, int total) {
        progress.setMaximum(total);
        progress.setValue(done);
        QApplication::processEvents();
        return !progress.wasCanceled();
    };
    if (choices.each) {
        auto results = io::bakeEachObject(m_document->scene(), options);
        progress.reset();
        if (!results) {
            m_time->setText(QString::fromStdString(results.message()));
            return results.status();
        }
        QStringList files;
        for (const io::BakeResult& r : results.value())
            files << QString::fromStdString(r.cache.filename().string());
        m_time->setText(tr("Exported %1 frames of each object to %2 (each with its rest mesh)")
                            .arg(results->empty() ? 0 : results->front().frames)
                            .arg(files.join(", ")));
        return Status::success();
    }
    auto result = io::bake(m_document->scene(), options);
    progress.reset();
    if (!result) {
        m_time->setText(QString::fromStdString(result.message()));
        return result.status();
    }
    // Say every file written: the rest mesh the cache matches is one of them.
    QString text = tr("Exported %1 frames to %2 (and its rest mesh %3)")
                       .arg(result->frames)
                       .arg(QString::fromStdString(result->cache.string()))
                       .arg(QString::fromStdString(result->restMesh.filename().string()));
    if (result->seam)
        text += tr(" · loop seam %1× the median frame step").arg(result->seam->ratio, 0, 'f', 2);
    for (const std::string& note : result->notes)  // a compressed export's error and size
        text += " · " + QString::fromStdString(note.substr(note.find(": ") == std::string::npos ? 0 : note.find(": ") + 2));
    m_time->setText(text);
    return Status::success();
}

void TimelinePanel::renderClip(int index) {
    // Size and camera first: the viewport's view is what the animator framed; the ¾ view is the CLI's.
    QDialog settings(this);
    settings.setWindowTitle(tr("Render Video"));
    auto* form = new QFormLayout(&settings);
    auto* size = new QComboBox;
    size->setObjectName("renderSize");
    for (const QSize s : {QSize(640, 360), QSize(960, 540), QSize(1280, 720), QSize(1920, 1080)})
        size->addItem(QStringLiteral("%1 × %2").arg(s.width()).arg(s.height()), s);
    size->setCurrentIndex(1);
    form->addRow(tr("Size"), size);
    auto* camera = new QComboBox;
    camera->setObjectName("renderCamera");
    if (m_viewCamera)
        camera->addItem(tr("This view (the viewport's camera)"));
    camera->addItem(tr("¾ view of the whole scene (as softtouch-cli render)"));
    form->addRow(tr("Camera"), camera);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
    connect(buttons, &QDialogButtonBox::accepted, &settings, &QDialog::accept);
    connect(buttons, &QDialogButtonBox::rejected, &settings, &QDialog::reject);
    form->addRow(buttons);
    if (settings.exec() != QDialog::Accepted)
        return;
    const QSize pixels = size->currentData().toSize();
    std::optional<render::CameraPlacement> placement;
    if (m_viewCamera && camera->currentIndex() == 0)
        placement = m_viewCamera();
    const QString path = QFileDialog::getSaveFileName(this, tr("Render Video"), suggestedOutputPath(index, "mp4"),
                                                      tr("MP4 video (*.mp4);;Animated GIF (*.gif)"));
    if (path.isEmpty())
        return;
    const Status s = renderClipTo(index, path, pixels.width(), pixels.height(), placement);
    if (!s && !s.wasCancelled())
        QMessageBox::critical(this, tr("Render failed"), QString::fromStdString(s.message()));
}

Status TimelinePanel::renderClipTo(int index, const QString& path, int width, int height,
                                   std::optional<render::CameraPlacement> camera) {
    const ClipLibrary& library = m_document->project().clips;
    const auto format = io::videoFormatFromPath(path.toStdString());
    if (!format)
        return Status::error(path.toStdString() + ": use .mp4, .gif or a folder ending in '/'");
    render::VideoRenderOptions options;
    options.video.output = path.toStdString();
    options.video.format = *format;
    options.video.width = width;
    options.video.height = height;
    options.camera = camera;
    options.frames.clips = &library;
    if (index >= 0 && std::size_t(index) < library.clips.size())
        options.frames.clip = library.clips[std::size_t(index)].name;
    // The render runs on its own thread: its EGL context cannot be current on the UI thread, where the
    // viewport's GLX context lives (glvnd allows one window-system API per thread). The UI thread keeps
    // the progress dialog alive and passes Cancel on.
    std::atomic<int> done{0}, total{0};
    std::atomic<bool> cancelled{false}, finished{false};
    options.progress = [&](int d, int t) {
        done = d;
        total = t;
        return !cancelled.load();
    };
    std::optional<Result<render::VideoRenderResult>> outcome;
    const Scene scene = m_document->scene();
    std::thread worker([&] {
        outcome.emplace(render::renderVideo(scene, options));
        finished = true;
    });
    QProgressDialog progress(tr("Rendering %1…").arg(path), tr("Cancel"), 0, 100, this);
    progress.setWindowModality(Qt::WindowModal);
    progress.setMinimumDuration(300);
    while (!finished) {
        progress.setMaximum(std::max(total.load(), 1));
        progress.setValue(done.load());
        if (progress.wasCanceled())
            cancelled = true;
        QApplication::processEvents(QEventLoop::AllEvents, 20);
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    worker.join();
    Result<render::VideoRenderResult>& result = *outcome;
    progress.reset();
    if (!result) {
        m_time->setText(QString::fromStdString(result.message()));
        return result.status();
    }
    m_time->setText(tr("Rendered %1 frames (%2) to %3").arg(result->frames).arg(QString::fromStdString(result->codec)).arg(path));
    return Status::success();
}

bool TimelinePanel::editClips(const QString& text, const std::function<Status(ClipLibrary&)>& change) {
    const ClipLibrary& library = m_document->project().clips;
    ClipLibrary after = library;
    Status s = change(after);
    if (s)
        s = after.validate(m_document->scene());
    if (!s) {
        m_time->setText(QString::fromStdString(s.message()));
        return false;
    }
    m_document->undoStack()->push(new ClipsEditCommand(m_document, library, std::move(after), text));
    return true;
}

bool TimelinePanel::renameClip(int index, const QString& name) {
    const std::string to = name.trimmed().toStdString();
    return editClips(tr("Rename clip to %1").arg(name.trimmed()), [&](ClipLibrary& library) -> Status {
        if (index < 0 || std::size_t(index) >= library.clips.size())
            return Status::error("no clip " + std::to_string(index));
        if (to.empty())
            return Status::error("a clip needs a name");
        if (library.clips[std::size_t(index)].name != to && library.findClip(to))
            return Status::error("there is already a clip named \"" + to + "\"");
        library.clips[std::size_t(index)].name = to;
        return Status::success();
    });
}

bool TimelinePanel::duplicateClip(int index) {
    return editClips(tr("Duplicate clip"), [&](ClipLibrary& library) -> Status {
        if (index < 0 || std::size_t(index) >= library.clips.size())
            return Status::error("no clip " + std::to_string(index));
        Clip copy = library.clips[std::size_t(index)];
        const std::string base = copy.name + " copy";
        copy.name = base;
        for (int n = 2; library.findClip(copy.name); ++n)
            copy.name = base + " " + std::to_string(n);
        library.clips.insert(library.clips.begin() + index + 1, std::move(copy));
        return Status::success();
    });
}

bool TimelinePanel::deleteClip(int index) {
    return editClips(tr("Delete clip"), [&](ClipLibrary& library) -> Status {
        if (index < 0 || std::size_t(index) >= library.clips.size())
            return Status::error("no clip " + std::to_string(index));
        library.clips.erase(library.clips.begin() + index);
        return Status::success();
    });
}

bool TimelinePanel::setClipLoop(int index, bool loop) {
    const auto& clips = m_document->project().clips.clips;
    if (index < 0 || std::size_t(index) >= clips.size())
        return false;
    const QString name = QString::fromStdString(clips[std::size_t(index)].name);
    return editClips(loop ? tr("Loop clip %1").arg(name) : tr("Stop looping clip %1").arg(name),
                     [&](ClipLibrary& library) -> Status {
                         Clip& clip = library.clips[std::size_t(index)];
                         // A keyed clip made to its last key holds that key as its last frame; as a cycle the last
                         // key is where the next pass starts (frame N is frame 0 again), so the span loses that
                         // frame, and gets it back as a one-shot. A clip trimmed otherwise keeps its length.
                         if (const NamedKeyframes* keys = clip.source == ClipSource::Keyframes ? library.findKeyframes(clip.sourceName)
                                                                                               : nullptr) {
                             double last = clip.startSeconds;
                             for (const KeyframeAnimation& object : keys->objects)
                                 if (!object.keys().empty())
                                     last = std::max(last, object.keys().back().seconds);
                             const int period = int(std::lround((last - clip.startSeconds) * clip.fps));
                             if (period >= 2 && loop && !clip.loop && clip.frames == period + 1)
                                 clip.frames = period;
                             else if (period >= 2 && !loop && clip.loop && clip.frames == period)
                                 clip.frames = period + 1;
                         }
                         clip.loop = loop;
                         clip.blendFrames = loop ? loopBlendFrames(clip) : 0;
                         return Status::success();
                     });
}

bool TimelinePanel::retimeClip(int index, double rate) {
    return editClips(tr("Clip frame rate %1").arg(rate), [&](ClipLibrary& library) -> Status {
        if (index < 0 || std::size_t(index) >= library.clips.size())
            return Status::error("no clip " + std::to_string(index));
        Clip& clip = library.clips[std::size_t(index)];
        const double scale = rate / clip.fps;
        clip.frames = std::max(1, int(std::lround(clip.frames * scale)));
        clip.blendFrames = std::min(clip.frames, int(std::lround(clip.blendFrames * scale)));
        clip.fps = rate;
        return Status::success();
    });
}

void TimelinePanel::askToRenameClip(int index) {
    const ClipLibrary& library = m_document->project().clips;
    if (index < 0 || std::size_t(index) >= library.clips.size())
        return;
    bool ok = false;
    const QString name = QInputDialog::getText(this, tr("Rename Clip"), tr("Name"), QLineEdit::Normal,
                                               QString::fromStdString(library.clips[std::size_t(index)].name), &ok);
    if (ok)
        renameClip(index, name);
}

void TimelinePanel::showClipMenu(const QPoint& pos) {
    const int row = m_clips->indexAt(pos).row();
    if (row < 0)
        return;
    m_clips->setCurrentRow(row);
    const Clip clip = m_document->project().clips.clips[std::size_t(row)];
    QMenu menu(this);
    menu.addAction(tr("Play"), this, [this] {
        if (!isPlaying())
            togglePlayback();
    });
    menu.addAction(tr("Rename…"), this, [this, row] { askToRenameClip(row); });
    menu.addAction(tr("Duplicate"), this, [this, row] { duplicateClip(row); });
    menu.addAction(tr("Frame Rate…"), this, [this, row, clip] {
        bool ok = false;
        const double rate = QInputDialog::getDouble(this, tr("Clip Frame Rate"), tr("Frames per second (same duration)"),
                                                    clip.fps, 1.0, 1000.0, 3, &ok);
        if (ok)
            retimeClip(row, rate);
    });
    QAction* loop = menu.addAction(tr("Loop"), this, [this, row, clip] { setClipLoop(row, !clip.loop); });
    loop->setCheckable(true);
    loop->setChecked(clip.loop);
    menu.addSeparator();
    menu.addAction(tr("Delete"), this, [this, row] { deleteClip(row); });
    menu.exec(m_clips->viewport()->mapToGlobal(pos));
}

bool TimelinePanel::eventFilter(QObject* watched, QEvent* event) {
    // Delete in the clips list deletes the selected clip (one undo step).
    if (watched == m_clips && event->type() == QEvent::KeyPress) {
        const auto* key = static_cast<QKeyEvent*>(event);
        if ((key->key() == Qt::Key_Delete || key->key() == Qt::Key_Backspace) && m_clips->currentRow() >= 0) {
            deleteClip(m_clips->currentRow());
            return true;
        }
    }
    // A click on empty space in the clips or takes list puts nothing on show: the transport drives the live
    // simulation again.
    if ((watched == m_clips->viewport() || watched == m_takes->viewport()) && event->type() == QEvent::MouseButtonPress) {
        auto* list = watched == m_clips->viewport() ? m_clips : m_takes;
        if (!list->itemAt(static_cast<QMouseEvent*>(event)->position().toPoint())) {
            list->setCurrentRow(-1);
            list->clearSelection();
            showNothing();
            showRanges();
            showLoopState();
            return true;
        }
    }
    return QWidget::eventFilter(watched, event);
}

void TimelinePanel::refreshLists() {
    QStringList bases;
    for (const SceneObject& o : m_document->scene().objects)
        if (o.baseAnimation)
            bases << tr("%1 follows \"%2\" from %3 to %4 s of its take%5")
                         .arg(QString::fromStdString(o.name), QString::fromStdString(o.baseAnimation->take))
                         .arg(o.baseAnimation->start, 0, 'g', 4)
                         .arg(o.baseAnimation->start + o.baseAnimation->duration(), 0, 'g', 4)
                         .arg(o.baseAnimation->loop ? tr(", looping") : QString());
    m_baseRange->setText(bases.isEmpty() ? QString() : tr("Base animation: %1").arg(bases.join("; ")));
    m_baseRange->setVisible(!bases.isEmpty());
    const ClipLibrary& library = m_document->project().clips;
    m_clipShown = -1;  // a clip may have changed: evaluate again
    const int takeRow = m_takes->currentRow(), clipRow = m_clips->currentRow();
    const QSignalBlocker blockTakes(m_takes);
    const QSignalBlocker blockClips(m_clips);
    m_takes->clear();
    for (const NamedSession& s : library.sessions)
        m_takes->addItem(tr("%1 · %2 s").arg(QString::fromStdString(s.name)).arg(s.session.endSeconds() - s.session.startSeconds(), 0, 'f', 2));
    m_clips->clear();
    for (const Clip& c : library.clips)
        m_clips->addItem(tr("%1 · %2 frames @ %3%4")
                             .arg(QString::fromStdString(c.name))
                             .arg(c.frames)
                             .arg(c.fps)
                             .arg(c.loop ? tr(" · loop") : QString()));
    // The row selected before stays selected when it still exists (a rename, a retime); the ruler follows it.
    if (clipRow >= 0 && clipRow < m_clips->count()) {
        m_clips->setCurrentRow(clipRow);
        const Clip& clip = library.clips[std::size_t(clipRow)];
        if (m_ruler->lastFrame() != clip.frames - 1 || m_ruler->fps() != clip.fps) {
            const int frame = m_ruler->frame();
            m_ruler->setSpan(clip.frames - 1, clip.fps, clip.startSeconds);
            m_ruler->setFrame(frame);
        }
    } else if (takeRow >= 0 && takeRow < m_takes->count() && clipRow < 0) {
        m_takes->setCurrentRow(takeRow);
    } else if (clipRow >= 0) {
        showNothing();  // the clip shown was deleted
    }
    if (m_clips->currentRow() < 0 && m_takes->currentRow() < 0 && clipRow < 0 && takeRow < 0) {
        // Key time, for the keys; the playhead stays where it is (a key just set there, say) unless the span changed.
        const int last = std::max(1, m_document->scene().world.frames) - 1;
        if (m_ruler->lastFrame() != last || m_ruler->fps() != fps() || m_ruler->originSeconds() != 0.0)
            m_ruler->setSpan(last, fps());
    }
    showRanges();
    showLoopState();
}

}  // namespace softtouch::ui

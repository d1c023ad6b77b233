#include "ui/keyframe_panel.h"

#include "ui/edit_commands.h"
#include "ui/frame_ruler.h"
#include "ui/spin_box.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QSpinBox>

#include <algorithm>
#include <cmath>
#include <functional>

namespace softtouch::ui {

namespace {

/// A keyframe set named `name` with no keys, one animation per object of `scene` on its lattice's nodes.
NamedKeyframes emptyKeySet(const std::string& name, const Scene& scene) {
    NamedKeyframes set;
    set.name = name;
    for (const SceneObject& o : scene.objects)
        set.objects.emplace_back(std::size_t(o.lattice.nodeCount()));
    return set;
}

}  // namespace

KeyframePanel::KeyframePanel(Document* document, SimulationController* simulation, Viewport* viewport, QWidget* parent)
    : QWidget(parent), m_document(document), m_simulation(simulation), m_viewport(viewport) {
    auto* layout = new QGridLayout(this);
    m_sets = new QComboBox;
    m_sets->setObjectName("keySet");
    m_sets->setToolTip(tr("The keyframe set these keys belong to: each set is its own animation, with its own clips. "
                          "The timeline's dope sheet shows the same set."));
    auto* newSet = new QPushButton(tr("New set"));
    newSet->setObjectName("newKeySet");
    newSet->setToolTip(tr("Start another keyframe set, empty, beside the others."));
    auto* sets = new QHBoxLayout;
    sets->addWidget(m_sets, 1);
    sets->addWidget(newSet);
    layout->addLayout(sets, 0, 0);
    m_list = new QListWidget;
    m_list->setObjectName("keys");
    layout->addWidget(m_list, 1, 0, 6, 1);
    m_frame = new QSpinBox;
    m_frame->setObjectName("keyFrame");
    m_frame->setRange(0, 1000000);
    m_frame->setToolTip(tr("The frame Key pose (I) keys at, counted from the scene's start at its frame rate; it "
                           "follows the playhead on the timeline's ruler."));
    m_seconds = new QLabel;
    auto* at = new QHBoxLayout;
    at->addWidget(m_frame, 1);
    at->addWidget(m_seconds);
    layout->addWidget(new QLabel(tr("Key frame")), 0, 1);
    layout->addLayout(at, 0, 2);
    connect(m_frame, &QSpinBox::valueChanged, this, &KeyframePanel::showSeconds);
    auto* key = new QPushButton(tr("Key pose"));
    key->setToolTip(tr("Key the current pose of the selected nodes (all nodes when none is selected)."));
    auto* move = new QPushButton(tr("Move key here"));
    auto* copy = new QPushButton(tr("Copy key here"));
    auto* remove = new QPushButton(tr("Delete key"));
    layout->addWidget(key, 1, 1);
    layout->addWidget(move, 1, 2);
    layout->addWidget(copy, 2, 1);
    layout->addWidget(remove, 2, 2);
    m_interpolation = new QComboBox;
    m_interpolation->setObjectName("keyInterpolation");
    for (KeyInterpolation how : {KeyInterpolation::Smooth, KeyInterpolation::Linear, KeyInterpolation::Constant})
        m_interpolation->addItem(keyInterpolationLabel(how), int(how));
    m_interpolation->setToolTip(tr("How the selected key moves on to the next: smooth (a spline through the keys), "
                                   "linear (a straight line), constant (held, then a snap to the next key). Also on "
                                   "the key's right-click menu in the Timeline's ruler."));
    m_interpolation->setEnabled(false);
    layout->addWidget(new QLabel(tr("Interpolation")), 3, 1);
    layout->addWidget(m_interpolation, 3, 2);
    m_goals = new QCheckBox(tr("As goals (physics follow-through)"));
    m_goalStrength = makeSpinBox(0.01, kGoalWeight.high, 2, QString(), 0.5);
    m_goalStrength->setObjectName("goalStrength");
    m_goalStrength->setValue(GoalSettings{}.weight);
    m_goalStrength->setPrefix(QStringLiteral("× "));
    m_goalStrength->setToolTip(tr("How hard the goal springs pull the keyed nodes to their keys (%1 N/m and %2 N·s/m "
                                  "per node at × 1): higher follows the keys more closely, lower leaves more to "
                                  "the material.")
                                   .arg(GoalSettings{}.stiffness)
                                   .arg(GoalSettings{}.damping));
    m_goalStrength->setEnabled(false);
    connect(m_goals, &QCheckBox::toggled, m_goalStrength, &QWidget::setEnabled);
    auto* clip = new QPushButton(tr("Clip from keys"));
    layout->addWidget(m_goals, 4, 1, 1, 2);
    layout->addWidget(new QLabel(tr("Goal strength")), 5, 1);
    layout->addWidget(m_goalStrength, 5, 2);
    layout->addWidget(clip, 6, 1, 1, 2);
    m_message = new QLabel;
    m_message->setWordWrap(true);
    layout->addWidget(m_message, 7, 0, 1, 3);

    connect(key, &QPushButton::clicked, this, [this] { keyPose(keyTime()); });
    connect(move, &QPushButton::clicked, this, [this] { moveKey(m_list->currentRow(), keyTime(), false); });
    connect(copy, &QPushButton::clicked, this, [this] { moveKey(m_list->currentRow(), keyTime(), true); });
    connect(remove, &QPushButton::clicked, this, [this] { deleteKey(m_list->currentRow()); });
    connect(clip, &QPushButton::clicked, this, [this] { makeClip(m_goals->isChecked()); });
    connect(m_list, &QListWidget::currentRowChanged, this, &KeyframePanel::showKey);
    connect(m_interpolation, &QComboBox::activated, this, [this](int item) {
        setInterpolation(m_list->currentRow(), KeyInterpolation(m_interpolation->itemData(item).toInt()));
    });
    connect(m_sets, &QComboBox::activated, this, [this](int item) { setKeySet(m_sets->itemText(item).toStdString()); });
    connect(newSet, &QPushButton::clicked, this, [this] { newKeySet(); });
    connect(document, &Document::clipsChanged, this, &KeyframePanel::refresh);
    connect(document, &Document::sceneReplaced, this, &KeyframePanel::pickSetOf);
    pickSetOf();
}

void KeyframePanel::pickSetOf() {
    m_set = kDefaultSet;  // refresh() moves on to the first set where the project has sets but not this one
    refresh();
    emit keySetChanged();
}

void KeyframePanel::setKeySet(const std::string& name) {
    if (name == m_set)
        return;
    m_set = name;
    {
        const QSignalBlocker quiet(m_list);
        m_list->setCurrentRow(-1);  // a row of the other set's keys means nothing here
    }
    refresh();
    emit keySetChanged();
}

bool KeyframePanel::newKeySet() {
    const Scene& scene = m_document->scene();
    const ClipLibrary& library = m_document->project().clips;
    int n = 2;
    while (library.findKeyframes(std::string(kDefaultSet) + " " + std::to_string(n)))
        ++n;
    NamedKeyframes fresh = emptyKeySet(std::string(kDefaultSet) + " " + std::to_string(n), scene);
    ClipLibrary after = library;
    after.keyframes.push_back(fresh);
    m_set = fresh.name;  // shown once the library has it
    m_document->undoStack()->push(new ClipsEditCommand(m_document, library, std::move(after),
                                                       tr("New key set %1").arg(QString::fromStdString(fresh.name))));
    emit keySetChanged();
    return true;
}

void KeyframePanel::refreshSets() {
    const QSignalBlocker quiet(m_sets);
    m_sets->clear();
    for (const NamedKeyframes& k : m_document->project().clips.keyframes)
        m_sets->addItem(QString::fromStdString(k.name));
    if (m_sets->findText(QString::fromStdString(m_set)) < 0)
        m_sets->addItem(QString::fromStdString(m_set));  // no keys yet: the first key makes it
    m_sets->setCurrentIndex(m_sets->findText(QString::fromStdString(m_set)));
}

std::vector<LatticeKey> KeyframePanel::keys() const {
    const NamedKeyframes* set = m_document->project().clips.findKeyframes(m_set);
    const auto object = std::size_t(m_viewport->currentObject());
    if (!set || object >= set->objects.size())
        return {};
    return set->objects[object].keys();
}

bool KeyframePanel::edit(const QString& text, const std::function<Status(KeyframeAnimation&)>& change) {
    const Scene& scene = m_document->scene();
    const auto object = std::size_t(m_viewport->currentObject());
    if (object >= scene.objects.size())
        return false;
    ClipLibrary after = m_document->project().clips;
    NamedKeyframes* set = nullptr;
    for (NamedKeyframes& k : after.keyframes)
        if (k.name == m_set)
            set = &k;
    if (!set) {
        after.keyframes.push_back(emptyKeySet(m_set, scene));
        set = &after.keyframes.back();
    }
    if (object >= set->objects.size() || set->objects[object].nodeCount() != std::size_t(scene.objects[object].lattice.nodeCount())) {
        m_message->setText(tr("The keys were made on another lattice; delete them first."));
        return false;
    }
    if (Status s = change(set->objects[object]); !s) {
        m_message->setText(QString::fromStdString(s.message()));
        return false;
    }
    m_document->undoStack()->push(new ClipsEditCommand(m_document, m_document->project().clips, std::move(after), text));
    m_message->clear();
    return true;
}

double KeyframePanel::keyTime() const { return m_frame->value() / m_document->scene().world.fps; }

void KeyframePanel::showInterpolation(KeyInterpolation interpolation) {
    const QSignalBlocker quiet(m_interpolation);
    m_interpolation->setCurrentIndex(m_interpolation->findData(int(interpolation)));
}

void KeyframePanel::showSeconds() { m_seconds->setText(tr("%1 s").arg(keyTime(), 0, 'f', 3)); }

void KeyframePanel::setKeyTime(double seconds) {
    m_frame->setValue(int(std::lround(seconds * m_document->scene().world.fps)));
}

bool KeyframePanel::keyPose(double seconds) {
    const SceneSimulation* sim = m_simulation->simulation();
    const auto object = std::size_t(m_viewport->currentObject());
    if (!sim || object >= sim->objectCount())
        return false;
    const std::vector<Vec3> rest = sim->object(object).lattice.restNodes();
    const std::vector<Vec3> pose = sim->simulator(object).state().position;
    std::vector<std::uint32_t> nodes(m_viewport->selection().begin(), m_viewport->selection().end());
    return edit(tr("Key pose at %1 s").arg(seconds), [&](KeyframeAnimation& a) -> Status {
        auto index = a.setKey(seconds, rest, pose, nodes);
        return index ? Status::success() : Status::error(index.message());
    });
}

bool KeyframePanel::moveKey(int index, double seconds, bool copy) {
    if (index < 0)
        return false;
    return edit(copy ? tr("Copy key") : tr("Move key"), [&](KeyframeAnimation& a) -> Status {
        auto moved = copy ? a.copyKey(std::size_t(index), seconds) : a.moveKey(std::size_t(index), seconds);
        return moved ? Status::success() : Status::error(moved.message());
    });
}

bool KeyframePanel::deleteKey(int index) {
    if (index < 0)
        return false;
    return edit(tr("Delete key"), [&](KeyframeAnimation& a) { return a.deleteKey(std::size_t(index)); });
}

bool KeyframePanel::setInterpolation(int index, KeyInterpolation interpolation) {
    if (index < 0)
        return false;
    return edit(tr("Set key interpolation to %1").arg(keyInterpolationName(interpolation)),
                [&](KeyframeAnimation& a) { return a.setInterpolation(std::size_t(index), interpolation); });
}

namespace {

/// Deletes keys `indices` of `a`, the highest first, so each index still names the key it did.
Status deleteKeysAt(KeyframeAnimation& a, QList<int> indices) {
    std::sort(indices.begin(), indices.end(), std::greater<>());
    for (int i : indices)
        if (Status s = a.deleteKey(std::size_t(i)); !s)
            return s;
    return Status::success();
}

}  // namespace

bool KeyframePanel::moveKeys(const QList<int>& indices, double seconds, bool copy) {
    if (indices.isEmpty())
        return false;
    const QString text = copy ? tr("Copy %n key(s)", "", int(indices.size())) : tr("Move %n key(s)", "", int(indices.size()));
    return edit(text, [&](KeyframeAnimation& a) -> Status {
        std::vector<LatticeKey> moved;
        for (int i : indices) {
            if (i < 0 || std::size_t(i) >= a.keys().size())
                return Status::error("no key " + std::to_string(i));
            moved.push_back(a.keys()[std::size_t(i)]);
        }
        if (!copy) {  // all taken out first, so a key may land where another of the selection was
            if (Status s = deleteKeysAt(a, indices); !s)
                return s;
        }
        for (LatticeKey& key : moved) {
            key.seconds += seconds;
            if (auto inserted = a.insertKey(std::move(key)); !inserted)
                return Status::error(inserted.message());
        }
        return Status::success();
    });
}

bool KeyframePanel::deleteKeys(const QList<int>& indices) {
    if (indices.isEmpty())
        return false;
    return edit(tr("Delete %n key(s)", "", int(indices.size())),
                [&](KeyframeAnimation& a) { return deleteKeysAt(a, indices); });
}

bool KeyframePanel::setInterpolation(const QList<int>& indices, KeyInterpolation interpolation) {
    if (indices.isEmpty())
        return false;
    return edit(tr("Set %n key(s) to %1", "", int(indices.size())).arg(keyInterpolationName(interpolation)),
                [&](KeyframeAnimation& a) -> Status {
                    for (int i : indices)
                        if (Status s = a.setInterpolation(std::size_t(i), interpolation); !s)
                            return s;
                    return Status::success();
                });
}

void KeyframePanel::showKey(int index) {
    const std::vector<LatticeKey> k = keys();
    const SceneSimulation* sim = m_simulation->simulation();
    const NamedKeyframes* set = m_document->project().clips.findKeyframes(m_set);
    m_interpolation->setEnabled(index >= 0 && std::size_t(index) < k.size());
    if (index < 0 || std::size_t(index) >= k.size() || !sim || !set)
        return;
    showInterpolation(k[std::size_t(index)].interpolation);
    if (m_list->currentRow() != index) {
        const QSignalBlocker quiet(m_list);
        m_list->setCurrentRow(index);
    }
    setKeyTime(k[std::size_t(index)].seconds);
    std::vector<std::vector<Vec3>> pose;
    for (std::size_t i = 0; i < sim->objectCount(); ++i) {
        const std::vector<Vec3> rest = sim->object(i).lattice.restNodes();
        pose.push_back(i < set->objects.size() && !set->objects[i].keys().empty()
                           ? set->objects[i].pose(k[std::size_t(index)].seconds, rest)
                           : sim->simulator(i).state().position);
    }
    m_simulation->showPose(pose);
}

bool KeyframePanel::makeClip(bool goals) {
    const std::vector<LatticeKey> k = keys();
    if (k.size() < 2) {
        m_message->setText(tr("A clip needs at least two keys."));
        return false;
    }
    const ClipLibrary& library = m_document->project().clips;
    Clip clip;
    clip.source = ClipSource::Keyframes;
    clip.sourceName = m_set;
    clip.fps = m_document->scene().world.fps;
    clip.startSeconds = k.front().seconds;
    clip.frames = std::max(1, int(std::lround((k.back().seconds - k.front().seconds) * clip.fps)) + 1);
    if (goals) {
        clip.goals = GoalSettings{};
        clip.goals->weight = m_goalStrength->value();
    }
    int n = 1;
    while (library.findClip(m_set + " clip" + (n > 1 ? " " + std::to_string(n) : "")))
        ++n;
    clip.name = m_set + " clip" + (n > 1 ? " " + std::to_string(n) : "");
    ClipLibrary after = library;
    after.clips.push_back(clip);
    if (Status s = after.validate(m_document->scene()); !s) {
        m_message->setText(QString::fromStdString(s.message()));
        return false;
    }
    m_document->undoStack()->push(new ClipsEditCommand(m_document, library, std::move(after),
                                                       tr("Make clip %1").arg(QString::fromStdString(clip.name))));
    m_message->setText(tr("Added %1 to the clips (see the Timeline).").arg(QString::fromStdString(clip.name)));
    return true;
}

void KeyframePanel::refresh() {
    // The shown set is one of the project's, or "keys" in a project with none yet (the first key makes it): a
    // project opens on "keys" or its first set, and a set an undo took away gives way to them.
    const ClipLibrary& library = m_document->project().clips;
    if (!library.keyframes.empty() && !library.findKeyframes(m_set)) {
        m_set = library.findKeyframes(kDefaultSet) ? kDefaultSet : library.keyframes.front().name;
        emit keySetChanged();
    }
    refreshSets();
    const QSignalBlocker block(m_list);
    const int selected = m_list->currentRow();
    m_list->clear();
    // Frames, as the ruler counts them (the scene's rate), and how the key moves on: what fits a narrow dock.
    // The seconds and the nodes in its tooltip.
    const double fps = m_document->scene().world.fps;
    const std::vector<LatticeKey> all = keys();
    for (const LatticeKey& k : all) {
        m_list->addItem(tr("frame %1 · %2").arg(k.seconds * fps, 0, 'g', 6).arg(keyInterpolationLabel(k.interpolation).toLower()));
        m_list->item(m_list->count() - 1)->setToolTip(tr("%1 s · %n node(s)", nullptr, int(k.nodes.size())).arg(k.seconds, 0, 'f', 3));
    }
    if (selected >= 0 && selected < int(all.size())) {
        m_list->setCurrentRow(selected);
        showInterpolation(all[std::size_t(selected)].interpolation);
    }
    m_interpolation->setEnabled(m_list->currentRow() >= 0);
    showSeconds();  // the scene's rate may have changed
}

}  // namespace softtouch::ui

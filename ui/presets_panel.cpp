#include "ui/presets_panel.h"

#include "ui/edit_commands.h"
#include "ui/material_thumbnail.h"

#include <QMessageBox>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QVBoxLayout>

namespace softtouch::ui {

namespace {
/// Where a preset named `name` is saved in the user folder (lower case, runs of other characters as '-').
QString presetFileName(const QString& name) {
    QString file = name.toLower();
    file.replace(QRegularExpression("[^a-z0-9]+"), "-");
    return QDir(PresetsPanel::userFolder()).filePath(file + ".stpreset");
}
}  // namespace

PresetsPanel::PresetsPanel(Document* document, Viewport* viewport, QString shippedFolder, QWidget* parent)
    : QWidget(parent), m_document(document), m_viewport(viewport), m_shipped(std::move(shippedFolder)) {
    auto* layout = new QVBoxLayout(this);
    m_list = new QListWidget;
    m_list->setObjectName("presetList");
    layout->addWidget(m_list);
    auto* buttons = new QHBoxLayout;
    auto* apply = new QPushButton(tr("Apply"));
    apply->setToolTip(tr("Apply to the selected nodes, or to the whole lattice when none is selected."));
    auto* save = new QPushButton(tr("Save material…"));
    auto* saveSetupButton = new QPushButton(tr("Save setup…"));
    saveSetupButton->setToolTip(tr("Share the object's lattice, painted maps, anchors, drivers and swim clips."));
    auto* import = new QPushButton(tr("Import…"));
    buttons->addWidget(apply);
    buttons->addWidget(save);
    buttons->addWidget(saveSetupButton);
    buttons->addWidget(import);
    layout->addLayout(buttons);
    m_message = new QLabel;
    m_message->setWordWrap(true);
    layout->addWidget(m_message);
    connect(apply, &QPushButton::clicked, this, [this] { applyRow(m_list->currentRow()); });
    connect(m_list, &QListWidget::itemDoubleClicked, this, [this] { applyRow(m_list->currentRow()); });
    connect(save, &QPushButton::clicked, this, [this] {
        bool ok = false;
        const QString name = QInputDialog::getText(this, tr("Save Preset"), tr("Preset name:"), QLineEdit::Normal, QString(), &ok);
        if (ok && !name.trimmed().isEmpty()) {
            const Status s = saveCurrent(name.trimmed());
            m_message->setText(s ? tr("Saved to %1").arg(userFolder()) : QString::fromStdString(s.message()));
        }
    });
    connect(saveSetupButton, &QPushButton::clicked, this, [this] {
        bool ok = false;
        const QString name = QInputDialog::getText(this, tr("Save Setup"), tr("Setup name:"), QLineEdit::Normal, QString(), &ok);
        if (ok && !name.trimmed().isEmpty()) {
            const Status s = saveSetup(name.trimmed());
            m_message->setText(s ? tr("Saved to %1").arg(userFolder()) : QString::fromStdString(s.message()));
        }
    });
    connect(import, &QPushButton::clicked, this, [this] {
        const QString path = QFileDialog::getOpenFileName(this, tr("Import Preset"), QString(), tr("SoftTouch presets (*.stpreset)"));
        if (!path.isEmpty()) {
            const Status s = importFile(path);
            m_message->setText(s ? tr("Imported into %1").arg(userFolder()) : QString::fromStdString(s.message()));
        }
    });
    reload();
}

QString PresetsPanel::userFolder() {
    return QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + "/presets";
}

void PresetsPanel::reload() {
    m_presets.clear();
    m_list->clear();
    QStringList problems;
    m_list->setIconSize(QSize(56, 56));
    const QString shippedSetups = m_shipped.isEmpty() ? QString() : QDir(m_shipped + "/../setups").absolutePath();
    for (const QString& folder : {m_shipped, shippedSetups, userFolder()}) {
        if (folder.isEmpty())
            continue;
        const QDir dir(folder);
        for (const QString& file : dir.entryList({"*.stpreset"}, QDir::Files, QDir::Name)) {
            const QString path = dir.filePath(file);
            Entry entry{path, std::nullopt, std::nullopt};
            QString name, description;
            QImage thumbnail;
            if (auto material = io::loadMaterialPreset(path.toStdString())) {
                // The thumbnail: the preset on a 4x4x4 block held at its top.
                const LatticeShape shape;
                const Lattice block = Lattice::create(shape, OrientedBox{}).value();
                LatticeMaterial m = uniformMaterial(block, 0.02, 80.0, 0.9);
                if (io::applyMaterialPreset(material.value(), block, m))
                    thumbnail = materialThumbnail(shape, m);
                name = QString::fromStdString(material->name);
                description = QString::fromStdString(material->description);
                entry.material = std::move(material.value());
            } else if (auto setup = io::loadSetupPreset(path.toStdString())) {
                thumbnail = materialThumbnail(setup->shape, setup->material);
                name = tr("Setup: %1").arg(QString::fromStdString(setup->name));
                description = QString::fromStdString(setup->description);
                entry.setup = std::move(setup.value());
            } else {
                problems << QString::fromStdString(material.message());
                continue;
            }
            auto* item = new QListWidgetItem(QIcon(QPixmap::fromImage(thumbnail)), name, m_list);
            item->setToolTip(description + "\n" + path);
            m_presets.push_back(std::move(entry));
        }
    }
    m_message->setText(problems.join("\n"));
}

int PresetsPanel::count() const { return int(m_presets.size()); }

bool PresetsPanel::applyRow(int row) {
    const int object = m_viewport->currentObject();
    if (row < 0 || row >= count() || std::size_t(object) >= m_document->scene().objects.size())
        return false;
    const Entry& entry = m_presets[std::size_t(row)];
    if (entry.setup) {
        // A setup replaces the object's lattice setup, drivers and clips: one undo step for all of it.
        auto applied = io::applySetupPreset(*entry.setup, m_document->project(), std::size_t(object));
        if (!applied) {
            m_message->setText(QString::fromStdString(applied.message()));
            return false;
        }
        m_document->undoStack()->push(new ProjectEditCommand(m_document, m_document->project(), std::move(applied.value()),
                                                             tr("Apply setup %1").arg(QString::fromStdString(entry.setup->name))));
        m_message->setText(tr("Setup applied to the object (lattice, painted maps, anchors, drivers, clips)."));
        return true;
    }
    const SceneObject& o = m_document->scene().objects[std::size_t(object)];
    const io::MaterialPreset& preset = *entry.material;
    const std::vector<int> nodes(m_viewport->selection().begin(), m_viewport->selection().end());
    if (nodes.empty()) {
        // The whole lattice gets the preset's single values: a painted map is lost (undo brings it back,
        // but an animator who meant a few nodes should hear it before, not after).
        QStringList painted;
        const LatticeMaterial& m = o.material;
        for (const auto& [values, label] : {std::pair{&m.mass, tr("mass")}, {&m.stiffness, tr("stiffness")},
                                            {&m.damping, tr("spring damping")}, {&m.nodeDamping, tr("node damping")}}) {
            double lo = 1e300, hi = -1e300;
            for (std::size_t n = 0; n < values->size(); ++n)
                if (n >= m.isVoid.size() || !m.isVoid[n]) {
                    lo = std::min(lo, (*values)[n]);
                    hi = std::max(hi, (*values)[n]);
                }
            if (hi > lo * (1.0 + 1e-9) + 1e-300)
                painted << label;
        }
        if (!painted.isEmpty()) {
            const QString question = tr("No nodes are selected, so \"%1\" replaces the whole lattice, including its "
                                        "painted %2. Apply it anyway? (Select nodes to apply it to them only.)")
                                         .arg(QString::fromStdString(preset.name), painted.join(", "));
            const bool go = m_confirm ? m_confirm(question)
                                      : QMessageBox::question(this, tr("Replace painted values?"), question) == QMessageBox::Yes;
            if (!go) {
                m_message->setText(tr("Not applied: the painted values are kept."));
                return false;
            }
        }
    }
    LatticeMaterial after = o.material;
    if (Status s = io::applyMaterialPreset(preset, o.lattice, after, nodes); !s) {
        m_message->setText(QString::fromStdString(s.message()));
        return false;
    }
    const QString name = QString::fromStdString(preset.name);
    m_document->undoStack()->push(new MaterialEditCommand(
        m_document, object, o.material, std::move(after),
        nodes.empty() ? tr("Apply preset %1").arg(name) : tr("Apply preset %1 to %n node(s)", nullptr, int(nodes.size())).arg(name)));
    m_message->setText(nodes.empty() ? tr("Applied to the whole lattice.") : tr("Applied to the selected nodes."));
    return true;
}

Status PresetsPanel::saveCurrent(const QString& name) {
    const int object = m_viewport->currentObject();
    if (std::size_t(object) >= m_document->scene().objects.size())
        return Status::error("no object to take the material from");
    QDir().mkpath(userFolder());
    const QString path = presetFileName(name);
    const Status s = io::saveMaterialPreset(name.toStdString(), "Saved from " + m_document->displayName().toStdString(),
                                            m_document->scene().objects[std::size_t(object)].material, path.toStdString());
    if (s)
        reload();
    return s;
}

Status PresetsPanel::saveSetup(const QString& name) {
    auto setup = io::setupFromProject(m_document->project(), std::size_t(m_viewport->currentObject()));
    if (!setup)
        return Status::error(setup.message());
    setup->name = name.toStdString();
    setup->description = "Saved from " + m_document->displayName().toStdString();
    QDir().mkpath(userFolder());
    const Status s = io::saveSetupPreset(setup.value(), presetFileName(name).toStdString());
    if (s)
        reload();
    return s;
}

Status PresetsPanel::importFile(const QString& path) {
    // Valid as the kind it declares, or refused with the reason (file, JSON pointer, what was expected).
    const auto preset = io::loadPreset(path.toStdString());
    if (!preset)
        return preset.status();
    const std::string name = std::visit([](const auto& p) { return p.name; }, preset.value());
    QDir().mkpath(userFolder());
    const QString target = presetFileName(QString::fromStdString(name));
    QFile::remove(target + ".part");
    if (!QFile::copy(path, target + ".part") || (QFile::exists(target) && !QFile::remove(target)) ||
        !QFile::rename(target + ".part", target))
        return Status::error("cannot copy " + path.toStdString() + " into " + userFolder().toStdString());
    reload();
    return Status::success();
}

}  // namespace softtouch::ui

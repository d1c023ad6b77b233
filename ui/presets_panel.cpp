#include "ui/presets_panel.h"

#include "ui/edit_commands.h"

#include <QDir>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QVBoxLayout>

namespace softtouch::ui {

PresetsPanel::PresetsPanel(Document* document, Viewport* viewport, QString shippedFolder, QWidget* parent)
    : QWidget(parent), m_document(document), m_viewport(viewport), m_shipped(std::move(shippedFolder)) {
    auto* layout = new QVBoxLayout(this);
    m_list = new QListWidget;
    m_list->setObjectName("presetList");
    layout->addWidget(m_list);
    auto* buttons = new QHBoxLayout;
    auto* apply = new QPushButton(tr("Apply"));
    apply->setToolTip(tr("Apply to the selected nodes, or to the whole lattice when none is selected."));
    auto* save = new QPushButton(tr("Save current…"));
    buttons->addWidget(apply);
    buttons->addWidget(save);
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
    reload();
}

QString PresetsPanel::userFolder() {
    return QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + "/presets";
}

void PresetsPanel::reload() {
    m_presets.clear();
    m_list->clear();
    QStringList problems;
    for (const QString& folder : {m_shipped, userFolder()}) {
        if (folder.isEmpty())
            continue;
        const QDir dir(folder);
        for (const QString& file : dir.entryList({"*.stpreset"}, QDir::Files, QDir::Name)) {
            const QString path = dir.filePath(file);
            auto preset = io::loadMaterialPreset(path.toStdString());
            if (!preset) {
                problems << QString::fromStdString(preset.message());
                continue;
            }
            auto* item = new QListWidgetItem(QString::fromStdString(preset->name), m_list);
            item->setToolTip(QString::fromStdString(preset->description) + "\n" + path);
            m_presets.emplace_back(path, std::move(preset.value()));
        }
    }
    m_message->setText(problems.join("\n"));
}

int PresetsPanel::count() const { return int(m_presets.size()); }

bool PresetsPanel::applyRow(int row) {
    const int object = m_viewport->currentObject();
    if (row < 0 || row >= count() || std::size_t(object) >= m_document->scene().objects.size())
        return false;
    const SceneObject& o = m_document->scene().objects[std::size_t(object)];
    const io::MaterialPreset& preset = m_presets[std::size_t(row)].second;
    const std::vector<int> nodes(m_viewport->selection().begin(), m_viewport->selection().end());
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
    QString file = name.toLower();
    file.replace(QRegularExpression("[^a-z0-9]+"), "-");
    const QString path = QDir(userFolder()).filePath(file + ".stpreset");
    const Status s = io::saveMaterialPreset(name.toStdString(), "Saved from " + m_document->displayName().toStdString(),
                                            m_document->scene().objects[std::size_t(object)].material, path.toStdString());
    if (s)
        reload();
    return s;
}

}  // namespace softtouch::ui

#pragma once
/// The presets dock: the shipped material and setup presets and the user's own (in the user's data
/// folder), each with a thumbnail of how its material sags; a material applies to the selected nodes
/// or the whole lattice, a setup (lattice, painted maps, anchors, drivers, clips; remapped when the
/// resolutions differ) to the current object, each as one undo step; the current material is saved
/// as a new preset to share.

#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "ui/viewport.h"

#include <QWidget>

#include <functional>
#include <optional>

class QListWidget;
class QLabel;

namespace softtouch::ui {

/// Material presets.
class PresetsPanel : public QWidget {
    Q_OBJECT
public:
    /// `shippedFolder`: the bundled presets/materials folder.
    PresetsPanel(Document* document, Viewport* viewport, QString shippedFolder, QWidget* parent = nullptr);

    /// Where "Save as preset" writes: <AppDataLocation>/presets.
    static QString userFolder();
    /// Reloads both folders.
    void reload();
    /// Number of presets listed.
    int count() const;
    /// Applies preset `row` to the selection (or, with none selected, the whole lattice). Replacing a
    /// painted map on the whole lattice asks first (see setConfirm); false when refused or failed.
    bool applyRow(int row);
    /// Replaces the yes/no question asked before a preset overwrites painted values (a dialog by default;
    /// tests answer it themselves). It gets the question and returns true to go on.
    void setConfirm(std::function<bool(const QString&)> confirm) { m_confirm = std::move(confirm); }
    /// Saves the current object's material as a preset named `name` in the user folder.
    Status saveCurrent(const QString& name);
    /// Saves the current object's setup (lattice, painted maps, anchors, voids, drivers, drivers clips)
    /// as a setup preset named `name` in the user folder.
    Status saveSetup(const QString& name);
    /// Imports a preset file shared by someone else: validated (errors name the file and the JSON
    /// pointer), then copied into the user folder and listed.
    Status importFile(const QString& path);

private:
    Document* m_document;
    Viewport* m_viewport;
    QString m_shipped;
    QListWidget* m_list = nullptr;
    QLabel* m_message = nullptr;
    struct Entry {
        QString path;
        std::optional<io::MaterialPreset> material;
        std::optional<io::SetupPreset> setup;
    };
    std::vector<Entry> m_presets;
    std::function<bool(const QString&)> m_confirm;
};

}  // namespace softtouch::ui

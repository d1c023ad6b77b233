#pragma once
/// The timeline dock: record takes (everything that drives the body, per step, so a take replays
/// exactly), keep them in the project's clip library, make clips of them (range, fps, loop with
/// closure), scrub takes and clips, and export a clip with progress and cancel (the same io::bake the
/// CLI runs).

#include "core/clip.h"
#include "io/export_formats.h"
#include "render/camera.h"
#include "ui/simulation_controller.h"

#include <QWidget>

#include <functional>
#include <optional>

class QCheckBox;
class QLabel;
class QListWidget;
class QPushButton;
class QSlider;

namespace softtouch::ui {

/// Takes and clips of the open document.
class TimelinePanel : public QWidget {
    Q_OBJECT
public:
    TimelinePanel(Document* document, SimulationController* simulation, QWidget* parent = nullptr);

    /// Frames per second of the scrub slider for takes (the scene's clip rate).
    double fps() const;
    /// Number of takes (recorded sessions) in the project.
    int takeCount() const;

public slots:
    void toggleRecording();
    /// Shows take `index` at `frame` (replayed exactly).
    void scrubTo(int index, int frame);
    /// Shows clip `index` at `frame`.
    void showClipFrame(int index, int frame);
    /// Makes a clip of take `index` (all of it; a loop with a quarter-second closure when `loop`).
    bool makeClip(int index, bool loop);
    /// Asks for a file and exports clip `index` (or the drivers when < 0) with a progress dialog.
    void exportClip(int index);
    /// The export dialog's file types, one per export of the registry (io/export_formats.h), in its order:
    /// "Point cache (*.pc2)", …; a base-path export (vat, lattice) takes any name.
    static QStringList exportFilters();
    /// Exports without asking (tests, scripts); returns the message shown. The format comes from the
    /// path's extension (vat and lattice from a base name ending _vat / _lattice), or is given (the
    /// dialog's file type: compressed morphs and skinned glTF are .glb files too) with its default
    /// settings.
    Status exportClipTo(int index, const QString& path);
    Status exportClipTo(int index, const QString& path, const io::ExportFormat& format);
    /// Where the export and render dialogs start: beside the project (else the home folder), named after
    /// the project and the clip ("angelfish-swim-swim.pc2"), with extension `suffix`.
    QString suggestedOutputPath(int index, const QString& suffix) const;
    /// The status line's text (what the last export or render said).
    QString statusText() const;
    /// Asks for the size, the camera (the viewport's view, or the CLI's ¾ view) and a file, and renders
    /// clip `index` (or the drivers when < 0) as a video.
    void renderClip(int index);
    /// Renders without asking: .mp4, .gif or a folder ending in '/' for PNG frames, at width × height,
    /// from `camera` (none: the CLI's ¾ view of the rest bounds, render::videoCameraPlacement).
    Status renderClipTo(int index, const QString& path, int width = 960, int height = 540,
                        std::optional<render::CameraPlacement> camera = std::nullopt);
    /// Where Render video's "this view" stands (the main window passes the viewport's camera).
    void setViewCamera(std::function<render::CameraPlacement()> view) { m_viewCamera = std::move(view); }

private:
    void refreshLists();
    void selectTake(int row);
    void selectClip(int row);

    Document* m_document;
    SimulationController* m_simulation;
    QPushButton* m_record = nullptr;
    QListWidget* m_takes = nullptr;
    QListWidget* m_clips = nullptr;
    QCheckBox* m_loop = nullptr;
    QSlider* m_slider = nullptr;
    QLabel* m_time = nullptr;
    QLabel* m_baseRange = nullptr;  ///< Each object's base animation: take, range, loop (hidden when none).
    NodeFrames m_clipFrames;   ///< The selected clip, evaluated.
    std::function<render::CameraPlacement()> m_viewCamera;  ///< See setViewCamera().
    int m_clipShown = -1;      ///< Which clip m_clipFrames holds ...
    std::uint64_t m_clipRevision = 0;  ///< ... evaluated at this document revision.
};

}  // namespace softtouch::ui

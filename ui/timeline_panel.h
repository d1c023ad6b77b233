#pragma once
/// The timeline dock: record takes (everything that drives the body, per step, so a take replays
/// exactly), keep them in the project's clip library, make clips of them (an in/out range cut on the
/// frame ruler, fps, loop with closure), scrub and play takes and clips on the ruler (ui/frame_ruler.h,
/// which also shows the pose keys), rename, duplicate, retime and delete clips (one undo step each), and
/// export a clip with progress and cancel (the same io::bake the CLI runs).

#include "core/authoring/clip.h"
#include "io/export/export_formats.h"
#include "io/pipeline/clip_preview.h"
#include "render/camera.h"
#include "ui/simulation_controller.h"

#include <QWidget>

#include <functional>
#include <optional>

class QCheckBox;
class QLabel;
class QListWidget;
class QPushButton;
class QTimer;

namespace softtouch::ui {

class DopeSheet;
class FrameRuler;

/// How an export writes: which objects (a scene of several), and a GLB packed for shipping.
struct ExportChoices {
    std::vector<std::string> only;  ///< These objects only, by name (empty: every object).
    bool each = false;              ///< One file per object: the name + "-OBJECT" (io::perObjectPath()).
    bool groups = false;            ///< OBJ files name each object's faces with "g OBJECT".
    bool compress = false;          ///< A GLB packed for shipping (bake --compress; glb, pca and skin to a .glb).
    bool fittedBones = false;       ///< A skin export fits its own bones even where the mesh came with a rig (bake --rig fitted).
    bool preview = false;           ///< Then writes the clip's preview page beside it and opens it (softtouch-cli preview).
};

/// Takes and clips of the open document.
class TimelinePanel : public QWidget {
    Q_OBJECT
public:
    TimelinePanel(Document* document, SimulationController* simulation, QWidget* parent = nullptr);

    /// Frames per second of the scrub slider for takes (the scene's clip rate).
    double fps() const;
    /// Number of takes (recorded sessions) in the project.
    int takeCount() const;

signals:
    /// A clip of keyframe set `set` was chosen in the Clips list: the keys panel shows that set.
    void keyedClipChosen(const std::string& set);

public slots:
    void toggleRecording();
    /// Shows take `index` at `frame` (replayed exactly).
    void scrubTo(int index, int frame);
    /// Shows clip `index` at `frame`.
    void showClipFrame(int index, int frame);
    /// Makes a clip of take `index` (all of it; a loop with a quarter-second closure when `loop`).
    bool makeClip(int index, bool loop);
    /// Makes a clip of frames [in, out) of take `index` at the scene's fps.
    bool makeClip(int index, bool loop, int in, int out);
    /// Renames clip `index` (unique, not empty); one undo step. False, with the reason shown, when refused.
    bool renameClip(int index, const QString& name);
    /// Adds a copy of clip `index` named "<name> copy" (numbered when taken); one undo step.
    bool duplicateClip(int index);
    bool deleteClip(int index);
    /// Samples clip `index` at `fps` over the same seconds (frames and loop closure rescaled); one undo step.
    bool retimeClip(int index, double fps);
    /// Makes clip `index` a cycle (closed over a quarter second, at most half the clip) or a one-shot; one undo
    /// step. Any clip: cut from a take, keyed or of the drivers.
    bool setClipLoop(int index, bool loop);

    /// The frame ruler (keys shown on it are the keys panel's; the main window wires them).
    FrameRuler* ruler() const { return m_ruler; }
    /// The dope sheet under the ruler: every object's keys and the keyed clips (its key edits are the keys
    /// panel's, wired by the main window; showing a clip and its loop are this panel's).
    DopeSheet* dopeSheet() const { return m_dopeSheet; }
    /// Shows the scene's keys and keyed clips in the dope sheet again (the current object's keys editable).
    void refreshDopeSheet();
    /// Plays the selected clip or take from the playhead, in a loop when looping is on; again: pauses.
    void togglePlayback();
    bool isPlaying() const;
    /// A clip or take is on show: the one transport (Space, the arrows, Home) drives it, not the live simulation.
    bool showsClipOrTake() const;
    /// What is on show, as the status line names it ("clip swim", "take 1"); empty when nothing is.
    QString shownName() const;
    /// Shows the first frame (`last` false) or the last one of the clip or take on show.
    void goToEnd(bool last);
    /// Moves playback on by `seconds` of the clip's time (what a timer tick does; tests call it directly).
    void advancePlayback(double seconds);
    /// One frame on (+1) or back (-1), wrapping in a loop.
    void stepFrame(int delta);
    /// Asks for a file and exports clip `index` (or the drivers when < 0) with a progress dialog.
    void exportClip(int index);
    /// Writes the preview page of the export at `path` beside it and opens it in the web browser.
    void previewExport(const QString& path);
    /// The export dialog's file types, one per export of the registry (io/export/export_formats.h), in its order:
    /// "Point cache (*.pc2)", …; a base-path export (vat, lattice) takes any name.
    static QStringList exportFilters();
    /// Exports without asking (tests, scripts); returns the message shown. The format comes from the
    /// path's extension (vat and lattice from a base name ending _vat / _lattice), or is given (the
    /// dialog's file type: compressed morphs and skinned glTF are .glb files too) with its default
    /// settings, for the objects the choices name and packed when they say so.
    Status exportClipTo(int index, const QString& path);
    Status exportClipTo(int index, const QString& path, const io::ExportFormat& format);
    Status exportClipTo(int index, const QString& path, const io::ExportFormat& format, const ExportChoices& choices);
    /// Where the preview page's player and shaders are (softtouch-cli preview's); with none, Export… offers no
    /// preview page.
    void setPreviewAssets(io::PreviewAssets assets) { m_previewAssets = std::move(assets); }
    /// The object "only the current object" exports (the main window passes the viewport's).
    void setCurrentObjectSource(std::function<int()> current) { m_currentObject = std::move(current); }
    /// Where the dope sheet learns which keyframe set it shows (the keys panel's; "keys" without one).
    void setKeySetSource(std::function<std::string()> set) { m_keySet = std::move(set); }
    /// The name of the clip Export… writes now: the selected clip's, or "" (the drivers) when none is selected.
    std::string exportedClipName() const;
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

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    void refreshLists();
    void selectTake(int row);
    void selectClip(int row);
    /// The clips cut from the take on show and the base animations, as ranges on the ruler.
    void showRanges();
    /// Shows the playhead's frame of the selected clip or take.
    void showFrame(int frame);
    /// Applies `change` to a copy of the clip library as one undo step named `text`; false, with the reason
    /// shown, when the result does not validate.
    bool editClips(const QString& text, const std::function<Status(ClipLibrary&)>& change);
    /// The Loop box shows the selected clip's loop (and sets it), or with no clip selected what "Clip from take"
    /// will cut.
    void showLoopState();
    /// No clip or take on show (deselected, or the one on show deleted): playback stops, the line gives its hint
    /// and the ruler spans the scene's frames.
    void showNothing();
    void showClipMenu(const QPoint& pos);
    /// Asks for clip `index`'s new name (double-click, the list's menu) and renames it.
    void askToRenameClip(int index);

    Document* m_document;
    SimulationController* m_simulation;
    QPushButton* m_record = nullptr;
    QListWidget* m_takes = nullptr;
    QListWidget* m_clips = nullptr;
    bool m_loopForCut = false;  ///< The Loop box's choice for "Clip from take" (see showLoopState()).
    QCheckBox* m_loop = nullptr;
    FrameRuler* m_ruler = nullptr;
    DopeSheet* m_dopeSheet = nullptr;
    QPushButton* m_play = nullptr;
    QCheckBox* m_loopPlayback = nullptr;
    QTimer* m_playTimer = nullptr;
    double m_playPosition = 0.0;   ///< Playback's place, frames (fractional between ticks).
    QLabel* m_time = nullptr;
    io::PreviewAssets m_previewAssets;
    QLabel* m_baseRange = nullptr;  ///< Each object's base animation: take, range, loop (hidden when none).
    NodeFrames m_clipFrames;   ///< The selected clip, evaluated.
    std::function<render::CameraPlacement()> m_viewCamera;  ///< See setViewCamera().
    std::function<int()> m_currentObject;                   ///< See setCurrentObjectSource().
    std::function<std::string()> m_keySet;                  ///< See setKeySetSource().
    int m_clipShown = -1;      ///< Which clip m_clipFrames holds ...
    std::uint64_t m_clipRevision = 0;  ///< ... evaluated at this document revision.
};

}  // namespace softtouch::ui

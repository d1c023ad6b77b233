#pragma once
/// The editor's document: one project (scene + where it came from), its undo stack and the typed
/// change signals the views listen to. Every change to the scene goes through an undo command
/// (edit_commands.h) that calls the set*() functions here; views never change the scene directly.

#include "core/scene/scene.h"
#include "io/documents/project_file.h"
#include "io/import/animation_import.h"

#include <QObject>
#include <QString>
#include <QUndoStack>

#include <cstdint>

namespace softtouch::ui {

/// One open project.
class Document : public QObject {
    Q_OBJECT
public:
    explicit Document(QObject* parent = nullptr);
    /// Silences the undo stack first: its teardown is not the user going back to a clean state
    /// (listeners such as the autosave would take it for one).
    ~Document() override;

    /// Loads a project; on failure the document is left as it was and the message names the file,
    /// the JSON pointer and what was expected.
    Status open(const QString& path);
    /// Writes the project atomically to `path` (the previous file survives any failure) and makes
    /// it the document's path; marks the document clean.
    Status saveAs(const QString& path);
    /// Writes the project to a copy without changing the document's path or clean state (autosave).
    Status saveCopy(const QString& path) const;
    /// Makes `path` the document's file without writing it (recovering an autosave of that file): mesh
    /// references are rebased onto it and the document counts as modified. Empty: not yet saved.
    void adoptPath(const QString& path);
    /// Replaces the scene by a single object made from a mesh file (core newScene()): a 4x4x4 Bezier
    /// lattice fitted to it, the default Continuum material and the new-scene integrator (Verlet unless
    /// the body is too stiff for it at 240 steps/s), written explicitly when saved.
    Status importMesh(const QString& path);
    /// Starts an untitled, empty scene (File ▸ New): no objects yet, the world a new scene has; nothing to undo.
    void newEmptyScene();
    /// Adds an object (one undo step) made from a mesh file with its own animation (io/import/animation_import.h):
    /// the take and range of `request` (by default the file's first take, whole, looping, sampled at 120 per
    /// second), on a fitted 4x4x4 Bezier lattice with the default material and goal weight ½ on every node
    /// (core/animation/base_motion.h). The scene's other objects stay. `report` receives what the import found (take,
    /// length, vertices, unit).
    Status importAnimatedMesh(const QString& path, const io::AnimationRequest& request = {}, QString* report = nullptr);

    /// Makes `pose` (object i's lattice nodes) its rest shape as one undo step (core/scene/rest_shape.h): the mesh
    /// takes the posed shape, the lattice returns to rest around it (its box grown where the mesh left it),
    /// and the project keeps the edit to replay on load. Fails, changing nothing, for an object on its own
    /// animation or a pose of another node count.
    Status applyRestShape(int object, const std::vector<Vec3>& pose);

    /// Adds an object made from a mesh file (one undo step) on a fitted 4x4x4 Bezier lattice with the default
    /// material, as a new scene's (core newScene()), where the file puts it, or beside the scene's objects
    /// along x when it would overlap them (its "position" in the project). Its name is the file's, numbered
    /// when taken. Takes and keyframe sets gain it at rest (core/authoring/clip.h withObjectInserted()).
    Status addMesh(const QString& path);
    /// Adds a copy of object i right after it (one undo step), beside it along x, a fifth of its box apart:
    /// mesh, lattice, material, drivers, rest-shape edits and base animation; no keys of its own.
    Status duplicateObject(int object);
    /// Removes object i (one undo step) and its state, drags and keys from every take and keyframe set;
    /// refused for the last object.
    Status deleteObject(int object);

    const io::Project& project() const { return m_project; }
    const Scene& scene() const { return m_project.scene; }
    /// Path of the project file; empty for an imported mesh not yet saved.
    QString filePath() const;
    /// Name shown in the title bar.
    QString displayName() const;
    QUndoStack* undoStack() { return &m_undo; }
    /// True when the scene differs from what was last opened or saved.
    bool isModified() const { return !m_undo.isClean(); }
    /// Counts every change of the scene or clip library (each change signal below, undo and redo
    /// included): what is computed from them (a clip's evaluated frames) is keyed on it.
    std::uint64_t revision() const { return m_revision; }

    // Edit primitives: only undo commands call these.
    /// Replaces object i's material (same node count); emits materialChanged.
    void setMaterial(int object, const LatticeMaterial& material);
    /// Replaces the world settings; emits worldChanged.
    void setWorld(const WorldSettings& world);
    /// Replaces the whole scene and clip library, keeping the file path and the undo history (a
    /// setup preset applied to an object); emits sceneReplaced.
    void setProjectContent(const io::Project& project);
    /// Replaces the clip library (takes, clips, keyframe sets); emits clipsChanged.
    void setClips(const ClipLibrary& clips);
    /// Replaces object i's lattice and material together (resolution or box change); emits latticeChanged.
    void setLattice(int object, const Lattice& lattice, const LatticeMaterial& material);

signals:
    /// Object i's painted values, anchors or voids changed.
    void materialChanged(int object);
    /// Object i's lattice (and so its node count) changed.
    void latticeChanged(int object);
    /// The clip library (takes, clips) changed.
    void clipsChanged();
    /// Gravity, planes or simulation settings changed.
    void worldChanged();
    /// A different scene was opened or imported: rebuild everything.
    void sceneReplaced();
    /// The file path changed (open, save as).
    void filePathChanged(const QString& path);

private:
    void replaceProject(io::Project project);
    /// The scene core's newScene() makes of a mesh file (Import Mesh's; Add Mesh takes its object); errors
    /// name the file.
    static Result<Scene> sceneFromMeshFile(const QString& path);
    /// Moves `object` (mesh, lattice, base animation) along x beside the scene's objects when it would overlap
    /// them, a fifth of its width apart; returns the move (the project keeps it as the object's "position").
    Vec3 placeBeside(SceneObject& object) const;
    /// Inserts `object` at `index` with what the project keeps of it, as one undo step named `text`.
    Status insertObject(SceneObject object, std::string meshReference, Vec3 meshOffset, std::vector<RestShapeEdit> edits,
                        std::size_t index, const QString& text);

    io::Project m_project;
    QUndoStack m_undo;
    std::uint64_t m_revision = 0;
};

}  // namespace softtouch::ui

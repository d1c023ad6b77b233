#pragma once
/// Undo commands: every change to a document is one of these. Each stores the value before and
/// after (a lattice's material is a few kilobytes, so whole copies keep the commands trivially
/// correct), and edits that share a merge key collapse into one undo step: one brush stroke, or a
/// run of edits of the same property.

#include "ui/document.h"
#include "ui/simulation_controller.h"

#include <QUndoCommand>

namespace softtouch::ui {

/// Merge keys for property edits (brush strokes use their own increasing stroke numbers above these).
enum MergeKey : int {
    kNoMerge = -1,
    kMergeStiffness = 1,
    kMergeDamping,
    kMergeMass,
    kMergeAnisotropy,
    kMergeFrequency,
    kMergeGravity,
    kMergeTimeStep,
    kMergeStrainLimits,
    kMergeVolume,
    kFirstStrokeKey = 1000,  ///< Brush strokes: one key per stroke.
};

/// Replaces an object's material (painted values, anchors, voids, global material settings).
class MaterialEditCommand : public QUndoCommand {
public:
    MaterialEditCommand(Document* document, int object, LatticeMaterial before, LatticeMaterial after,
                        const QString& text, int mergeKey = kNoMerge);
    void undo() override;
    void redo() override;
    int id() const override { return m_mergeKey == kNoMerge ? -1 : 1; }
    bool mergeWith(const QUndoCommand* other) override;

private:
    Document* m_document;
    int m_object;
    LatticeMaterial m_before;
    LatticeMaterial m_after;
    int m_mergeKey;
};

/// Replaces the world settings (gravity, planes, integrator, time step).
class WorldEditCommand : public QUndoCommand {
public:
    WorldEditCommand(Document* document, WorldSettings before, WorldSettings after, const QString& text,
                     int mergeKey = kNoMerge);
    void undo() override;
    void redo() override;
    int id() const override { return m_mergeKey == kNoMerge ? -1 : 2; }
    bool mergeWith(const QUndoCommand* other) override;

private:
    Document* m_document;
    WorldSettings m_before;
    WorldSettings m_after;
    int m_mergeKey;
};

/// Replaces the clip library (a new take, a clip made from it, a deleted clip).
class ClipsEditCommand : public QUndoCommand {
public:
    ClipsEditCommand(Document* document, ClipLibrary before, ClipLibrary after, const QString& text);
    void undo() override;
    void redo() override;

private:
    Document* m_document;
    ClipLibrary m_before;
    ClipLibrary m_after;
};

/// Replaces the scene and clip library as a whole (a setup preset applied to an object).
class ProjectEditCommand : public QUndoCommand {
public:
    ProjectEditCommand(Document* document, io::Project before, io::Project after, const QString& text);
    void undo() override;
    void redo() override;

private:
    Document* m_document;
    io::Project m_before;
    io::Project m_after;
};

/// Replaces an object's lattice together with its material (resolution, kind or box changes).
class LatticeEditCommand : public QUndoCommand {
public:
    LatticeEditCommand(Document* document, int object, Lattice before, LatticeMaterial beforeMaterial,
                       Lattice after, LatticeMaterial afterMaterial, const QString& text, int mergeKey = kNoMerge);
    void undo() override;
    void redo() override;
    int id() const override { return m_mergeKey == kNoMerge ? -1 : 3; }
    bool mergeWith(const QUndoCommand* other) override;

private:
    Document* m_document;
    int m_object;
    Lattice m_before;
    LatticeMaterial m_beforeMaterial;
    Lattice m_after;
    LatticeMaterial m_afterMaterial;
    int m_mergeKey;
};

/// Poses an object's lattice nodes (G/R/S in the viewport, ui/node_transform.h). The pose is the running
/// simulation's state, not the document's, but it is the user's work like any edit, so Ctrl+Z takes it back;
/// a pose whose lattice has since been replaced (another node count) is left alone.
class PoseEditCommand : public QUndoCommand {
public:
    PoseEditCommand(SimulationController* simulation, int object, std::vector<Vec3> before, std::vector<Vec3> after,
                    const QString& text);
    void undo() override;
    void redo() override;

private:
    SimulationController* m_simulation;
    int m_object;
    std::vector<Vec3> m_before;
    std::vector<Vec3> m_after;
};

}  // namespace softtouch::ui

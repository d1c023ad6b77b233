#include "ui/edit_commands.h"

namespace softtouch::ui {

MaterialEditCommand::MaterialEditCommand(Document* document, int object, LatticeMaterial before,
                                         LatticeMaterial after, const QString& text, int mergeKey)
    : QUndoCommand(text),
      m_document(document),
      m_object(object),
      m_before(std::move(before)),
      m_after(std::move(after)),
      m_mergeKey(mergeKey) {}

void MaterialEditCommand::undo() { m_document->setMaterial(m_object, m_before); }
void MaterialEditCommand::redo() { m_document->setMaterial(m_object, m_after); }

bool MaterialEditCommand::mergeWith(const QUndoCommand* other) {
    const auto* o = static_cast<const MaterialEditCommand*>(other);
    if (o->m_mergeKey != m_mergeKey || o->m_object != m_object)
        return false;
    m_after = o->m_after;
    return true;
}

WorldEditCommand::WorldEditCommand(Document* document, WorldSettings before, WorldSettings after,
                                   const QString& text, int mergeKey)
    : QUndoCommand(text),
      m_document(document),
      m_before(std::move(before)),
      m_after(std::move(after)),
      m_mergeKey(mergeKey) {}

void WorldEditCommand::undo() { m_document->setWorld(m_before); }
void WorldEditCommand::redo() { m_document->setWorld(m_after); }

bool WorldEditCommand::mergeWith(const QUndoCommand* other) {
    const auto* o = static_cast<const WorldEditCommand*>(other);
    if (o->m_mergeKey != m_mergeKey)
        return false;
    m_after = o->m_after;
    return true;
}

ClipsEditCommand::ClipsEditCommand(Document* document, ClipLibrary before, ClipLibrary after, const QString& text)
    : QUndoCommand(text), m_document(document), m_before(std::move(before)), m_after(std::move(after)) {}

void ClipsEditCommand::undo() { m_document->setClips(m_before); }
void ClipsEditCommand::redo() { m_document->setClips(m_after); }

ProjectEditCommand::ProjectEditCommand(Document* document, io::Project before, io::Project after, const QString& text)
    : QUndoCommand(text), m_document(document), m_before(std::move(before)), m_after(std::move(after)) {}

void ProjectEditCommand::undo() { m_document->setProjectContent(m_before); }
void ProjectEditCommand::redo() { m_document->setProjectContent(m_after); }

LatticeEditCommand::LatticeEditCommand(Document* document, int object, Lattice before,
                                       LatticeMaterial beforeMaterial, Lattice after,
                                       LatticeMaterial afterMaterial, const QString& text, int mergeKey)
    : QUndoCommand(text),
      m_document(document),
      m_object(object),
      m_before(std::move(before)),
      m_beforeMaterial(std::move(beforeMaterial)),
      m_after(std::move(after)),
      m_afterMaterial(std::move(afterMaterial)),
      m_mergeKey(mergeKey) {}

void LatticeEditCommand::undo() { m_document->setLattice(m_object, m_before, m_beforeMaterial); }
void LatticeEditCommand::redo() { m_document->setLattice(m_object, m_after, m_afterMaterial); }

bool LatticeEditCommand::mergeWith(const QUndoCommand* other) {
    const auto* o = static_cast<const LatticeEditCommand*>(other);
    if (o->m_mergeKey != m_mergeKey || o->m_object != m_object)
        return false;
    m_after = o->m_after;
    m_afterMaterial = o->m_afterMaterial;
    return true;
}

PoseEditCommand::PoseEditCommand(SimulationController* simulation, int object, std::vector<Vec3> before,
                                 std::vector<Vec3> after, const QString& text)
    : QUndoCommand(text), m_simulation(simulation), m_object(object), m_before(std::move(before)), m_after(std::move(after)) {}

void PoseEditCommand::undo() { m_simulation->setObjectPose(m_object, m_before); }
void PoseEditCommand::redo() { m_simulation->setObjectPose(m_object, m_after); }

}  // namespace softtouch::ui

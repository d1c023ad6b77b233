// The document's object edits: add a mesh as a new object, duplicate one, delete one. Each is one undo
// step over the whole project, and keeps the clip library fitting the scene (core/authoring/clip.h: takes and
// keyframe sets gain or lose the object).

#include "ui/document.h"

#include "ui/edit_commands.h"

#include <QFileInfo>

#include <set>

namespace softtouch::ui {

namespace {

/// `name`, or "name 2", "name 3", … when the scene has it already.
std::string uniqueName(const Scene& scene, const std::string& name) {
    std::set<std::string> names;
    for (const SceneObject& o : scene.objects)
        names.insert(o.name);
    std::string out = name;
    for (int k = 2; names.count(out); ++k)
        out = name + " " + std::to_string(k);
    return out;
}

/// Moves an object by `offset`: its mesh, lattice box and (a copy of) its base animation.
void moveObject(SceneObject& o, const Vec3& offset) {
    Mesh mesh = *o.mesh;  // a new mesh: the scene's other copies (undo) keep theirs
    for (Vec3f& p : mesh.positions)
        p += offset.cast<float>();
    o.mesh = std::move(mesh);
    OrientedBox box = o.lattice.box();
    box.origin += offset;
    o.lattice = Lattice::create(o.lattice.shape(), box).value();  // the same shape over a moved valid box
    if (o.baseAnimation) {
        auto moved = std::make_shared<BaseAnimation>(*o.baseAnimation);
        for (auto& sample : moved->samples)
            for (Vec3f& p : sample)
                p += offset.cast<float>();
        o.baseAnimation = std::move(moved);
    }
}

}  // namespace

Status Document::insertObject(SceneObject object, std::string meshReference, Vec3 meshOffset,
                              std::vector<RestShapeEdit> edits, std::size_t index, const QString& text) {
    io::Project after = m_project;
    const std::size_t count = after.scene.objects.size();
    index = std::min(index, count);
    object.name = uniqueName(after.scene, object.name);
    const std::vector<Vec3> rest = object.lattice.restNodes();
    after.meshReferences.resize(count);
    after.meshOffsets.resize(count, Vec3::Zero());
    after.restShapeEdits.resize(count);
    after.scene.objects.insert(after.scene.objects.begin() + std::ptrdiff_t(index), std::move(object));
    after.meshReferences.insert(after.meshReferences.begin() + std::ptrdiff_t(index), std::move(meshReference));
    after.meshOffsets.insert(after.meshOffsets.begin() + std::ptrdiff_t(index), meshOffset);
    after.restShapeEdits.insert(after.restShapeEdits.begin() + std::ptrdiff_t(index), std::move(edits));
    after.clips = withObjectInserted(after.clips, index, rest);
    if (auto check = SceneSimulation::create(after.scene); !check)
        return Status::error(check.message());
    if (Status s = after.clips.validate(after.scene); !s)
        return s;
    m_undo.push(new ProjectEditCommand(this, m_project, std::move(after), text));
    return Status::success();
}

Vec3 Document::placeBeside(SceneObject& object) const {
    Vec3 offset = Vec3::Zero();
    if (!m_project.scene.objects.empty()) {
        const Bounds scene = restBounds(m_project.scene);
        const Bounds added = object.mesh->bounds();
        if ((added.min.array() <= scene.max.array()).all() && (added.max.array() >= scene.min.array()).all())
            offset.x() = scene.max.x() - added.min.x() + 0.2 * (added.max.x() - added.min.x());
    }
    moveObject(object, offset);
    return offset;
}

Status Document::addMesh(const QString& path) {
    auto made = sceneFromMeshFile(path);  // the object a new scene would make of it
    if (!made)
        return made.status();
    // Where the file puts it, unless that overlaps the scene's objects: then beside them along x, a fifth of
    // its width apart (kept as its "position", so the project reopens the same).
    SceneObject object = std::move(made->objects.front());
    const Vec3 offset = placeBeside(object);
    const QString name = QFileInfo(path).fileName();
    if (m_project.scene.objects.empty())  // the first body of an empty scene: the step a new scene of it would take
        m_project.scene.world.simulation = made->world.simulation;
    return insertObject(std::move(object), std::filesystem::absolute(path.toStdString()).string(), offset, {},
                        m_project.scene.objects.size(), tr("Add mesh %1").arg(name));
}

Status Document::duplicateObject(int object) {
    if (object < 0 || std::size_t(object) >= m_project.scene.objects.size())
        return Status::error("no object " + std::to_string(object));
    const auto i = std::size_t(object);
    SceneObject copy = m_project.scene.objects[i];
    // Beside the original along x, a fifth of its box apart, so both can be seen and picked.
    const OrientedBox& box = copy.lattice.box();
    const Vec3 offset = Vec3::UnitX() * 1.2 * (box.axes.cwiseAbs() * box.size).x();
    moveObject(copy, offset);
    std::vector<RestShapeEdit> edits = i < m_project.restShapeEdits.size() ? m_project.restShapeEdits[i] : std::vector<RestShapeEdit>{};
    for (RestShapeEdit& e : edits) {  // they replay in scene coordinates: moved with the object
        e.box.origin += offset;
        for (Vec3& x : e.nodes)
            x += offset;
    }
    const Vec3 meshOffset = (i < m_project.meshOffsets.size() ? m_project.meshOffsets[i] : Vec3::Zero()) + offset;
    const std::string reference = i < m_project.meshReferences.size() ? m_project.meshReferences[i] : std::string();
    const QString name = QString::fromStdString(copy.name);
    return insertObject(std::move(copy), reference, meshOffset, std::move(edits), i + 1, tr("Duplicate %1").arg(name));
}

Status Document::deleteObject(int object) {
    if (object < 0 || std::size_t(object) >= m_project.scene.objects.size())
        return Status::error("no object " + std::to_string(object));
    const auto i = std::size_t(object);
    io::Project after = m_project;
    const QString name = QString::fromStdString(after.scene.objects[i].name);
    after.scene.objects.erase(after.scene.objects.begin() + std::ptrdiff_t(i));
    if (i < after.meshReferences.size())
        after.meshReferences.erase(after.meshReferences.begin() + std::ptrdiff_t(i));
    if (i < after.meshOffsets.size())
        after.meshOffsets.erase(after.meshOffsets.begin() + std::ptrdiff_t(i));
    if (i < after.restShapeEdits.size())
        after.restShapeEdits.erase(after.restShapeEdits.begin() + std::ptrdiff_t(i));
    after.clips = withObjectRemoved(after.clips, i);
    m_undo.push(new ProjectEditCommand(this, m_project, std::move(after), tr("Delete %1").arg(name)));
    return Status::success();
}

}  // namespace softtouch::ui

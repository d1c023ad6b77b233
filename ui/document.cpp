#include "ui/document.h"

#include "io/import/animation_import.h"
#include "io/import/mesh_import.h"
#include "ui/edit_commands.h"

#include <QFileInfo>

#include <set>

namespace softtouch::ui {

Document::Document(QObject* parent) : QObject(parent) {
    // First among each signal's receivers, so every listener already sees the new revision.
    const auto bump = [this] { ++m_revision; };
    connect(this, &Document::materialChanged, this, bump);
    connect(this, &Document::latticeChanged, this, bump);
    connect(this, &Document::clipsChanged, this, bump);
    connect(this, &Document::worldChanged, this, bump);
    connect(this, &Document::sceneReplaced, this, bump);
}

Document::~Document() { m_undo.blockSignals(true); }

Status Document::open(const QString& path) {
    auto loaded = io::loadProject(path.toStdString());
    if (!loaded)
        return Status::error(loaded.message());
    replaceProject(std::move(loaded.value()));
    return Status::success();
}

Status Document::saveAs(const QString& path) {
    if (Status s = io::saveProject(m_project, path.toStdString()); !s)
        return s;
    namespace fs = std::filesystem;
    const fs::path target = fs::absolute(path.toStdString());
    const bool moved = m_project.path != target;
    // Mesh references are relative to the project file: rebase them the way saveProject wrote them.
    if (!m_project.path.empty()) {
        const fs::path from = fs::absolute(m_project.path).parent_path();
        for (std::string& ref : m_project.meshReferences) {
            if (!ref.empty() && !fs::path(ref).is_absolute())
                ref = (from / ref).lexically_normal().lexically_relative(target.parent_path()).generic_string();
        }
    }
    m_project.path = target;
    m_undo.setClean();
    if (moved)
        emit filePathChanged(path);
    return Status::success();
}

void Document::adoptPath(const QString& path) {
    namespace fs = std::filesystem;
    const fs::path from = fs::absolute(m_project.path).parent_path();
    const fs::path target = path.isEmpty() ? fs::path() : fs::absolute(path.toStdString());
    for (std::string& ref : m_project.meshReferences) {
        if (ref.empty() || fs::path(ref).is_absolute())
            continue;
        const fs::path resolved = (from / ref).lexically_normal();
        ref = target.empty() ? resolved.string() : resolved.lexically_relative(target.parent_path()).generic_string();
    }
    m_project.path = target;
    m_undo.resetClean();
    emit filePathChanged(path);
}

Status Document::saveCopy(const QString& path) const {
    return io::saveProject(m_project, path.toStdString());
}

Result<Scene> Document::sceneFromMeshFile(const QString& path) {
    auto mesh = io::importMesh(path.toStdString());
    if (!mesh)
        return Status::error(mesh.message());
    // A Continuum fish body on a fitted 4x4x4 lattice, on the integrator that keeps its wobble.
    auto scene = newScene(QFileInfo(path).completeBaseName().toStdString(), std::move(mesh.value()));
    if (!scene)
        return Status::error(path.toStdString() + ": " + scene.message());
    return scene;
}

Status Document::importMesh(const QString& path) {
    auto scene = sceneFromMeshFile(path);
    if (!scene)
        return scene.status();
    io::Project project;
    project.scene = std::move(scene.value());
    project.meshReferences.push_back(std::filesystem::absolute(path.toStdString()).string());
    replaceProject(std::move(project));
    return Status::success();
}

void Document::newEmptyScene() {
    io::Project project;
    project.scene.world.simulation = newSceneSimulation(project.scene);
    replaceProject(std::move(project));
}

Status Document::importAnimatedMesh(const QString& path, const io::AnimationRequest& request, QString* report) {
    auto animated = io::importAnimatedMesh(path.toStdString(), request);
    if (!animated)
        return Status::error(animated.message());
    // The object as a new scene would make it, moved into this scene beside the others.
    auto made = newScene(QFileInfo(path).completeBaseName().toStdString(), std::move(animated->mesh));
    if (!made)
        return Status::error(path.toStdString() + ": " + made.message());
    SceneObject object = std::move(made->objects.front());
    object.baseAnimation = std::make_shared<BaseAnimation>(std::move(animated->animation));
    object.material.goalWeight.assign(object.material.mass.size(), 0.5);
    if (m_project.scene.objects.empty())
        m_project.scene.world.simulation = made->world.simulation;
    const std::size_t index = m_project.scene.objects.size();
    const Vec3 offset = placeBeside(object);  // not inside the fish already there
    if (Status s = insertObject(std::move(object), std::filesystem::absolute(path.toStdString()).string(), offset, {},
                                index, tr("Import animated mesh %1").arg(QFileInfo(path).fileName()));
        !s)
        return Status::error(path.toStdString() + ": " + s.message());
    if (report) {
        const SceneObject& added = m_project.scene.objects[index];
        *report = tr("%1: take \"%2\", %3 s, %4 vertices, %5")
                      .arg(QString::fromStdString(added.name), QString::fromStdString(added.baseAnimation->take))
                      .arg(added.baseAnimation->duration())
                      .arg(added.mesh->positions.size())
                      .arg(QString::fromStdString(animated->unit));
    }
    return Status::success();
}

Status Document::applyRestShape(int object, const std::vector<Vec3>& pose) {
    if (object < 0 || std::size_t(object) >= m_project.scene.objects.size())
        return Status::error("no object " + std::to_string(object));
    auto change = withRestShape(m_project.scene.objects[std::size_t(object)], pose);
    if (!change)
        return Status::error(change.message());
    io::Project after = m_project;
    after.scene.objects[std::size_t(object)] = std::move(change->object);
    after.restShapeEdits.resize(after.scene.objects.size());
    after.restShapeEdits[std::size_t(object)].push_back(std::move(change->edit));
    if (auto check = SceneSimulation::create(after.scene); !check)
        return Status::error(check.message());
    m_undo.push(new ProjectEditCommand(this, m_project, std::move(after),
                                       tr("Pose as rest shape of %1").arg(QString::fromStdString(m_project.scene.objects[std::size_t(object)].name))));
    return Status::success();
}

QString Document::filePath() const {
    return QString::fromStdString(m_project.path.string());
}

QString Document::displayName() const {
    if (!m_project.path.empty())
        return QFileInfo(filePath()).fileName();
    if (!m_project.scene.objects.empty())
        return QString::fromStdString(m_project.scene.objects.front().name) + " (unsaved)";
    return tr("untitled");
}

void Document::setMaterial(int object, const LatticeMaterial& material) {
    m_project.scene.objects[std::size_t(object)].material = material;
    emit materialChanged(object);
}

void Document::setWorld(const WorldSettings& world) {
    m_project.scene.world = world;
    emit worldChanged();
}

void Document::setProjectContent(const io::Project& project) {
    m_project.scene = project.scene;
    m_project.meshReferences = project.meshReferences;
    m_project.meshOffsets = project.meshOffsets;
    m_project.restShapeEdits = project.restShapeEdits;
    m_project.clips = project.clips;
    emit sceneReplaced();
}

void Document::setClips(const ClipLibrary& clips) {
    m_project.clips = clips;
    emit clipsChanged();
}

void Document::setLattice(int object, const Lattice& lattice, const LatticeMaterial& material) {
    SceneObject& o = m_project.scene.objects[std::size_t(object)];
    o.lattice = lattice;
    o.material = material;
    emit latticeChanged(object);
}

void Document::replaceProject(io::Project project) {
    const QString oldPath = filePath();
    m_project = std::move(project);
    m_undo.clear();
    m_undo.setClean();
    emit sceneReplaced();
    if (filePath() != oldPath)
        emit filePathChanged(filePath());
}

}  // namespace softtouch::ui

#include "io/documents/clip_library_json.h"
#include "io/documents/document_json.h"
#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "io/import/animation_import.h"

#include "core/base/ranges.h"
#include "core/geometry/mesh_surface.h"
#include "core/geometry/mesh_volume.h"
#include "core/geometry/node_field_fit.h"
#include "core/solver/integrator.h"
#include "core/solver/simulator.h"

#include "io/documents/trajectory_file.h"
#include "io/files/atomic_file.h"
#include "io/files/file_text.h"
#include "io/import/mesh_import.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softtouch::io {
namespace fs = std::filesystem;
using nlohmann::json;

using namespace document;

namespace {

/// An object's "totalMass" spread by its "massDistribution": "box" (the default, spreadTotalMass) or
/// "mesh", by each node's share of the mesh's volume (core/geometry/mesh_volume.h), written as kg per node or, for
/// a Continuum material, as the density map that gives those masses.
void spreadObjectMass(const JsonValue& v, const Lattice& lattice, const Mesh& mesh, LatticeMaterial& material,
                      const std::optional<double>& totalMass) {
    const JsonValue distribution = v["massDistribution"];
    const std::optional<std::string> by = distribution.string();
    if (by && *by != "box" && *by != "mesh") {
        distribution.problem("expected \"box\" or \"mesh\", got \"" + *by + "\"");
        return;
    }
    if (by && !totalMass) {
        distribution.problem("spreads a \"totalMass\", and this material gives none");
        return;
    }
    if (by != "mesh") {
        spreadTotalMass(lattice, material, totalMass);
        return;
    }
    auto shares = meshVolumeShares(lattice, mesh);
    if (!shares) {
        distribution.problem(shares.message());
        return;
    }
    const bool continuum = material.model == MaterialModel::Continuum;
    const std::vector<double> volume = nodeVolumes(lattice);
    const std::vector<double> kg = meshMassPerNode(shares.value(), material.isVoid, *totalMass);
    for (std::size_t n = 0; n < material.mass.size(); ++n)
        if (!material.isVoid[n])
            material.mass[n] = continuum ? kg[n] / volume[n] : kg[n];  // a density gives that mass
}

/// An object's "animation": which take of its mesh file, which part of it, how it is sampled, and how the
/// body follows it (its "goal" springs).
std::optional<AnimationRequest> readAnimationRequest(const JsonValue& a, FollowSettings& follow) {
    if (!a.expectObject())
        return std::nullopt;
    a.checkKeys({"take", "start", "end", "loop", "sampleRate", "goal"});
    AnimationRequest request;
    request.take = a["take"].string().value_or("");
    if (auto x = a["start"].number(0.0, ranges::kMaxClipStart, "s"))
        request.start = *x;
    if (auto x = a["end"].number(0.0, ranges::kMaxClipStart, "s")) {
        if (*x <= request.start) {
            // Said here, at its field; the import would only say it again about the mesh.
            a["end"].problem("expected an end after \"start\" (" + detail::formatNumber(request.start) + " s)");
            return std::nullopt;
        }
        request.end = *x;
    }
    request.loop = a["loop"].boolean().value_or(true);
    if (auto x = a["sampleRate"].number(1.0, 1000.0, "samples/s"))
        request.rate = *x;
    if (const JsonValue g = a["goal"]; g.expectObject()) {
        g.checkKeys({"frequency", "dampingRatio"});
        if (auto x = g["frequency"].number(1e-3, 1000.0, "Hz"))
            follow.frequency = *x;
        if (auto x = g["dampingRatio"].number(0.0, 100.0))
            follow.dampingRatio = *x;
    }
    return request;
}

/// An object's "restShape": the edits of its rest shape (core/scene/rest_shape.h), each the lattice it was made on
/// (with its box) and the posed nodes, replayed in order over `mesh`, the object's mesh as read and placed.
/// False, with the problem recorded, when one is malformed or cannot apply.
bool readRestShape(const JsonValue& v, const SceneObject& object, Mesh& mesh, std::vector<RestShapeEdit>& edits) {
    if (!v.exists())
        return true;
    if (object.baseAnimation) {
        v.problem("an object on its own animation takes its rest shape from the animation; remove \"restShape\"");
        return false;
    }
    if (!v.isArray()) {
        v.problem("expected an array of edits [{\"lattice\": {\"kind\", \"nodes\", \"box\"}, \"nodes\": [[x, y, z], ...]}]");
        return false;
    }
    for (std::size_t e = 0; e < v.size(); ++e) {
        const JsonValue item = v.at(e);
        if (!item.expectObject(true))
            return false;
        item.checkKeys({"lattice", "nodes"});
        if (!item["lattice"]["box"].exists()) {
            item["lattice"].problem("expected the \"box\" the edit was made on");
            return false;
        }
        const auto lattice = readLattice(item["lattice"], mesh);
        if (!lattice)
            return false;
        RestShapeEdit edit;
        edit.shape = lattice->shape();
        edit.box = lattice->box();
        const JsonValue nodes = item["nodes"];
        if (nodes.size() != std::size_t(lattice->nodeCount())) {
            nodes.problem("expected " + std::to_string(lattice->nodeCount()) + " node positions [x, y, z], one per node of the lattice");
            return false;
        }
        for (std::size_t n = 0; n < nodes.size(); ++n) {
            const auto x = nodes.at(n).vec3(true);
            if (!x)
                return false;
            edit.nodes.push_back(*x);
        }
        if (Status s = applyRestShapeEdit(mesh, edit); !s) {
            item.problem(s.message());
            return false;
        }
        edits.push_back(std::move(edit));
    }
    return true;
}

/// An object's "goalWeightPoints": goal weights given at points, [[x, y, z, w], ...] in scene coordinates (a vertex group
/// painted in another tool, at the mesh's vertices), fitted to the lattice's nodes (core/geometry/node_field_fit.h).
/// The nodes' weights are what the object keeps: a save writes them as the material's "goalWeight".
void readGoalWeightPoints(const JsonValue& v, const JsonValue& material, SceneObject& object) {
    if (!v.exists())
        return;
    if (!object.baseAnimation) {
        v.problem("goal weights need the object's own animation (\"animation\") to follow");
        return;
    }
    if (material["goalWeight"].exists()) {
        v.problem("give the goal weights once: here at points or as the material's \"goalWeight\", not both");
        return;
    }
    if (!v.isArray() || v.size() == 0) {
        v.problem("expected a non-empty array of [x, y, z, weight], weight in [0, 1]");
        return;
    }
    std::vector<PointValue> points;
    points.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        const JsonValue item = v.at(i);
        if (item.size() != 4) {
            item.problem("expected [x, y, z, weight]");
            return;
        }
        PointValue p;
        for (int c = 0; c < 3; ++c) {
            const auto x = item.at(std::size_t(c)).number(-ranges::kMaxMeshSize, ranges::kMaxMeshSize, "m", true);
            if (!x)
                return;
            p.point[c] = *x;
        }
        const auto w = item.at(3).number(kGoalWeightRange.low, kGoalWeightRange.high, "", true);
        if (!w)
            return;
        p.value = *w;
        points.push_back(p);
    }
    auto field = fitNodeField(object.lattice, points);
    if (!field) {
        v.problem(field.message());
        return;
    }
    object.material.goalWeight = std::move(field.value());
}

void readObject(const JsonValue& v, const fs::path& baseDir, Project& project, JsonIssues& issues) {
    if (!v.expectObject(true))
        return;
    v.checkKeys({"name", "mesh", "animation", "position", "restShape", "lattice", "material", "goalWeightPoints", "anchors", "voids",
                 "drivers"});
    SceneObject object;
    object.name = v["name"].string().value_or("object " + std::to_string(project.scene.objects.size()));
    const auto meshRef = v["mesh"].string(true);
    if (!meshRef)
        return;
    Mesh mesh;  // as read and placed, then the object's (shared) rest mesh
    if (const JsonValue a = v["animation"]; a.exists()) {
        // The mesh's own animation: the mesh is its first sample (io/import/animation_import.h).
        auto request = readAnimationRequest(a, object.follow);
        if (!request)
            return;
        auto animated = importAnimatedMesh(baseDir / *meshRef, *request);
        if (!animated) {
            v["mesh"].problem(animated.message());
            return;
        }
        mesh = std::move(animated->mesh);
        object.baseAnimation = std::make_shared<BaseAnimation>(std::move(animated->animation));
        project.importNotes.push_back(object.name + ": take \"" + object.baseAnimation->take + "\" from " +
                                      detail::formatNumber(object.baseAnimation->start) + " s for " +
                                      detail::formatNumber(object.baseAnimation->duration()) + " s at " +
                                      detail::formatNumber(object.baseAnimation->rate) + " samples/s" +
                                      (object.baseAnimation->loop ? ", looping" : "") + "; " +
                                      std::to_string(mesh.positions.size()) + " vertices in " + animated->unit);
    } else {
        auto imported = importMesh(baseDir / *meshRef);
        if (!imported) {
            v["mesh"].problem(imported.message());
            return;
        }
        mesh = std::move(imported.value());
    }
    // Where the mesh goes in the scene: its file's coordinates moved by this (a lattice "box", like
    // everything else in the file, is in scene coordinates).
    Vec3 offset = Vec3::Zero();
    if (auto x = v["position"].vec3()) {
        if (x->norm() > ranges::kMaxMeshSize)
            v["position"].problem("expected at most 1e5 m from the origin");
        else
            offset = *x;
    }
    for (Vec3f& p : mesh.positions)
        p += offset.cast<float>();
    if (object.baseAnimation && !offset.isZero()) {
        auto moved = std::make_shared<BaseAnimation>(*object.baseAnimation);
        for (auto& sample : moved->samples)
            for (Vec3f& p : sample)
                p += offset.cast<float>();
        object.baseAnimation = std::move(moved);
    }
    std::vector<RestShapeEdit> restShape;
    if (!readRestShape(v["restShape"], object, mesh, restShape))
        return;
    object.mesh = std::move(mesh);
    auto lattice = readLattice(v["lattice"], object.mesh);
    if (!lattice)
        return;
    object.lattice = *lattice;
    object.material = uniformMaterial(object.lattice, 0.02, 80.0, 0.9);
    std::optional<double> totalMass;
    readMaterial(v["material"], object.material, totalMass, true, baseDir);

    readGoalWeightPoints(v["goalWeightPoints"], v["material"], object);
    readAnchors(v["anchors"], object.lattice, object.material.anchor);
    if (const JsonValue voids = v["voids"]; voids.expectObject()) {
        voids.checkKeys({"auto", "nodes", "region"});
        if (voids["auto"].boolean().value_or(false))
            object.material.isVoid = findEmptyNodes(object.lattice, object.mesh);
        if (voids["nodes"].exists() || voids["region"].exists()) {
            for (int node : readNodeSelection(voids, object.lattice))
                object.material.isVoid[std::size_t(node)] = 1;
        }
    }
    spreadObjectMass(v["material"], object.lattice, object.mesh, object.material, totalMass);
    readDrivers(v["drivers"], object.drivers);
    // The solver's limits, then the body itself, which validates combinations (every node void, …).
    if (issues.empty()) {
        if (Status s = checkObjectLimits(object, project.scene.world); !s) {
            v.problem(s.message());
        } else if (auto body = buildLatticeBody(object.lattice, object.material); !body) {
            v.problem(body.message());
        } else {
            // A step the explicit schemes would refuse at rest fails every bake: say so here, not there.
            const SimulationSettings& settings = project.scene.world.simulation;
            ExternalForces rest;
            rest.gravity = project.scene.world.gravity;
            const Simulator simulator(body.value(), settings);
            if (simulator.substepsFor(rest) > settings.maxSubsteps) {
                std::ostringstream msg;
                msg << "at dt = " << settings.dt << " s this body needs more than " << settings.maxSubsteps << " substeps of "
                    << integratorName(settings.integrator) << " a step (stable step " << simulator.stableStep(rest)
                    << " s): lower dt, soften the stiffest spring, raise the lightest mass, or use implicit-euler";
                v.problem(msg.str());
            }
        }
    }
    project.meshReferences.push_back(*meshRef);
    project.meshOffsets.resize(project.meshReferences.size() - 1, Vec3::Zero());
    project.meshOffsets.push_back(offset);
    project.restShapeEdits.resize(project.meshReferences.size() - 1);
    project.restShapeEdits.push_back(std::move(restShape));
    project.scene.objects.push_back(std::move(object));
}

void readWorld(const JsonValue& root, const fs::path& baseDir, WorldSettings& w) {
    if (const JsonValue world = root["world"]; world.expectObject()) {
        world.checkKeys({"gravity", "planes", "colliders", "bodyCollisions"});
        if (auto g = world["gravity"].vec3()) {
            if (g->norm() > ranges::kMaxGravity)
                world["gravity"].problem("expected at most 1e4 m/s² (a thousand g), got a magnitude of " + std::to_string(g->norm()));
            else
                w.gravity = *g;
        }
        const JsonValue planes = world["planes"];
        if (planes.exists() && !planes.isArray())
            planes.problem("expected an array of planes");
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const JsonValue p = planes.at(i);
            if (!p.expectObject(true))
                continue;
            p.checkKeys({"point", "normal", "restitution", "friction"});
            CollisionPlane plane;
            if (auto x = p["point"].vec3()) plane.point = *x;
            if (auto n = p["normal"].vec3()) {
                if (n->norm() < 1e-9)
                    p["normal"].problem("the normal must not be zero");
                else
                    plane.normal = n->normalized();
            }
            if (auto x = p.field(ranges::kRestitution)) plane.restitution = *x;
            if (auto x = p.field(ranges::kFriction)) plane.friction = *x;
            w.planes.push_back(plane);
        }
        // Objects against each other (core/body/body_contacts.h): off unless the file turns them on.
        if (const JsonValue bodies = world["bodyCollisions"]; bodies.exists() && bodies.expectObject()) {
            bodies.checkKeys({"enabled", "restitution", "friction"});
            if (auto x = bodies["enabled"].boolean()) w.bodyCollisions.enabled = *x;
            if (auto x = bodies.field(ranges::kRestitution)) w.bodyCollisions.restitution = *x;
            if (auto x = bodies.field(ranges::kFriction)) w.bodyCollisions.friction = *x;
        }
        // Spheres, capsules, boxes and meshes (core/body/colliders.h); each shape has its own size keys.
        const JsonValue colliders = world["colliders"];
        if (colliders.exists() && !colliders.isArray())
            colliders.problem("expected an array of colliders");
        for (std::size_t i = 0; i < colliders.size(); ++i) {
            const JsonValue v = colliders.at(i);
            if (!v.expectObject(true))
                continue;
            Collider c;
            const auto shape = v["shape"].string();
            if (!shape || (*shape != "sphere" && *shape != "capsule" && *shape != "box" && *shape != "mesh")) {
                v["shape"].problem("expected \"sphere\", \"capsule\", \"box\" or \"mesh\"");
                continue;
            }
            c.shape = *shape == "sphere"    ? ColliderShape::Sphere
                      : *shape == "capsule" ? ColliderShape::Capsule
                      : *shape == "box"     ? ColliderShape::Box
                                            : ColliderShape::Mesh;
            if (c.shape == ColliderShape::Mesh) {
                v.checkKeys({"shape", "mesh", "oneSided", "centre", "axes", "scale", "restitution", "friction"});
                // Closed unless the file says the mesh is a one-sided sheet (core/geometry/mesh_surface.h, SurfaceSides): an
                // open mesh read as a solid let bodies fall through it.
                const bool oneSided = v["oneSided"].boolean().value_or(false);
                if (const auto ref = v["mesh"].string(true)) {
                    auto mesh = importMesh(baseDir / *ref);
                    auto surface = mesh ? MeshSurface::create(std::move(mesh.value()), *ref,
                                                              oneSided ? SurfaceSides::OneSided : SurfaceSides::Closed)
                                        : Result<std::shared_ptr<const MeshSurface>>(Status::error(mesh.message()));
                    if (surface)
                        c.surface = surface.value();
                    else
                        v["mesh"].problem(surface.message());
                }
                if (auto x = v.field(ranges::kMeshColliderScale)) c.scale = *x;
            } else if (c.shape == ColliderShape::Sphere)
                v.checkKeys({"shape", "centre", "radius", "restitution", "friction"});
            else if (c.shape == ColliderShape::Capsule)
                v.checkKeys({"shape", "centre", "radius", "axis", "halfLength", "restitution", "friction"});
            else
                v.checkKeys({"shape", "centre", "halfExtents", "axes", "restitution", "friction"});
            if (auto x = v["centre"].vec3(true)) c.centre = *x;
            if (c.shape == ColliderShape::Sphere || c.shape == ColliderShape::Capsule)
                if (auto x = v.field(ranges::kColliderRadius, true)) c.radius = *x;
            if (c.shape == ColliderShape::Capsule) {
                if (auto x = v.field(ranges::kCapsuleHalfLength, true)) c.halfLength = *x;
                if (auto a = v["axis"].vec3(true)) {
                    if (a->norm() < 1e-9)
                        v["axis"].problem("the axis must not be zero");
                    else
                        c.axis = a->normalized();
                }
            }
            if (c.shape == ColliderShape::Box || c.shape == ColliderShape::Mesh) {
                if (c.shape == ColliderShape::Box)
                    if (auto h = v["halfExtents"].vec3(true)) {
                        if ((h->array() <= 0.0).any() || (h->array() > 1e6).any())
                            v["halfExtents"].problem("each half extent must be in (0, 1e6] m");
                        else
                            c.halfExtents = *h;
                    }
                const JsonValue axes = v["axes"];
                if (axes.exists()) {
                    if (!axes.isArray() || axes.size() != 3) {
                        axes.problem("expected three axis vectors [[x], [y], [z]]");
                    } else {
                        for (std::size_t k = 0; k < 3; ++k)
                            if (auto a = axes.at(k).vec3(true))
                                c.axes.col(Eigen::Index(k)) = *a;
                        if ((c.axes.transpose() * c.axes - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6)
                            axes.problem("the axes must be unit and at right angles");
                    }
                }
            }
            if (auto x = v.field(ranges::kRestitution)) c.restitution = *x;
            if (auto x = v.field(ranges::kFriction)) c.friction = *x;
            if (c.shape == ColliderShape::Mesh && !c.surface)
                continue;  // its mesh's problem is reported
            w.colliders.push_back(c);
        }
    }
    if (const JsonValue sim = root["simulation"]; sim.expectObject()) {
        sim.checkKeys({"integrator", ranges::kDt.name, ranges::kXpbdSubsteps.name, ranges::kEnergyCheckSteps.name, "sleep"});
        if (auto name = sim["integrator"].string()) {
            if (auto kind = parseIntegratorKind(*name))
                w.simulation.integrator = *kind;
            else
                sim["integrator"].problem("expected " + integratorNames([](const IntegratorInfo&) { return true; }) +
                                          ", got \"" + *name + "\"");
        }
        if (auto x = sim.field(ranges::kDt)) w.simulation.dt = *x;
        if (auto x = sim.field(ranges::kXpbdSubsteps)) w.simulation.xpbdSubsteps = int(*x);
        if (auto x = sim.field(ranges::kEnergyCheckSteps)) w.simulation.energyCheckSteps = int(*x);
        if (auto x = sim["sleep"].boolean()) w.simulation.sleep = *x;
    }
    if (const JsonValue clip = root["clip"]; clip.expectObject()) {
        clip.checkKeys({ranges::kFrames.name, ranges::kFps.name});
        if (auto x = clip.field(ranges::kFrames)) w.frames = int(*x);
        if (auto x = clip.field(ranges::kFps)) w.fps = *x;
    }
    // What core checks beyond each field (a safety net: a rule added there is enforced here too).
    WorldSettings checked = w;
    if (Status s = checked.validate(); !s)
        root.problem(s.message());
}

/// Reads a whole project from its parsed document, collecting every problem.
std::optional<Project> readProject(const json& doc, const fs::path& path, JsonIssues& issues) {
    const JsonValue root(&doc, "", &issues);
    if (!readHeader(root, kProjectFormat, kProjectVersion))
        return std::nullopt;
    root.checkKeys({"format", "version", "objects", "world", "simulation", "clip", "clips", "sessions", "keyframes"});
    Project project;
    project.path = path;
    const fs::path baseDir = path.parent_path();
    const JsonValue objects = root["objects"];
    // An empty scene is a project too (the editor's File ▸ New); a bake of it says there is nothing to simulate.
    if (!objects.isArray())
        objects.problem("expected an array of objects");
    // The world first: an object's body is built (and checked) only where the solver can run it.
    readWorld(root, baseDir, project.scene.world);
    for (std::size_t i = 0; i < objects.size(); ++i)
        readObject(objects.at(i), baseDir, project, issues);
    // The library refers to the objects' lattices: read it only onto a valid scene.
    if (!issues.empty())
        return std::nullopt;
    readClipLibrary(root, root["version"].integer(1, 1000000).value_or(1), project);
    if (!issues.empty())
        return std::nullopt;
    return project;
}

}  // namespace

Result<Project> loadProject(const fs::path& path) { return loadDocument<Project>(path, readProject); }

Result<Project> loadProjectToRun(const fs::path& path) {
    auto project = loadProject(path);
    if (project && project->scene.objects.empty())
        return Status::error(path.string() + ": /objects: the scene has no objects to simulate (add a mesh first)");
    return project;
}

std::vector<std::string> validateFile(const fs::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return issues.messages();
    const std::string format = doc->is_object() && doc->contains("format") && (*doc)["format"].is_string()
                                   ? (*doc)["format"].get<std::string>()
                                   : std::string();
    if (format == "softtouch-trajectory") {  // a device recording, or a script for the scripted device
        auto trajectory = loadTrajectory(path);
        if (trajectory)
            return {};
        JsonIssues all(path.string());
        all.addGeneral(trajectory.message());
        return all.messages();
    }
    if (format == kPresetFormat) {  // either kind, every problem listed
        if (declaresSetup(*doc))
            readSetupPreset(*doc, path, issues);
        else
            readMaterialPreset(*doc, path, issues);
        return issues.messages();
    }
    readProject(*doc, path, issues);
    return issues.messages();
}

Status saveProject(const Project& project, const fs::path& path) {
    // Mesh references are relative to the project file: rebase them when saving somewhere else.
    // A project not yet saved (an imported mesh) has no path: its references are kept as they are
    // (fs::absolute of an empty path throws).
    const fs::path from = project.path.empty() ? fs::path() : fs::absolute(project.path).parent_path();
    const fs::path to = fs::absolute(path).parent_path();
    // An absolute reference (a mesh imported from a file dialog) is written relative too, as Blender's "//" paths
    // are, so the project's folder can be moved or shared with its meshes; it stays absolute only where no
    // relative path leads there.
    auto rebased = [&](const std::string& ref) {
        if (ref.empty())
            return ref;
        if (fs::path(ref).is_absolute()) {
            const fs::path relative = fs::path(ref).lexically_normal().lexically_relative(to.lexically_normal());
            return relative.empty() ? ref : relative.generic_string();
        }
        if (project.path.empty())
            return ref;
        return (from / ref).lexically_normal().lexically_relative(to.lexically_normal()).generic_string();
    };
    json objects = json::array();
    for (std::size_t i = 0; i < project.scene.objects.size(); ++i) {
        const SceneObject& o = project.scene.objects[i];
        const json lattice = latticeJson(o.lattice.shape(), o.lattice.box());
        json drivers = json::array();
        for (const Driver& d : o.drivers)
            drivers.push_back(driverJson(d));
        json object = {{"name", o.name},
                       {"mesh", rebased(i < project.meshReferences.size() ? project.meshReferences[i] : std::string())},
                       {"lattice", lattice},
                       {"drivers", drivers}};
        if (i < project.meshOffsets.size() && !project.meshOffsets[i].isZero())
            object["position"] = vec(project.meshOffsets[i]);
        if (i < project.restShapeEdits.size() && !project.restShapeEdits[i].empty()) {
            json edits = json::array();
            for (const RestShapeEdit& e : project.restShapeEdits[i]) {
                json nodes = json::array();
                for (const Vec3& x : e.nodes)
                    nodes.push_back(vec(x));
                edits.push_back({{"lattice", latticeJson(e.shape, e.box)}, {"nodes", nodes}});
            }
            object["restShape"] = edits;
        }
        if (const auto& a = o.baseAnimation)
            object["animation"] = {{"take", a->take},
                                   {"start", a->start},
                                   {"end", a->start + a->duration()},
                                   {"loop", a->loop},
                                   {"sampleRate", a->rate},
                                   {"goal", {{"frequency", o.follow.frequency}, {"dampingRatio", o.follow.dampingRatio}}}};
        writeMaterial(o.lattice, o.material, object);
        objects.push_back(object);
    }
    const WorldSettings& w = project.scene.world;
    json planes = json::array();
    for (const CollisionPlane& p : w.planes)
        planes.push_back({{"point", vec(p.point)}, {"normal", vec(p.normal)}, {ranges::kRestitution.name, p.restitution},
                          {ranges::kFriction.name, p.friction}});
    json colliders = json::array();
    for (const Collider& c : w.colliders) {
        json entry = {{"shape", colliderShapeName(c.shape)}, {"centre", vec(c.centre)}};
        if (c.shape == ColliderShape::Sphere || c.shape == ColliderShape::Capsule)
            entry[ranges::kColliderRadius.name] = c.radius;
        if (c.shape == ColliderShape::Capsule) {
            entry["axis"] = vec(c.axis);
            entry[ranges::kCapsuleHalfLength.name] = c.halfLength;
        }
        if (c.shape == ColliderShape::Box)
            entry["halfExtents"] = vec(c.halfExtents);
        if (c.shape == ColliderShape::Mesh) {
            entry["mesh"] = rebased(c.surface->source());
            if (c.surface->sides() == SurfaceSides::OneSided)  // absent means closed: older files read as before
                entry["oneSided"] = true;
            entry[ranges::kMeshColliderScale.name] = c.scale;
        }
        if (c.shape == ColliderShape::Box || c.shape == ColliderShape::Mesh)
            entry["axes"] = {vec(c.axes.col(0)), vec(c.axes.col(1)), vec(c.axes.col(2))};
        entry[ranges::kRestitution.name] = c.restitution;
        entry[ranges::kFriction.name] = c.friction;
        colliders.push_back(entry);
    }
    json world = {{"gravity", vec(w.gravity)}, {"planes", planes}};
    if (!colliders.empty())
        world["colliders"] = colliders;
    if (w.bodyCollisions.enabled)
        world["bodyCollisions"] = {{"enabled", true},
                                   {ranges::kRestitution.name, w.bodyCollisions.restitution},
                                   {ranges::kFriction.name, w.bodyCollisions.friction}};
    json doc = {{"format", kProjectFormat},
                      {"version", kProjectVersion},
                      {"objects", objects},
                      {"world", world},
                      {"simulation",
                       {{"integrator", std::string(integratorName(w.simulation.integrator))},
                        {ranges::kDt.name, w.simulation.dt},
                        {ranges::kXpbdSubsteps.name, w.simulation.xpbdSubsteps},
                        {"sleep", w.simulation.sleep}}},
                      {"clip", {{ranges::kFrames.name, w.frames}, {ranges::kFps.name, w.fps}}}};
    if (w.simulation.energyCheckSteps != SimulationSettings{}.energyCheckSteps)  // rarely changed: named only then
        doc["simulation"][ranges::kEnergyCheckSteps.name] = w.simulation.energyCheckSteps;
    writeClipLibrary(project.clips, doc);
    return writeFileAtomically(path, doc.dump(2) + "\n");
}

}  // namespace softtouch::io

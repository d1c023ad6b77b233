#include "io/pipeline/bake.h"

#include "core/base/node_change.h"

#include "io/export/vertex_cache.h"
#include "io/files/atomic_file.h"
#include "io/import/animation_import.h"
#include "io/pipeline/frame_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <set>

namespace softtouch::io {

namespace {

/// A target may be absent or a regular file (replaced); anything else (a folder, a device such as
/// /dev/full, a FIFO) is refused, because a rename would replace it or fail half-way.
Status checkOutputTarget(const std::filesystem::path& target) {
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(target, ec);
    if (ec || !std::filesystem::exists(status) || std::filesystem::is_regular_file(status))
        return Status::success();
    const char* kind = std::filesystem::is_directory(status) ? "a folder"
                       : std::filesystem::is_symlink(status) ? "a symbolic link"
                                                              : "not a regular file (a device, FIFO or socket)";
    return Status::error("cannot write '" + target.string() + "': it exists and is " + kind + "; nothing was written");
}

/// The skeleton the one object written came skinned to, posed at every frame, for a skin export that keeps it
/// (ClipExportOptions::skinRig); null where the export fits its own bones, with the reason in `why` when the
/// object does follow a base animation. Fails only where the source rig was asked for and cannot be had.
Result<std::shared_ptr<const SourceRig>> sourceRigFor(const FrameSource& source, const std::vector<bool>& written,
                                                      const BakeOptions& options, int frames, std::string& why) {
    using SkinRig = ClipExportOptions::SkinRig;
    const SkinRig wanted = options.exportOptions.skinRig;
    if (!options.format->takesBones || wanted == SkinRig::Fitted)
        return std::shared_ptr<const SourceRig>();
    const SceneSimulation& sim = source.simulation();
    std::vector<std::size_t> objects;
    for (std::size_t i = 0; i < sim.objectCount(); ++i)
        if (written[i])
            objects.push_back(i);
    auto without = [&](const std::string& reason, bool followsRig) -> Result<std::shared_ptr<const SourceRig>> {
        if (wanted == SkinRig::Source)
            return Status::error("--rig source: " + reason);
        if (followsRig)
            why = reason;
        return std::shared_ptr<const SourceRig>();
    };
    if (objects.size() != 1)
        return without("the bake writes " + std::to_string(objects.size()) + " objects; a skin onto a source rig takes one "
                       "(bake them one by one with --each-object)",
                       false);
    const std::size_t i = objects.front();
    const SceneObject& object = sim.object(i);
    if (!sim.followsBaseAnimation(i) || !object.baseAnimation)
        return without("object '" + object.name + "' has no base animation, so no rig of its own", false);
    if (i >= options.meshSources.size() || options.meshSources[i].file.empty())
        return without("the file object '" + object.name + "' came from is not known (or its rest shape was edited)", true);
    const MeshSource& from = options.meshSources[i];
    const BaseAnimation& animation = *object.baseAnimation;
    std::vector<double> takeSeconds(static_cast<std::size_t>(frames));
    for (int f = 0; f < frames; ++f)
        takeSeconds[std::size_t(f)] = animation.takeSeconds(source.secondsAt(f));
    auto read = importSourceRig(from.file, animation.take, takeSeconds);
    if (!read)
        return without(read.message(), true);
    SourceRig& rig = read.value();
    if (rig.mesh.bind.size() != object.mesh->positions.size())
        return without("the skinned mesh of '" + from.file.string() + "' has " + std::to_string(rig.mesh.bind.size()) +
                       " vertices and object '" + object.name + "' " + std::to_string(object.mesh->positions.size()),
                       true);
    // A mesh moved on load ("position") moves its whole rig: the top-level nodes carry the offset.
    for (std::size_t n = 0; n < rig.skeleton.nodes.size(); ++n) {
        if (rig.skeleton.nodes[n].parent >= 0)
            continue;
        rig.skeleton.nodes[n].rest.translation += from.offset;
        for (auto& pose : rig.skeleton.poses)
            pose[n].translation += from.offset;
    }
    return std::shared_ptr<const SourceRig>(std::make_shared<SourceRig>(std::move(rig)));
}

}  // namespace

std::vector<MeshSource> meshSources(const Project& project) {
    std::vector<MeshSource> sources(project.meshReferences.size());
    const std::filesystem::path folder = project.path.empty() ? std::filesystem::path()
                                                              : std::filesystem::absolute(project.path).parent_path();
    for (std::size_t i = 0; i < sources.size(); ++i) {
        const std::string& ref = project.meshReferences[i];
        if (ref.empty() || (i < project.restShapeEdits.size() && !project.restShapeEdits[i].empty()))
            continue;
        const std::filesystem::path path(ref);
        sources[i].file = path.is_absolute() || folder.empty() ? path : (folder / path).lexically_normal();
        if (i < project.meshOffsets.size())
            sources[i].offset = project.meshOffsets[i];
    }
    return sources;
}

std::uint32_t appendToRestMesh(Mesh& rest, const Mesh& object) {
    const auto base = std::uint32_t(rest.positions.size());
    rest.positions.insert(rest.positions.end(), object.positions.begin(), object.positions.end());
    if (!object.normals.empty())
        rest.normals.insert(rest.normals.end(), object.normals.begin(), object.normals.end());
    for (const auto& t : object.triangles)
        rest.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    return base;
}

Result<BakeResult> bake(const Scene& scene, const BakeOptions& options) {
    BakeResult result;
    FrameRequest request;
    request.clips = options.clips;
    request.clip = options.clip;
    request.frames = options.frames;
    request.fps = options.fps;
    request.clipProgress = options.simulating;
    auto created = FrameSource::create(scene, request, &result.warnings);
    if (!created)
        return created.status();
    FrameSource& source = created.value();
    const SceneSimulation& sim = source.simulation();
    const int frames = source.frameCount();
    result.clip = source.clipName();
    result.seam = source.seam();

    // The objects written: all, or those named.
    std::vector<bool> written(sim.objectCount(), options.objects.empty());
    for (const std::string& name : options.objects) {
        bool found = false;
        for (std::size_t i = 0; i < sim.objectCount(); ++i)
            if (sim.object(i).name == name)
                found = written[i] = true;
        if (!found) {
            std::string names;
            for (std::size_t i = 0; i < sim.objectCount(); ++i)
                names += (i ? ", '" : "'") + sim.object(i).name + "'";
            return Status::error("the scene has no object named '" + name + "' (it has " + names + ")");
        }
    }

    // The rest mesh of the objects written, concatenated in scene order: the cache's vertex order.
    ClipSetup setup;
    Mesh& rest = setup.restMesh;
    for (std::size_t i = 0; i < sim.objectCount(); ++i) {
        if (!written[i])
            continue;
        const SceneObject& object = sim.object(i);
        const Mesh& m = object.mesh;
        const auto base = std::uint32_t(rest.positions.size());
        ClipObject clipObject{object.name, base, std::uint32_t(m.positions.size()),
                              std::uint32_t(rest.triangles.size()), std::uint32_t(m.triangles.size()), object.lattice};
        setup.objects.push_back(std::move(clipObject));
        appendToRestMesh(rest, m);
        if (options.objectGroups)  // the OBJ writers name each object's faces after it
            rest.parts.push_back({object.name, base, std::uint32_t(m.positions.size())});
    }
    if (rest.normals.size() != rest.positions.size())
        rest.computeNormals();

    const ExportFormat& format = *options.format;
    result.files = exportFiles(format, options.output, std::size_t(frames));
    result.cache = result.files.front();
    result.restMesh = restMeshPath(options.output, format);
    result.points = rest.positions.size();
    // Every target is checked before anything is written: publishing is a rename per file, and a rename
    // that fails half-way (onto a folder) would leave the files published before it replaced.
    if (options.output.filename().empty() || options.output.stem().empty())
        return Status::error("--out '" + options.output.string() + "' names a folder, not a file: add a file name");
    std::vector<std::filesystem::path> targets = result.files;
    targets.push_back(result.restMesh);
    for (const std::filesystem::path& target : targets)
        if (Status s = checkOutputTarget(target); !s)
            return s;
    // Temporaries a killed run left (kill -9, a power cut) are swept in one pass over each folder: this
    // run's targets, and for a format of one file per frame every frame of the same name, so that a
    // re-run with fewer frames sweeps the frames beyond its own too.
    std::map<std::filesystem::path, std::set<std::string>> targetNames;
    for (const std::filesystem::path& target : targets)
        targetNames[target.parent_path()].insert(target.filename().string());
    const bool sequence = exportFiles(format, options.output, 2).size() == 2;  // a file per frame: the OBJ sequence
    for (const auto& [folder, names] : targetNames)
        removeStaleTemporaries(folder, [&, &names = names](const std::string& name) {
            return names.count(name) != 0 || (sequence && isObjSequenceFrameName(options.output, name));
        });

    auto writer = format.makeWriter(options.output, options.exportOptions);
    if (writer->needsNodes())
        for (std::size_t i = 0; i < sim.objectCount(); ++i)
            if (written[i] && sim.followsBaseAnimation(i))
                return Status::error("object '" + sim.object(i).name + "' moves with its own base animation, which its "
                                     "lattice cannot carry (the cache holds lattice nodes only, and a rig bends the "
                                     "mesh in ways the lattice cannot follow); export it as pc2, mdd, obj, glTF, skin, "
                                     "pca or vat");
    setup.info.pointCount = rest.positions.size();
    setup.info.frameCount = std::size_t(frames);
    setup.info.fps = source.fps();
    setup.loops = source.loopLength() > 0 && frames % source.loopLength() == 0;
    std::string fittedBecause;
    auto rig = sourceRigFor(source, written, options, frames, fittedBecause);
    if (!rig)
        return rig.status();
    setup.sourceRig = std::move(rig.value());
    if (Status s = writer->begin(options.output, setup); !s)
        return s;

    // One frame in memory: positions, normals when the writer wants them, node positions borrowed
    // from the frame source.
    std::vector<Vec3f> positions(rest.positions.size());
    std::vector<Vec3f> normals(writer->needsNormals() ? rest.positions.size() : 0);
    FrameData frame;
    frame.positions = positions;
    frame.normals = normals;
    // An object whose nodes did not move keeps last frame's mesh (a sleeping body costs nothing).
    std::vector<NodeChangeTracker> moved(sim.objectCount());
    result.objects = int(std::count(written.begin(), written.end(), true));
    for (int f = 0; f < frames; ++f) {
        source.seek(f, &result.warnings);
        if (const std::string& refusal = source.simulation().refusal(); !refusal.empty()) {
            writer->abort();
            return Status::error(refusal + "; nothing was written");
        }
        std::size_t offset = 0;
        for (std::size_t i = 0; i < sim.objectCount(); ++i) {
            if (!written[i])
                continue;
            const std::size_t n = sim.object(i).mesh->positions.size();
            const std::span<Vec3f> objectNormals =
                normals.empty() ? std::span<Vec3f>() : std::span<Vec3f>(normals).subspan(offset, n);
            if (moved[i].changed(source.nodes(i)) || sim.followsBaseAnimation(i)) {
                source.evaluate(i, std::span<Vec3f>(positions).subspan(offset, n), objectNormals, options.threads);
                ++result.meshEvaluations;
            }
            offset += n;
        }
        frame.nodes.clear();
        if (writer->needsNodes()) {
            for (std::size_t i = 0; i < sim.objectCount(); ++i)
                if (written[i])
                    frame.nodes.push_back(source.nodes(i));
        }
        if (Status s = writer->writeFrame(frame); !s) {
            writer->abort();
            return s;
        }
        if (options.progress && !options.progress(f + 1, frames)) {
            writer->abort();
            return Status::cancelled("the bake was cancelled; nothing was written");
        }
    }
    // The rest mesh first: a cache is never published without the mesh it matches.
    if (Status s = writeObj(result.restMesh, rest, {}, {}, options.objectGroups); !s) {
        writer->abort();
        return s;
    }
    if (Status s = writer->finish(); !s)
        return s;
    // The exporter's first: the CLI shows only the first few.
    result.warnings.insert(result.warnings.begin(), writer->warnings().begin(), writer->warnings().end());
    result.notes = writer->notes();
    if (!fittedBecause.empty())
        result.notes.push_back("bones fitted to the clip, not on the source rig: " + fittedBecause);
    result.frames = frames;
    return result;
}

std::filesystem::path perObjectPath(const std::filesystem::path& output, const std::string& name) {
    std::string safe = name.empty() ? std::string("object") : name;
    for (char& c : safe)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_')
            c = '_';
    std::filesystem::path out = output;
    out.replace_filename(output.stem().string() + "-" + safe + output.extension().string());
    return out;
}

Result<std::vector<BakeResult>> bakeEachObject(const Scene& scene, const BakeOptions& options) {
    std::vector<BakeResult> results;
    std::set<std::filesystem::path> outputs;
    for (const SceneObject& o : scene.objects)
        if (!outputs.insert(perObjectPath(options.output, o.name)).second)
            return Status::error("two objects would both write " + perObjectPath(options.output, o.name).string() +
                                 ": rename one");
    for (const SceneObject& o : scene.objects) {
        BakeOptions one = options;
        one.objects = {o.name};
        one.output = perObjectPath(options.output, o.name);
        auto baked = bake(scene, one);
        if (!baked)
            return Status::error("object '" + o.name + "': " + baked.message());
        results.push_back(std::move(baked.value()));
    }
    return results;
}

}  // namespace softtouch::io

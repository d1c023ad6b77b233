#include "io/pipeline/reference_cache.h"

#include "io/files/atomic_file.h"
#include "io/files/content_hash.h"

#include "analysis/clip_frames.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <unistd.h>

namespace softtouch::io {
namespace fs = std::filesystem;
namespace {

constexpr char kMagic[] = "softtouch-reference 1\n";
/// Bounds a stored file must respect to be read (a damaged or foreign file is refused, then made again).
constexpr std::uint64_t kMaxLevels = 64, kMaxText = 4096, kMaxObjects = 1024, kMaxFloats = std::uint64_t(1) << 31;

class Writer {
public:
    template <typename T>
    void put(const T& value) { m_bytes.append(reinterpret_cast<const char*>(&value), sizeof value); }
    void put(const std::string& text) {
        put(std::uint64_t(text.size()));
        m_bytes += text;
    }
    void put(const std::vector<Vec3f>& points) {
        put(std::uint64_t(points.size() * 3));
        m_bytes.append(reinterpret_cast<const char*>(points.data()), points.size() * sizeof(Vec3f));
    }
    const std::string& bytes() const { return m_bytes; }

private:
    std::string m_bytes = kMagic;
};

class Reader {
public:
    explicit Reader(std::string bytes) : m_bytes(std::move(bytes)) {
        m_ok = m_bytes.compare(0, sizeof kMagic - 1, kMagic) == 0;
        m_at = sizeof kMagic - 1;
    }
    template <typename T>
    T get() {
        T value{};
        if (m_ok && m_at + sizeof value <= m_bytes.size()) {
            std::memcpy(&value, m_bytes.data() + m_at, sizeof value);
            m_at += sizeof value;
        } else {
            m_ok = false;
        }
        return value;
    }
    std::string text() {
        const auto n = get<std::uint64_t>();
        if (!m_ok || n > kMaxText || m_at + n > m_bytes.size()) {
            m_ok = false;
            return {};
        }
        std::string out = m_bytes.substr(m_at, n);
        m_at += n;
        return out;
    }
    std::vector<Vec3f> points() {
        const auto n = get<std::uint64_t>();
        if (!m_ok || n % 3 != 0 || n > kMaxFloats || m_at + n * sizeof(float) > m_bytes.size()) {
            m_ok = false;
            return {};
        }
        std::vector<Vec3f> out(n / 3);
        if (n == 0) return out;  // memcpy's pointers must be valid even for no bytes
        std::memcpy(static_cast<void*>(out.data()), m_bytes.data() + m_at, n * sizeof(float));
        m_at += n * sizeof(float);
        return out;
    }
    bool ok() const { return m_ok && m_at == m_bytes.size(); }
    bool good() const { return m_ok; }

private:
    std::string m_bytes;
    std::size_t m_at = 0;
    bool m_ok = false;
};

fs::path fileFor(const fs::path& folder, const std::string& key) { return folder / (key + ".streference"); }

}  // namespace

fs::path referenceCacheFolder() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/')
        return fs::path(xdg) / "softtouch" / "references";
    const char* home = std::getenv("HOME");
    return fs::path(home && *home ? home : "/tmp") / ".cache" / "softtouch" / "references";
}

Result<std::string> referenceKey(const Project& project, const Clip& clip, const analysis::ReferenceOptions& options) {
    ContentHash hash;
    // The number changes whenever the converged solid itself changes (2: the material is one cubic cell's solid).
    hash.add(std::string("softtouch-reference 2 " SOFTTOUCH_VERSION));
    // The project as saved holds every authored setting (materials inline, drivers, world, clips); it is
    // written beside nothing the user has, then read back and removed.
    std::error_code ec;
    const fs::path scratch = fs::temp_directory_path(ec) / ("softtouch-key-" + std::to_string(::getpid()) + ".softtouch");
    if (Status s = saveProject(project, scratch); !s)
        return s;
    std::ifstream in(scratch, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fs::remove(scratch, ec);
    hash.add(text);
    // What the file only names: each mesh and its animation.
    for (const SceneObject& object : project.scene.objects) {
        hash.add(object.mesh->positions);
        hash.add(object.mesh->triangles);
        if (object.baseAnimation) {
            hash.add(&object.baseAnimation->start, sizeof(double));
            hash.add(&object.baseAnimation->rate, sizeof(double));
            for (const std::vector<Vec3f>& sample : object.baseAnimation->samples)
                hash.add(sample);
        }
    }
    // The clip itself (the default clip or the drivers are not in the file by name) and the ladder.
    hash.add(clip.name);
    hash.add(std::string(clipSourceName(clip.source)) + " " + clip.sourceName);
    hash.add(&clip.startSeconds, sizeof(double));
    hash.add(&clip.frames, sizeof(int));
    hash.add(&clip.fps, sizeof(double));
    const std::uint8_t loop = clip.loop;
    hash.add(&loop, sizeof loop);
    hash.add(&clip.blendFrames, sizeof(int));
    hash.add(options.nodes);
    hash.add(&options.dt, sizeof(double));
    char key[17];
    std::snprintf(key, sizeof key, "%016llx", static_cast<unsigned long long>(hash.value));
    return std::string(key);
}

KeptReference findKeptReference(const fs::path& folder, const Project& project, const std::string& clipName,
                                std::span<const analysis::ReferenceOptions> ladders) {
    KeptReference kept;
    const auto clip = analysis::clipToPlay(project.scene, project.clips, clipName);
    if (!clip)
        return kept;
    for (const analysis::ReferenceOptions& ladder : ladders) {
        auto key = referenceKey(project, clip.value(), ladder);
        if (!key)
            return {};
        kept.key = key.value();
        if ((kept.reference = readCachedReference(folder, kept.key)))
            break;
    }
    return kept;
}

std::shared_ptr<const analysis::ConvergedReference> readCachedReference(const fs::path& folder, const std::string& key) {
    std::ifstream in(fileFor(folder, key), std::ios::binary);
    if (!in)
        return nullptr;
    Reader r(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()));
    if (r.text() != key)
        return nullptr;
    auto reference = std::make_shared<analysis::ConvergedReference>();
    const auto levels = r.get<std::uint64_t>();
    if (!r.good() || levels > kMaxLevels)
        return nullptr;
    for (std::uint64_t i = 0; i < levels && r.good(); ++i) {
        analysis::ReferenceLevel level;
        level.what = r.text();
        level.change = r.get<double>();
        level.seconds = r.get<double>();
        reference->levels.push_back(level);
    }
    reference->uncertainty = r.get<double>();
    reference->spaceUncertainty = r.get<double>();
    reference->timeUncertainty = r.get<double>();
    reference->dt = r.get<double>();
    reference->spaceConverging = r.get<std::uint8_t>() != 0;
    reference->description = r.text();
    reference->frames.frames = r.get<std::int32_t>();
    const auto objects = r.get<std::uint64_t>();
    if (!r.good() || objects > kMaxObjects || reference->frames.frames < 1)
        return nullptr;
    for (std::uint64_t i = 0; i < objects && r.good(); ++i)
        reference->frames.positions.push_back(r.points());
    if (!r.ok())
        return nullptr;
    return reference;
}

Status writeCachedReference(const fs::path& folder, const std::string& key, const analysis::ConvergedReference& reference) {
    std::error_code ec;
    fs::create_directories(folder, ec);
    if (ec)
        return Status::error("cannot make the reference cache folder '" + folder.string() + "': " + ec.message());
    Writer w;
    w.put(key);
    w.put(std::uint64_t(reference.levels.size()));
    for (const analysis::ReferenceLevel& level : reference.levels) {
        w.put(level.what);
        w.put(level.change);
        w.put(level.seconds);
    }
    w.put(reference.uncertainty);
    w.put(reference.spaceUncertainty);
    w.put(reference.timeUncertainty);
    w.put(reference.dt);
    w.put(std::uint8_t(reference.spaceConverging));
    w.put(reference.description);
    w.put(std::int32_t(reference.frames.frames));
    w.put(std::uint64_t(reference.frames.positions.size()));
    for (const std::vector<Vec3f>& object : reference.frames.positions)
        w.put(object);
    return writeFileAtomically(fileFor(folder, key), w.bytes());
}

}  // namespace softtouch::io

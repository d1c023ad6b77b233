#pragma once
/// What a project (*.softtouch) and a preset (*.stpreset) share: the header check, a lattice, its
/// material with painted per-node maps, anchors and voids, and drivers. Each reader sits beside its
/// writer in document_json.cpp, so a key's two sides are read together. Internal to io/.

#include "core/animation/drivers.h"
#include "core/base/result.h"
#include "core/body/lattice_body.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"
#include "io/files/json_reader.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <vector>

namespace softtouch::io::document {

inline constexpr const char* kProjectFormat = "softtouch-project";
inline constexpr const char* kPresetFormat = "softtouch-preset";

/// Parses the file at `path` and hands the document to `read(doc, path, issues)`, which returns an
/// optional T: how projects and presets are loaded (each file parsed once; the failure is the issues'
/// summary: the first problem and how many more).
template <typename T, typename Read>
Result<T> loadDocument(const std::filesystem::path& path, Read read) {
    JsonIssues issues(path.string());
    if (const auto doc = parseJsonFile(path.string(), issues))
        if (std::optional<T> value = read(*doc, path, issues))
            return std::move(*value);
    return Status::error(issues.summary());
}

/// A preset file's kind: a setup preset says "kind": "setup"; a material preset has no kind.
bool declaresSetup(const nlohmann::json& doc);
/// Checks "format" and "version" of a document.
bool readHeader(const JsonValue& root, const char* format, int maxVersion);

/// Nodes selected by {"nodes": [[i,j,k],…]} or {"region": {"min": [u,v,w], "max": [u,v,w]}}.
std::vector<int> readNodeSelection(const JsonValue& v, const Lattice& lattice);
/// An "anchors" array: groups of nodes (by list or region) with a mode, pinned or heavy.
void readAnchors(const JsonValue& anchors, const Lattice& lattice, std::vector<AnchorMode>& out);

/// Applies a "material" object onto `m`. `totalMass` is returned for spreading once voids are known.
void readMaterial(const JsonValue& v, LatticeMaterial& m, std::optional<double>& totalMass, bool allowPreset,
                  const std::filesystem::path& baseDir);
/// A "totalMass" spread evenly over the non-void nodes (once voids are known).
void spreadTotalMass(const Lattice& lattice, LatticeMaterial& material, const std::optional<double>& totalMass);
/// The material, anchors and voids of a lattice as a project object writes them.
void writeMaterial(const Lattice& lattice, const LatticeMaterial& m, nlohmann::json& object);

/// An object's "lattice": kind, nodes per axis and its box (or fitted around `mesh`).
std::optional<Lattice> readLattice(const JsonValue& v, const Mesh& mesh);
/// [x, y, z].
nlohmann::json vec(const Vec3& v);
/// A lattice as written: kind, nodes per axis and its box.
nlohmann::json latticeJson(const LatticeShape& shape, const OrientedBox& box);

/// A "drivers" array, each driver validated.
void readDrivers(const JsonValue& drivers, std::vector<Driver>& out);
nlohmann::json driverJson(const Driver& driver);

}  // namespace softtouch::io::document

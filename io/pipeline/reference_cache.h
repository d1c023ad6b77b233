#pragma once
/// Converged references kept between studies (analysis/converged_reference.h): the solid's runs take
/// minutes, and a second study of the same scene and clip, or a re-measure after a pick, needs the same
/// one. A reference is stored under a key made of everything it depends on: the project as it would be
/// saved (material, drivers, world, clips), each object's mesh and base animation, the clip, how the
/// reference is made, and the SoftTouch version. Anything changed makes a new key; nothing is ever read
/// for a scene it was not made for.

#include "analysis/converged_reference.h"
#include "io/documents/project_file.h"

#include <filesystem>
#include <memory>
#include <span>
#include <string>

namespace softtouch::io {

/// $XDG_CACHE_HOME/softtouch/references, or ~/.cache/softtouch/references.
std::filesystem::path referenceCacheFolder();

/// The key of the reference of `clip` of `project` made with `options` (16 hex digits).
Result<std::string> referenceKey(const Project& project, const Clip& clip, const analysis::ReferenceOptions& options);

/// The reference stored in `folder` under `key`; nullptr when there is none or it cannot be read (a
/// damaged file is made again, not trusted).
std::shared_ptr<const analysis::ConvergedReference> readCachedReference(const std::filesystem::path& folder,
                                                                        const std::string& key);

/// A study's reference looked up in `folder` for the clip a study of `project` plays (`clipName`; empty: what
/// `bake` plays), trying `ladders` in order: the first one kept, and its key; when none is kept, the last ladder's
/// key, under which the reference the study then makes is kept. Both empty when there is no such clip.
struct KeptReference {
    std::shared_ptr<const analysis::ConvergedReference> reference;
    std::string key;
};
KeptReference findKeptReference(const std::filesystem::path& folder, const Project& project, const std::string& clipName,
                                std::span<const analysis::ReferenceOptions> ladders);

/// Stores `reference` in `folder` under `key` (written atomically; the folder is made when missing).
Status writeCachedReference(const std::filesystem::path& folder, const std::string& key,
                            const analysis::ConvergedReference& reference);

}  // namespace softtouch::io

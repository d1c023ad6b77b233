#pragma once
/// Version 2 of the project file: the clip library (clips, sessions, keyframe sets) as a project's three
/// top-level members, and the drivers clips a setup preset carries. Reader beside writer in
/// clip_library_json.cpp. Internal to io/.

#include "core/authoring/clip.h"
#include "io/documents/project_file.h"
#include "io/files/json_reader.h"

#include <nlohmann/json.hpp>

#include <optional>

namespace softtouch::io::document {

/// The project's "sessions", "keyframes" and "clips" (version >= 2), validated against its scene.
void readClipLibrary(const JsonValue& root, int version, Project& project);
/// The clip library as its three top-level members (nlohmann writes doubles with 17 significant
/// digits, so session states read back bit for bit and replays stay exact).
void writeClipLibrary(const ClipLibrary& lib, nlohmann::json& doc);
/// One clip.
std::optional<Clip> readClip(const JsonValue& v);
nlohmann::json clipJson(const Clip& c);

}  // namespace softtouch::io::document

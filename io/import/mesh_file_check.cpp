#include "io/import/mesh_file_check.h"

#include <cctype>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace softtouch::io {
namespace {

/// Bytes of one PLY scalar type (0 when unknown).
int plyTypeBytes(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
        return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
        return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
        return 4;
    if (type == "double" || type == "float64")
        return 8;
    return 0;
}

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::uint64_t minBytes = 0; ///< Binary: the fixed properties plus each list's count field.
};

Status checkPly(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line, format;
    std::vector<PlyElement> elements;
    std::uint64_t headerBytes = 0;
    int lineNumber = 0;
    // Only what the PLY format declares, in its order: "ply", "format F 1.0", then elements with their
    // properties, comments and obj_info, then "end_header". Anything else is refused here: assimp 5.2
    // loops for ever on some malformed headers (fuzz_mesh: a misspelt "elemnet" line), and a header
    // SoftTouch cannot read is a file it should not guess at.
    auto malformed = [&](const std::string& why) {
        return Status::error("its PLY header line " + std::to_string(lineNumber) + " ('" + line.substr(0, 80) + "') " + why);
    };
    // A PLY header is a few hundred bytes; stop reading it at 64 KiB.
    while (headerBytes < 65536 && std::getline(in, line)) {
        headerBytes += line.size() + 1;
        ++lineNumber;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        std::istringstream words(line);
        std::string keyword, extra;
        words >> keyword;
        if (lineNumber == 1) {
            if ((keyword != "ply" && keyword != "PLY") || (words >> extra))
                return malformed("is not 'ply'");
        } else if (keyword == "format") {
            std::string version;
            words >> format >> version;
            if (lineNumber != 2 || (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") ||
                version != "1.0" || (words >> extra))
                return malformed("is not 'format ascii|binary_little_endian|binary_big_endian 1.0' on line 2");
        } else if (keyword == "comment" || keyword == "obj_info") {
        } else if (keyword == "element") {
            PlyElement e;
            long double count = -1;
            words >> e.name >> count;
            if (!words || count < 0 || count > 1e15L || (words >> extra))
                return Status::error("its PLY header has an element line it cannot read: '" + line + "'");
            e.count = std::uint64_t(count);
            elements.push_back(e);
        } else if (keyword == "property") {
            if (elements.empty())
                return malformed("declares a property before any element");
            std::string type, name;
            words >> type;
            if (type == "list") {
                std::string countType, itemType;
                words >> countType >> itemType >> name;
                const bool integer = countType.find("int") != std::string::npos || countType.find("char") != std::string::npos ||
                                     countType.find("short") != std::string::npos;
                if (!integer || plyTypeBytes(countType) == 0 || plyTypeBytes(itemType) == 0 || name.empty() || (words >> extra))
                    return malformed("is not 'property list COUNT-TYPE ITEM-TYPE NAME' with PLY types");
                elements.back().minBytes += std::uint64_t(plyTypeBytes(countType));
            } else {
                words >> name;
                if (plyTypeBytes(type) == 0 || name.empty() || (words >> extra))
                    return malformed("is not 'property TYPE NAME' with a PLY type");
                elements.back().minBytes += std::uint64_t(plyTypeBytes(type));
            }
        } else if (keyword == "end_header") {
            if (format.empty())
                return malformed("ends the header before any 'format' line");
            break;
        } else {
            return malformed("is not one the PLY format declares (format, element, property, comment, obj_info, end_header)");
        }
    }
    if (line != "end_header") {
        // A file that starts as a PLY but whose header never ends: assimp 5.2 reads past the buffer on it.
        if (!elements.empty() || !format.empty())
            return Status::error("its PLY header has no end_header line within its first 64 KiB: it is cut or corrupt");
        return Status::success();  // not a PLY header at all; assimp reports it
    }
    std::uint64_t announced = 0;
    for (const PlyElement& e : elements)
        announced += e.count;
    std::ostringstream what;  // "elements 2000000000 vertex, 1 face"
    what << "elements";
    for (std::size_t i = 0; i < elements.size(); ++i)
        what << (i ? ", " : " ") << elements[i].count << " " << elements[i].name;
    if (format == "ascii") {
        // One element per line; count the body's non-empty lines (stopping once there are enough).
        std::uint64_t lines = 0;
        while (lines < announced && std::getline(in, line))
            if (line.find_first_not_of(" \t\r") != std::string::npos)
                ++lines;
        if (lines < announced)
            return Status::error("its PLY header announces " + what.str() + " (" + std::to_string(announced) +
                                 " lines) but the file holds " + std::to_string(lines) + ": it is truncated");
        return Status::success();
    }
    std::uint64_t needed = 0;
    for (const PlyElement& e : elements) {
        if (e.minBytes > 0 && e.count > (UINT64_MAX - needed) / e.minBytes)
            return Status::error("its PLY header announces " + what.str() + ", more than any file holds");
        needed += e.count * e.minBytes;
    }
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (!ec && needed > size - std::min(size, headerBytes))
        return Status::error("its PLY header announces " + what.str() + ", at least " + std::to_string(needed) +
                             " bytes, but the file holds " + std::to_string(size - std::min(size, headerBytes)) +
                             " after its header: it is truncated");
    return Status::success();
}

std::uint32_t littleU32(const unsigned char* b) {
    return std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
}

Status checkGlb(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char header[20] = {};
    in.read(reinterpret_cast<char*>(header), sizeof header);
    if (in.gcount() < 12 || std::string(reinterpret_cast<char*>(header), 4) != "glTF")
        return Status::success();  // not binary glTF; assimp reports it
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    const std::uint64_t stated = littleU32(header + 8);
    if (!ec && stated > size)
        return Status::error("its GLB header states " + std::to_string(stated) + " bytes but the file holds " +
                             std::to_string(size) + ": it is truncated");
    if (in.gcount() == 20 && !ec && 20 + std::uint64_t(littleU32(header + 12)) > size)
        return Status::error("its GLB JSON chunk states " + std::to_string(littleU32(header + 12)) +
                             " bytes but the file holds " + std::to_string(size) + ": it is truncated");
    return Status::success();
}

/// A cut OBJ ends in the middle of a line: a face with fewer than three corners or a vertex with fewer
/// than three coordinates, and no line break (a whole file may lack the final break, but not mid-element).
Status checkObjEnd(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in.tellg();
    const std::streamoff tail = std::min<std::streamoff>(size, 4096);
    std::string text(std::size_t(tail), '\0');
    in.seekg(size - tail);
    in.read(text.data(), tail);
    if (text.empty() || text.back() == '\n')
        return Status::success();
    const std::string last = text.substr(text.find_last_of('\n') == std::string::npos ? 0 : text.find_last_of('\n') + 1);
    std::istringstream words(last);
    std::string keyword, word;
    words >> keyword;
    int count = 0;
    while (words >> word)
        ++count;
    if ((keyword == "f" && count < 3) || (keyword == "v" && count < 3) || (keyword == "vn" && count < 3))
        return Status::error("its last line '" + last + "' is cut off: the file is truncated");
    return Status::success();
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

Status checkMeshFileIsWhole(const std::filesystem::path& path) {
    // By content first: assimp tries every importer whose signature matches, whatever the extension
    // (a PLY named .gltf is read as PLY).
    char magic[4] = {};
    std::ifstream(path, std::ios::binary).read(magic, sizeof magic);
    // Any capitalisation: assimp's PLY reader takes a file named .ply whatever its first line says, and
    // looped on a "Ply" header (fuzz_mesh); the strict check below then names what is wrong.
    std::string start(magic, 3);
    for (char& c : start)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    if (start == "ply")
        return checkPly(path);
    if (std::string(magic, 4) == "glTF")
        return checkGlb(path);
    if (lowerExtension(path) == ".obj")
        return checkObjEnd(path);
    return Status::success();
}

}  // namespace softtouch::io

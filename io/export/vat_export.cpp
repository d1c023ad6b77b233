// Vertex animation textures (VAT): two half-float OpenEXR images and a JSON sidecar, plus the rest
// mesh as GLB with the texture lookup in a UV channel, the layout Unity and Unreal VAT shaders
// sample (docs/formats.md, "Vertex animation textures", is the reference).
//
//   <base>.vat-position.exr  RGB half: position offset from the rest pose (metres, raw, not normalised)
//   <base>.vat-normal.exr    RGB half: unit normal (raw components in [-1, 1])
//   <base>.vat-mesh.glb      rest mesh: POSITION, NORMAL, indices,
//                            TEXCOORD_0 = (vertex index, 0), TEXCOORD_1 = lookup UV of frame 0
//   <base>.vat.json          frame count, fps, texture size, rows per frame, offset bounds, layout
//
// Texture layout: width = min(vertices, vatMaxWidth) texels; a frame takes rowsPerFrame =
// ceil(vertices / width) rows; vertex i of frame f is texel (i % width, f * rowsPerFrame + i / width),
// row 0 being the EXR's first scanline (frame 0 at the top). Unused texels of a frame's last row are 0.
//
// Streaming: one frame's rows are converted to half and handed to OpenEXR, which writes them to a
// staged temporary (scanline files, increasing y); nothing else is kept but the running bounds.

#include "io/export/clip_writer_internal.h"
#include "io/export/vertex_cache_internal.h"

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <ImfHeader.h>
#include <ImfRgbaFile.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>

namespace softtouch::io {

namespace detail {

/// The files of a VAT export to the base path `path`, the JSON last: a reader that finds it finds the
/// textures and mesh it describes.
std::vector<std::filesystem::path> vatFiles(const std::filesystem::path& path, std::size_t) {
    const auto with = [&](const char* suffix) { return std::filesystem::path(path) += suffix; };
    return {with(".vat-position.exr"), with(".vat-normal.exr"), with(".vat-mesh.glb"), with(".vat.json")};
}

}  // namespace detail

namespace {

/// Largest finite half float.
constexpr float kHalfMax = 65504.0f;
/// Texture side above which Unity and Unreal refuse or downscale textures.
constexpr int kEngineTextureLimit = 16384;

class VatWriter final : public ClipWriter {
public:
    explicit VatWriter(const ClipExportOptions& options) : m_options(options) {}
    ~VatWriter() override { abort(); }

    Status begin(const std::filesystem::path& path, const ClipSetup& setup) override {
        abort();
        m_warnings.clear();
        if (Status s = detail::checkCacheInfo(path, setup.info); !s)
            return s;
        const std::vector<std::filesystem::path> outputs = detail::vatFiles(path, setup.info.frameCount);
        if (m_options.vatMaxWidth < 1 || m_options.vatMaxWidth > 16384)
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": the VAT width limit must be in [1, 16384], got " +
                                 std::to_string(m_options.vatMaxWidth));
        if (setup.restMesh.positions.size() != setup.info.pointCount ||
            setup.restMesh.normals.size() != setup.info.pointCount)
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": the rest mesh has " +
                                 std::to_string(setup.restMesh.positions.size()) + " positions and " +
                                 std::to_string(setup.restMesh.normals.size()) + " normals, expected " +
                                 std::to_string(setup.info.pointCount) + " of each");
        const std::size_t width = std::min<std::size_t>(setup.info.pointCount, std::size_t(m_options.vatMaxWidth));
        const std::size_t rows = (setup.info.pointCount + width - 1) / width;
        const std::size_t height = rows * setup.info.frameCount;
        if (setup.info.pointCount > (std::size_t(1) << 24))
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": " +
                                 std::to_string(setup.info.pointCount) +
                                 " vertices; the mesh stores vertex indices as float, exact up to 2^24");
        if (height > std::size_t(std::numeric_limits<int>::max()))
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": " + std::to_string(height) +
                                 " rows do not fit an EXR image");
        for (const auto& output : outputs) {
            if (Status s = detail::checkWritable(output); !s)
                return s;
        }
        if (height > std::size_t(kEngineTextureLimit))
            m_warnings.push_back(detail::quoted(outputs[0]) + ": the textures are " + std::to_string(width) + " x " +
                                 std::to_string(height) + " texels; Unity and Unreal take at most " +
                                 std::to_string(kEngineTextureLimit) + " per side: bake fewer frames");
        m_path = path;
        m_setup = setup;
        m_width = width;
        m_rows = rows;
        m_height = height;
        for (const auto& output : outputs)
            m_files.push_back(std::make_unique<detail::StagedFile>(output));
        try {
            Imf::Header header(static_cast<int>(width), static_cast<int>(height));
            header.compression() = Imf::ZIP_COMPRESSION;  // lossless; ZIP's 16-line blocks suit a frame of rows
            header.lineOrder() = Imf::INCREASING_Y;
            m_position.emplace(m_files[0]->temporary().c_str(), header, Imf::WRITE_RGB, 1);
            m_normal.emplace(m_files[1]->temporary().c_str(), header, Imf::WRITE_RGB, 1);
        } catch (const std::exception& e) {
            abort();
            return Status::error("cannot write " + detail::quoted(outputs[0]) + ": OpenEXR: " + e.what());
        }
        m_pixels.assign(width * rows, Imf::Rgba(0.0f, 0.0f, 0.0f, 1.0f));
        m_lo = Vec3f::Constant(std::numeric_limits<float>::max());
        m_hi = -m_lo;
        m_framesWritten = 0;
        return Status::success();
    }

    Status writeFrame(const FrameData& frame) override {
        if (!m_position)
            return Status::error("no VAT is being written: begin() was not called or the write failed");
        if (Status s = checkFrameData(m_path, m_framesWritten, m_setup, frame, true, false); !s) {
            abort();
            return s;
        }
        const std::vector<Vec3f>& rest = m_setup.restMesh.positions;
        for (std::size_t v = 0; v < rest.size(); ++v) {
            const Vec3f offset = frame.positions[v] - rest[v];
            if (offset.cwiseAbs().maxCoeff() > kHalfMax) {
                Status s = Status::error("frame " + std::to_string(m_framesWritten) + " vertex " + std::to_string(v) +
                                         " moved " + detail::formatNumber(offset.cwiseAbs().maxCoeff()) +
                                         " m from rest, beyond half float's 65504; nothing was written to " +
                                         detail::quoted(m_path));
                abort();
                return s;
            }
            m_lo = m_lo.cwiseMin(offset);
            m_hi = m_hi.cwiseMax(offset);
        }
        try {
            writeRows(*m_position, [&](std::size_t v) { return frame.positions[v] - rest[v]; });
            writeRows(*m_normal, [&](std::size_t v) { return frame.normals[v]; });
        } catch (const std::exception& e) {
            Status s = Status::error("cannot write " + detail::quoted(m_files[0]->target()) + ": OpenEXR: " + e.what());
            abort();
            return s;
        }
        ++m_framesWritten;
        return Status::success();
    }

    Status finish() override {
        if (!m_position)
            return Status::error("no VAT is being written: begin() was not called or the write failed");
        if (m_framesWritten != m_setup.info.frameCount) {
            Status s = detail::frameCountMismatch(m_path, m_framesWritten, m_setup.info.frameCount);
            abort();
            return s;
        }
        try {
            m_position.reset();  // the destructors write the line offset tables
            m_normal.reset();
        } catch (const std::exception& e) {
            Status s = Status::error("cannot write " + detail::quoted(m_files[0]->target()) + ": OpenEXR: " + e.what());
            abort();
            return s;
        }
        Result<std::string> mesh = meshBytes();
        if (!mesh) {
            abort();
            return Status::error(mesh.message());
        }
        if (Status s = m_files[2]->write(mesh.value()); !s) {
            abort();
            return s;
        }
        if (Status s = m_files[3]->write(sidecar().dump(2) + "\n"); !s) {
            abort();
            return s;
        }
        Status s = detail::publishAll(m_files);
        abort();
        return s;
    }

    void abort() override {
        // OpenEXR's destructors finish the staged files; they are removed right after.
        try {
            m_position.reset();
            m_normal.reset();
        } catch (const std::exception&) {
        }
        m_files.clear();
        m_pixels.clear();
        m_pixels.shrink_to_fit();
        m_framesWritten = 0;
    }

    bool needsNormals() const override { return true; }

private:
    /// Converts one frame to half texels and appends its rows.
    template <typename Value>
    void writeRows(Imf::RgbaOutputFile& file, Value value) {
        for (std::size_t v = 0; v < m_setup.info.pointCount; ++v) {
            const Vec3f x = value(v);
            m_pixels[v] = Imf::Rgba(x.x(), x.y(), x.z(), 1.0f);
        }
        // OpenEXR addresses a frame buffer by absolute row: base - firstRow * width is where row 0 would be.
        const auto firstRow = std::ptrdiff_t(m_framesWritten * m_rows);
        const auto width = std::ptrdiff_t(m_width);
        file.setFrameBuffer(m_pixels.data() - firstRow * width, 1, std::size_t(width));
        file.writePixels(int(m_rows));
    }

    /// The rest mesh with the lookup UVs, as GLB.
    Result<std::string> meshBytes() const {
        const Mesh& rest = m_setup.restMesh;
        const std::size_t n = rest.positions.size();
        std::vector<float> index(2 * n, 0.0f);
        std::vector<float> lookup(2 * n);
        for (std::size_t v = 0; v < n; ++v) {
            index[2 * v] = float(v);  // exact: begin() keeps vertices below 2^24
            lookup[2 * v] = float((double(v % m_width) + 0.5) / double(m_width));
            lookup[2 * v + 1] = float((double(v / m_width) + 0.5) / double(m_height));
        }
        tinygltf::Model model;
        model.asset.version = "2.0";
        model.asset.generator = "SoftTouch (vertex animation textures)";
        model.buffers.emplace_back();
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.attributes["POSITION"] = detail::addFloatAccessor(model, rest.positions.front().data(), n, 3, true, true);
        primitive.attributes["NORMAL"] = detail::addFloatAccessor(model, rest.normals.front().data(), n, 3, true, false);
        primitive.attributes["TEXCOORD_0"] = detail::addFloatAccessor(model, index.data(), n, 2, true, false);
        primitive.attributes["TEXCOORD_1"] = detail::addFloatAccessor(model, lookup.data(), n, 2, true, false);
        primitive.indices = detail::addIndexAccessor(model, rest.triangles, 0);
        tinygltf::Mesh mesh;
        mesh.name = "vat";
        mesh.primitives.push_back(primitive);
        model.meshes.push_back(mesh);
        tinygltf::Node node;
        node.mesh = 0;
        model.nodes.push_back(node);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);
        model.scenes.push_back(scene);
        model.defaultScene = 0;
        return detail::serializeGltf(model, true, m_files[2]->target());
    }

    nlohmann::json sidecar() const {
        auto vec = [](const Vec3f& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
        nlohmann::json j;
        j["format"] = "softtouch-vat";
        j["version"] = 1;
        j["frameCount"] = m_setup.info.frameCount;
        j["fps"] = m_setup.info.fps;
        j["vertexCount"] = m_setup.info.pointCount;
        j["textureWidth"] = m_width;
        j["textureHeight"] = m_height;
        j["rowsPerFrame"] = m_rows;
        j["positionTexture"] = m_files[0]->target().filename().string();
        j["normalTexture"] = m_files[1]->target().filename().string();
        j["mesh"] = m_files[2]->target().filename().string();
        j["positionEncoding"] = "offset";   // texel = position - rest position, metres
        j["normalEncoding"] = "unit";       // texel = unit normal, components in [-1, 1]
        j["normalised"] = false;            // raw half floats; bounds are for shaders that remap
        j["bounds"] = {{"min", vec(m_lo)}, {"max", vec(m_hi)}};
        j["vertexIndexUV"] = "TEXCOORD_0.x";
        j["lookupUV"] = "TEXCOORD_1";
        j["texelCentres"] = true;           // lookup = ((i % width) + 0.5) / width, ((i / width) + 0.5) / height
        j["vOrigin"] = "top";               // v = 0 is the first scanline (glTF's UV convention)
        j["frameRowStep"] = double(m_rows) / double(m_height);  // add frame * this to the lookup's v
        return j;
    }

    ClipExportOptions m_options;
    std::filesystem::path m_path;
    ClipSetup m_setup;                                   ///< Copied by begin().
    std::size_t m_width = 0;                             ///< Texels per row.
    std::size_t m_rows = 0;                              ///< Rows per frame.
    std::size_t m_height = 0;                            ///< Rows in all.
    std::vector<std::unique_ptr<detail::StagedFile>> m_files;  ///< position, normal, mesh, json.
    std::optional<Imf::RgbaOutputFile> m_position;       ///< Open between begin() and finish().
    std::optional<Imf::RgbaOutputFile> m_normal;
    std::vector<Imf::Rgba> m_pixels;                     ///< One frame's texels, reused.
    Vec3f m_lo = Vec3f::Zero();                          ///< Smallest offset so far (bounds.min).
    Vec3f m_hi = Vec3f::Zero();                          ///< Largest offset so far (bounds.max).
    std::size_t m_framesWritten = 0;
};

}  // namespace

namespace detail {

/// The "vat" export (io/export/export_formats.cpp).
std::unique_ptr<ClipWriter> makeVatExport(const std::filesystem::path&, const ClipExportOptions& options) {
    return std::make_unique<VatWriter>(options);
}

}  // namespace detail

}  // namespace softtouch::io

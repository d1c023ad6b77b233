#pragma once
// Reading back the GLBs the exporter writes, with tinygltf, for the suites that check them.

#include <tiny_gltf.h>

#include <QtGlobal>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace softtouch::test {

/// Loads a GLB with tinygltf; fails the test on error.
inline tinygltf::Model loadGlb(const std::filesystem::path& path) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string error, warning;
    if (!loader.LoadBinaryFromFile(&model, &error, &warning, path.string()))
        qFatal("cannot load %s: %s", path.string().c_str(), error.c_str());
    return model;
}

/// The floats of a tightly packed FLOAT accessor; fails the test on any other.
inline std::vector<float> accessorFloats(const tinygltf::Model& model, int index) {
    const tinygltf::Accessor& accessor = model.accessors.at(std::size_t(index));
    const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(accessor.bufferView));
    if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || view.byteStride != 0)
        qFatal("accessor %d is not tightly packed floats", index);
    const std::size_t components = std::size_t(tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type)));
    std::vector<float> out(accessor.count * components);
    std::memcpy(out.data(), model.buffers.at(std::size_t(view.buffer)).data.data() + view.byteOffset + accessor.byteOffset,
                out.size() * sizeof(float));
    return out;
}

}  // namespace softtouch::test

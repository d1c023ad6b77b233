#include "core/body/material_channels.h"

namespace softtouch {

std::span<const MaterialChannel> materialChannels() {
    return kMaterialChannels;
}

const MaterialChannel& materialChannel(MaterialChannelId id) {
    for (const MaterialChannel& channel : kMaterialChannels)
        if (channel.id == id)
            return channel;
    return kMaterialChannels.front(); // unreachable: every id has a row (test_io_material_channels)
}

std::vector<double>& channelValues(LatticeMaterial& material, const MaterialChannel& channel) {
    std::vector<double>& values = material.*channel.values;
    values.resize(material.mass.size(), 0.0);
    return values;
}

} // namespace softtouch

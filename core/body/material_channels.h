#pragma once
/// The per-node channels of a LatticeMaterial, declared once. Validation, resampling to another lattice, the
/// project reader and writer, material presets, the paint brush and the editor's list of painted values all
/// iterate this table, so a new painted channel is a member of LatticeMaterial, an id and a row here, and the
/// physics that reads it (tests/io/test_material_channels.cpp checks every row end to end, and that
/// every per-node member of LatticeMaterial has one).

#include "core/body/lattice_body.h"

#include <array>
#include <span>

namespace softtouch {

/// Which channel: the brush and the editor name channels by it.
enum class MaterialChannelId : std::uint8_t {
    Mass,
    Stiffness,
    Damping,            ///< Spring damping (relative velocity along a spring).
    NodeDamping,        ///< Node damping (each node's absolute velocity: the paper's D).
    VolumePreservation, ///< How stiffly the mesh's volume around the node is kept, [0, 1].
    GoalWeight, ///< How closely the node follows a base animation, [0, 1] (core/animation/base_motion.h).
};

/// How a lattice-springs channel's values change when its material moves to a lattice of another resolution
/// as the same continuum (resampleMaterial(..., keepContinuum = true)). A Continuum material's values are per
/// volume or per area already and never change.
enum class ChannelScaling : std::uint8_t {
    NodeVolume, ///< Per node, like a mass: times the ratio of one node's share of the box.
    Spacing,    ///< Per spring, like a spring constant: times the ratio of the node spacings.
    Fraction,   ///< A fraction in [0, 1]: the same on any lattice and under either model.
};

/// One per-node channel.
struct MaterialChannel {
    MaterialChannelId id;
    const char* member; ///< The member's name ("goalWeight"), for messages and checks.
    std::vector<double> LatticeMaterial::*values; ///< Its values, one per lattice node.
    /// Its range, key and unit under each model: a member of MaterialRanges (mass, stiffness and the dampings
    /// mean other things under each model), or one range for both (`range`, the fractions).
    MaterialRange MaterialRanges::*modelRange = nullptr;
    const MaterialRange* range = nullptr;
    /// What a new material holds on every node: a member of DefaultMaterialValues, or 0 (nullptr).
    double DefaultMaterialValues::*defaultValue = nullptr;
    ChannelScaling scaling = ChannelScaling::Fraction;
    /// May be empty, meaning 0 on every node (a material made before the channel existed); a project file
    /// carries it only where some node is not 0.
    bool optional = false;
    bool checkedOnVoidNodes = true; ///< False for mass: a void node has none, whatever the file says.
    bool inPresets = true; ///< Carried by material presets (as one value: the mean over solid nodes).
    bool needsBaseAnimation = false; ///< Acts only on an object that moves with a base animation.

    const MaterialRange& rangeFor(MaterialModel model) const {
        return modelRange ? materialRanges(model).*modelRange : *range;
    }
    double defaultFor(MaterialModel model) const {
        return defaultValue ? defaultMaterialValues(model).*defaultValue : 0.0;
    }
};

/// Every channel, in the order validation reports them and the editor lists them. A new channel: its id
/// above, its row here, its member in LatticeMaterial, and the physics that reads it.
inline constexpr auto kMaterialChannels = std::to_array<MaterialChannel>({
    {.id = MaterialChannelId::Mass,
     .member = "mass",
     .values = &LatticeMaterial::mass,
     .modelRange = &MaterialRanges::mass,
     .defaultValue = &DefaultMaterialValues::mass,
     .scaling = ChannelScaling::NodeVolume,
     .checkedOnVoidNodes = false},
    {.id = MaterialChannelId::Stiffness,
     .member = "stiffness",
     .values = &LatticeMaterial::stiffness,
     .modelRange = &MaterialRanges::stiffness,
     .defaultValue = &DefaultMaterialValues::stiffness,
     .scaling = ChannelScaling::Spacing},
    {.id = MaterialChannelId::Damping,
     .member = "damping",
     .values = &LatticeMaterial::damping,
     .modelRange = &MaterialRanges::damping,
     .defaultValue = &DefaultMaterialValues::damping,
     .scaling = ChannelScaling::Spacing},
    // N·s/m per node under lattice springs, so it moves with the node's share of the box as mass does.
    {.id = MaterialChannelId::NodeDamping,
     .member = "nodeDamping",
     .values = &LatticeMaterial::nodeDamping,
     .modelRange = &MaterialRanges::nodeDamping,
     .defaultValue = &DefaultMaterialValues::nodeDamping,
     .scaling = ChannelScaling::NodeVolume},
    {.id = MaterialChannelId::VolumePreservation,
     .member = "volumePreservation",
     .values = &LatticeMaterial::volumePreservation,
     .range = &kVolumePreservationRange,
     .optional = true},
    // How an object follows its own animation is the scene's, not the material's: presets leave it.
    {.id = MaterialChannelId::GoalWeight,
     .member = "goalWeight",
     .values = &LatticeMaterial::goalWeight,
     .range = &kGoalWeightRange,
     .optional = true,
     .inPresets = false,
     .needsBaseAnimation = true},
});

/// kMaterialChannels.
std::span<const MaterialChannel> materialChannels();
const MaterialChannel& materialChannel(MaterialChannelId id);

/// The channel's values in a material: an optional channel a material has none of is sized to its nodes first
/// (0 everywhere).
std::vector<double>& channelValues(LatticeMaterial& material, const MaterialChannel& channel);

} // namespace softtouch

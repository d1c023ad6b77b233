#pragma once
/// Painting per-node values (mass, stiffness, spring and node damping) with a screen-space brush, plus
/// the bulk edits of selected nodes (fill, smooth). Pure functions over the material, so the viewport, the
/// properties panel and the tests share one implementation.

#include "core/body/lattice_body.h"
#include "core/body/material_channels.h"

#include <Eigen/Core>
#include <span>
#include <utility>
#include <vector>

namespace softtouch::ui {

/// Which painted value a brush changes: a channel of the material (core/body/material_channels.h).
using PaintField = MaterialChannelId;

/// How a dab's effect fades from its centre to its rim.
enum class BrushFalloff { Constant, Linear, Smooth };

/// The painting brush.
struct BrushSettings {
    PaintField field = PaintField::Stiffness; ///< Value painted.
    double value = 160.0;                    ///< Target value in the field's unit (materialRanges()). > 0 for mass.
    double radiusPixels = 60.0;              ///< Screen radius, pixels. [1, 2000].
    double strength = 0.5;                   ///< Fraction of the way to the target per dab at the centre. [0, 1].
    BrushFalloff falloff = BrushFalloff::Smooth; ///< Fade towards the rim.
};

/// The per-node array of a field (an optional channel is sized to the nodes first when a material has none).
std::vector<double>& fieldValues(LatticeMaterial& material, PaintField field);
const std::vector<double>& fieldValues(const LatticeMaterial& material, PaintField field);
/// Human name and unit of a field under a material model ("stiffness", "N/m"; "Young's modulus", "Pa";
/// "node damping rate", "1/s").
const char* fieldName(PaintField field, MaterialModel model);
/// The field's range and unit under a material model (MaterialChannel::rangeFor()).
const MaterialRange& fieldRange(PaintField field, MaterialModel model);
/// What a brush or a typed value may set in the field: fieldRange(), with mass kept above 0 (every other
/// field may go down to its range's low end).
std::pair<double, double> paintableRange(PaintField field, MaterialModel model);
/// Volume preservation scaled so its largest node value is `p`, the painted ratios kept (a map of zeros
/// becomes `p` everywhere; p = 0 turns it off).
void setLargestVolumePreservation(LatticeMaterial& material, double p);
const char* fieldUnit(PaintField field, MaterialModel model);

/// Weight of a dab at `distance` pixels from its centre: 1 at the centre, 0 from the radius on.
double brushWeight(double distancePixels, const BrushSettings& brush);

/// One dab: each node within the radius (by its screen position) moves its value towards the target
/// by strength × falloff. Void nodes are skipped. Returns true when any value changed.
bool applyDab(LatticeMaterial& material, std::span<const Eigen::Vector2d> nodeScreen, const Eigen::Vector2d& centre,
              const BrushSettings& brush);

/// Sets the field of the given nodes to `value`.
void fillNodes(LatticeMaterial& material, PaintField field, std::span<const int> nodes, double value);

/// Moves the field of the given nodes halfway to the mean of their grid neighbours (6-connected).
void smoothNodes(LatticeMaterial& material, const Lattice& lattice, PaintField field, std::span<const int> nodes);

}  // namespace softtouch::ui

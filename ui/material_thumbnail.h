#pragma once
/// Preset thumbnails that show how a material behaves, not a colour: a block with the preset's
/// material, held at its left face like a diving board (or by its own anchors), droops under gravity; the thumbnail
/// draws the lattice at rest (light) and sagged (dark), so a jelly droops and stiff rubber barely moves.

#include "core/body/lattice_body.h"

#include <QImage>

namespace softtouch::ui {

/// Draws the thumbnail of `material` (per node of a lattice of `shape`; no anchors: the left face is
/// pinned) at `size` pixels. A material that cannot be built gives a grey image with a cross.
QImage materialThumbnail(const LatticeShape& shape, const LatticeMaterial& material, int size = 72);

}  // namespace softtouch::ui

#pragma once
/// A clip's vertex displacements compressed into a few morph targets: their mean plus the principal
/// components (PCA) of what is left, with per-frame weights, as a game engine plays them (position =
/// rest + mean + Σ_k w_fk · target_k). The number of components is the fewest that keep every frame's
/// RMS vertex error at or below a target, so the compression is chosen by accuracy, not guessed.

#include <cstddef>
#include <span>
#include <vector>

namespace softtouch {

/// The fitted basis. Vectors hold `values` floats (x, y, z per vertex); weights hold one row per frame.
struct MorphBasis {
    std::vector<float> mean;                    ///< The frames' mean displacement.
    std::vector<std::vector<float>> components; ///< K orthonormal directions scaled to metres, most important first.
    std::vector<std::vector<float>> weights;    ///< [frame][k], the weight of component k at that frame.
    double worstFrameRms = 0.0;                 ///< Largest per-frame RMS vertex error of the reconstruction, metres.
    double worstVertexError = 0.0;              ///< Largest distance of any vertex in any frame from the clip, metres.
};

/// Fits `frames` rows of `values` displacements each (row-major in `deltas`, x y z per vertex): the fewest
/// components (at most `maxComponents`, at most frames − 1) whose reconstruction's per-frame RMS vertex
/// error is at most `rmsTarget` metres, or `maxComponents` when none is enough (worstFrameRms then says
/// by how much it misses). O(frames² · values) for the frames' Gram matrix.
MorphBasis fitMorphBasis(std::span<const float> deltas, std::size_t frames, std::size_t values, double rmsTarget,
                         std::size_t maxComponents);

/// The weights of `basis`'s components that best reproduce another set of per-frame vectors of the same
/// frames (normal displacements beside position ones): the same weights, with components fitted by least
/// squares (the weights' columns are orthogonal, so each is a projection). Returns mean and components.
MorphBasis fitMorphComponentsFor(const MorphBasis& basis, std::span<const float> deltas, std::size_t frames,
                                 std::size_t values);

}  // namespace softtouch

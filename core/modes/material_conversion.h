#pragma once
/// Carrying a project's lattice-springs material (values per node and spring of one lattice) over to
/// a Continuum material (values of the solid) that moves the same way on that lattice, so that it then
/// keeps its meaning when the lattice changes.

#include "core/base/result.h"
#include "core/body/lattice_body.h"
#include "core/modes/modes.h"

namespace softtouch {

/// What continuumEquivalent() kept: the lowest modes before and after.
struct MaterialConversion {
    LatticeMaterial material;          ///< The Continuum material.
    std::vector<VibrationMode> before; ///< Lowest modes of the lattice-springs material (up to 3).
    std::vector<VibrationMode> after;  ///< The same modes of the Continuum material.
};

/// The Continuum material equivalent to `springs` on `lattice`. Painted maps keep their ratios to
/// their mean; the means are chosen so that the body keeps its total mass, its lowest mode's frequency
/// and that mode's two damping ratios (node and spring). Higher modes move by what the two models'
/// different spring coefficients make of them (reported in `after`). A Continuum input is returned
/// unchanged. Fails when the body has no elastic mode to keep (every node pinned) or is too large for
/// the modal analysis.
Result<MaterialConversion> continuumEquivalent(const Lattice& lattice, const LatticeMaterial& springs);

}  // namespace softtouch

#include "core/modes/material_conversion.h"

namespace softtouch {

namespace {

Result<ModalAnalysis> modesOf(const Lattice& lattice, const LatticeMaterial& material) {
    auto body = buildLatticeBody(lattice, material);
    if (!body)
        return Status::error(body.message());
    auto modes = analyseModes(*body.value(), 3);
    if (modes && modes->modes.empty())
        return Status::error("the body has no elastic mode (every node is pinned or void)");
    return modes;
}

/// Values divided by their solid mean (all ones when the mean is 0).
std::vector<double> relative(const std::vector<double>& values, const LatticeMaterial& m) {
    const double mean = solidMean(values, m);
    std::vector<double> out(values.size(), 1.0);
    if (mean > 0.0)
        for (std::size_t n = 0; n < values.size(); ++n)
            out[n] = values[n] / mean;
    return out;
}

}  // namespace

Result<MaterialConversion> continuumEquivalent(const Lattice& lattice, const LatticeMaterial& springs) {
    auto before = modesOf(lattice, springs);
    if (!before)
        return Status::error(before.message());
    MaterialConversion out;
    out.before = before->modes;
    if (springs.model == MaterialModel::Continuum) {
        out.material = springs;
        out.after = before->modes;
        return out;
    }
    LatticeMaterial m = springs;
    m.model = MaterialModel::Continuum;
    // Mass: the painted ratios, scaled so the solid nodes weigh what they weighed.
    const std::vector<double> volume = nodeVolumes(lattice);
    m.mass = relative(springs.mass, springs);
    double total = 0.0, weighed = 0.0;
    for (std::size_t n = 0; n < m.mass.size(); ++n) {
        if (springs.isVoid[n])
            continue;
        total += springs.mass[n];
        weighed += m.mass[n] * volume[n];
    }
    for (double& rho : m.mass)
        rho *= total / weighed;
    // Stiffness and damping: ratios at unit scale, then one factor each from the lowest mode. K is
    // linear in the modulus (ω² ∝ E), the node term's ζ in the rate, the spring term's ζ in viscosity.
    m.stiffness = relative(springs.stiffness, springs);
    const bool springDamping = solidMean(springs.damping, springs) > 0.0;
    m.damping = springDamping ? relative(springs.damping, springs) : std::vector<double>(m.mass.size(), 0.0);
    // Node damping: the painted map's ratios become the rates' ratios (a uniform map, every project
    // before node damping was painted, stays a uniform rate), scaled below to keep the node ζ.
    const bool nodeDamping = solidMean(springs.nodeDamping, springs) > 0.0;
    m.nodeDamping = nodeDamping ? relative(springs.nodeDamping, springs) : std::vector<double>(m.mass.size(), 0.0);
    const VibrationMode& target = out.before.front();
    for (int pass = 0; pass < 2; ++pass) {  // the second pass only checks the scale landed (linear)
        auto now = modesOf(lattice, m);
        if (!now)
            return Status::error(now.message());
        const VibrationMode& mode = now->modes.front();
        const double ratio = target.frequencyHz / mode.frequencyHz;
        for (double& e : m.stiffness)
            e *= ratio * ratio;
        // For fixed damping ζ scales as 1/ω: the new ω is ratio times the old.
        if (nodeDamping && mode.nodeDampingRatio > 0.0)
            for (double& gamma : m.nodeDamping)
                gamma *= target.nodeDampingRatio * ratio / mode.nodeDampingRatio;
        if (springDamping && mode.springDampingRatio > 0.0)
            for (double& c : m.damping)
                c *= target.springDampingRatio * ratio / mode.springDampingRatio;
    }
    auto after = modesOf(lattice, m);
    if (!after)
        return Status::error(after.message());
    out.material = std::move(m);
    out.after = after->modes;
    return out;
}

}  // namespace softtouch

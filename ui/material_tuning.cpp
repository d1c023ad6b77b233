#include "ui/material_tuning.h"

#include <cmath>

namespace softtouch::ui {

namespace {
std::optional<VibrationMode> lowestMode(const Lattice& lattice, const LatticeMaterial& material,
                                       const FollowSettings* follow) {
    auto modes = materialModes(lattice, material, 1, follow);
    if (!modes || modes->modes.empty())
        return std::nullopt;
    return modes->modes.front();
}

void scaleDamping(LatticeMaterial& material, double factor) {
    for (double& c : material.damping)
        c *= factor;
    for (double& d : material.nodeDamping)
        d *= factor;
}
}  // namespace

MaterialSummary summarise(const Lattice& lattice, const LatticeMaterial& material) {
    MaterialSummary s;
    s.meanMass = solidMean(material.mass, material);
    s.meanStiffness = solidMean(material.stiffness, material);
    s.meanDamping = solidMean(material.damping, material);
    s.meanNodeDamping = solidMean(material.nodeDamping, material);
    const std::vector<double> kg = nodeMasses(lattice, material);
    for (std::size_t n = 0; n < kg.size(); ++n)
        s.totalMass += material.isVoid[n] ? 0.0 : kg[n];
    return s;
}

Result<ModalAnalysis> materialModes(const Lattice& lattice, const LatticeMaterial& material, int count,
                                    const FollowSettings* follow) {
    return objectModes(lattice, material, follow, count);
}

void setMean(std::vector<double>& values, const LatticeMaterial& material, double mean) {
    const double current = solidMean(values, material);
    if (current > 0.0) {
        for (double& v : values)
            v *= mean / current;
    } else {
        values.assign(values.size(), mean);
    }
}

bool setFrequency(const Lattice& lattice, LatticeMaterial& material, double hz, const FollowSettings* follow) {
    auto mode = lowestMode(lattice, material, follow);
    if (!mode || hz <= 0.0)
        return false;
    // Springs alone: every stiffness × (f'/f)² keeps the shapes, so one step lands exactly. With goal
    // springs the shape moves with the scale: repeat while more than 0.1% off (at most 8 steps). A mode the
    // goal springs make (a body on uniform goals swings on them at their frequency, whatever its material)
    // cannot be moved this way: the material is left as it was.
    const LatticeMaterial before = material;
    for (int step = 0; step < (follow ? 8 : 1); ++step) {
        const double ratio = hz / mode->frequencyHz;
        for (double& k : material.stiffness)
            k *= ratio * ratio;
        // ζ = φᵀCφ / 2ω with φ unchanged: scaling C with ω keeps every damping ratio.
        scaleDamping(material, ratio);
        if (!follow)
            return true;
        if (!(mode = lowestMode(lattice, material, follow)))
            break;
        if (std::abs(mode->frequencyHz / hz - 1.0) < 1e-3)
            return true;
    }
    material = before;
    return false;
}

bool setDampingRatio(const Lattice& lattice, LatticeMaterial& material, double ratio, const FollowSettings* follow) {
    auto mode = lowestMode(lattice, material, follow);
    if (!mode || ratio < 0.0)
        return false;
    if (mode->dampingRatio <= 0.0) {
        if (ratio == 0.0)
            return true;
        // Nothing to scale: start from the paper's node damping at a unit rate (1/s).
        const double start = material.model == MaterialModel::Continuum ? 1.0 : summarise(lattice, material).meanMass;
        material.nodeDamping.assign(material.nodeDamping.size(), start);
        mode = lowestMode(lattice, material, follow);
        if (!mode || mode->dampingRatio <= 0.0)
            return false;
    }
    scaleDamping(material, ratio / mode->dampingRatio);
    return true;
}

}  // namespace softtouch::ui

#include "ui/material_tuning.h"

#include <cmath>
#include <numbers>

namespace softtouch::ui {

namespace {
double meanOf(const std::vector<double>& values, const LatticeMaterial& m) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        if (!m.isVoid[n]) {
            sum += values[n];
            ++count;
        }
    }
    return count > 0 ? sum / count : 0.0;
}
}  // namespace

MaterialSummary summarise(const LatticeMaterial& material) {
    MaterialSummary s;
    s.meanMass = meanOf(material.mass, material);
    s.meanStiffness = meanOf(material.stiffness, material);
    s.meanDamping = meanOf(material.damping, material);
    for (std::size_t n = 0; n < material.mass.size(); ++n)
        s.totalMass += material.isVoid[n] ? 0.0 : material.mass[n];
    if (s.meanMass > 0.0 && s.meanStiffness > 0.0) {
        s.frequencyHz = std::sqrt(s.meanStiffness / s.meanMass) / (2.0 * std::numbers::pi);
        s.dampingRatio = s.meanDamping / (2.0 * std::sqrt(s.meanStiffness * s.meanMass));
    }
    return s;
}

void setMean(std::vector<double>& values, const LatticeMaterial& material, double mean) {
    const double current = meanOf(values, material);
    if (current > 0.0) {
        for (double& v : values)
            v *= mean / current;
    } else {
        values.assign(values.size(), mean);
    }
}

void setFrequency(LatticeMaterial& material, double hz) {
    const MaterialSummary s = summarise(material);
    if (s.frequencyHz <= 0.0 || hz <= 0.0)
        return;
    const double ratio = hz / s.frequencyHz;
    for (double& k : material.stiffness)
        k *= ratio * ratio;
    // c = 2 ζ √(k m): keeping ζ means damping follows √k, i.e. scales by the frequency ratio.
    for (double& c : material.damping)
        c *= ratio;
}

void setDampingRatio(LatticeMaterial& material, double ratio) {
    const MaterialSummary s = summarise(material);
    if (s.meanMass <= 0.0 || s.meanStiffness <= 0.0 || ratio < 0.0)
        return;
    setMean(material.damping, material, ratio * 2.0 * std::sqrt(s.meanStiffness * s.meanMass));
}

}  // namespace softtouch::ui

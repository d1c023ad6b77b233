#include "ui/node_brush.h"

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

std::vector<double>& fieldValues(LatticeMaterial& material, PaintField field) {
    return channelValues(material, materialChannel(field));
}

const std::vector<double>& fieldValues(const LatticeMaterial& material, PaintField field) {
    // Every material the editor holds has its maps sized (uniformMaterial, the project reader, resampling).
    return material.*materialChannel(field).values;
}

std::pair<double, double> paintableRange(PaintField field, MaterialModel model) {
    const MaterialRange& range = fieldRange(field, model);
    return {std::max(range.low, field == PaintField::Mass ? 1e-9 : 0.0), range.high};
}

const MaterialRange& fieldRange(PaintField field, MaterialModel model) { return materialChannel(field).rangeFor(model); }

void setLargestVolumePreservation(LatticeMaterial& material, double p) {
    const double largest = largestVolumePreservation(material);
    if (largest <= 0.0 || p <= 0.0 || material.volumePreservation.size() != material.mass.size()) {
        setVolumePreservation(material, std::clamp(p, 0.0, 1.0));
        return;
    }
    for (double& x : material.volumePreservation)
        x = std::clamp(x * p / largest, 0.0, 1.0);
}

const char* fieldName(PaintField field, MaterialModel model) { return fieldRange(field, model).label; }

const char* fieldUnit(PaintField field, MaterialModel model) { return fieldRange(field, model).unit; }

double brushWeight(double distancePixels, const BrushSettings& brush) {
    if (!(distancePixels < brush.radiusPixels))
        return 0.0;
    const double t = distancePixels / brush.radiusPixels;
    switch (brush.falloff) {
    case BrushFalloff::Constant: return 1.0;
    case BrushFalloff::Linear: return 1.0 - t;
    case BrushFalloff::Smooth: return 1.0 - t * t * (3.0 - 2.0 * t);
    }
    return 0.0;
}

bool applyDab(LatticeMaterial& material, std::span<const Eigen::Vector2d> nodeScreen, const Eigen::Vector2d& centre,
              const BrushSettings& brush) {
    std::vector<double>& values = fieldValues(material, brush.field);
    const MaterialRange& range = fieldRange(brush.field, material.model);
    const double target = std::clamp(brush.value, range.low, range.high);
    bool changed = false;
    for (std::size_t n = 0; n < nodeScreen.size() && n < values.size(); ++n) {
        if (material.isVoid[n])
            continue;
        const double w = brush.strength * brushWeight((nodeScreen[n] - centre).norm(), brush);
        if (w <= 0.0)
            continue;
        const double next = values[n] + w * (target - values[n]);
        if (next != values[n]) {
            values[n] = next;
            changed = true;
        }
    }
    return changed;
}

void fillNodes(LatticeMaterial& material, PaintField field, std::span<const int> nodes, double value) {
    std::vector<double>& values = fieldValues(material, field);
    const MaterialRange& range = fieldRange(field, material.model);
    for (int n : nodes)
        values[std::size_t(n)] = std::clamp(value, range.low, range.high);
}

void smoothNodes(LatticeMaterial& material, const Lattice& lattice, PaintField field, std::span<const int> nodes) {
    std::vector<double>& values = fieldValues(material, field);
    const std::vector<double> before = values;
    for (int n : nodes) {
        const auto c = lattice.coords(n);
        double sum = 0.0;
        int count = 0;
        for (int a = 0; a < 3; ++a) {
            for (int step : {-1, 1}) {
                auto d = c;
                d[std::size_t(a)] += step;
                if (d[std::size_t(a)] < 0 || d[std::size_t(a)] >= lattice.count(a))
                    continue;
                sum += before[std::size_t(lattice.index(d[0], d[1], d[2]))];
                ++count;
            }
        }
        if (count > 0)
            values[std::size_t(n)] = 0.5 * (before[std::size_t(n)] + sum / count);
    }
}

}  // namespace softtouch::ui

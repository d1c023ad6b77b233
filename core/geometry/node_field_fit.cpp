#include "core/geometry/node_field_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace softtouch {

Result<std::vector<double>> fitNodeField(const Lattice& lattice, std::span<const PointValue> points) {
    if (points.empty())
        return Status::error("no points to fit the node field to");
    const std::size_t n = std::size_t(lattice.nodeCount());
    std::vector<double> weighted(n, 0.0), weight(n, 0.0);
    for (std::size_t p = 0; p < points.size(); ++p) {
        const PointValue& at = points[p];
        if (!std::isfinite(at.value) || !at.point.allFinite())
            return Status::error("point " + std::to_string(p) + " is not finite");
        const Vec3 uvw = lattice.box().toParameters(at.point).cwiseMax(0.0).cwiseMin(1.0);
        for (const NodeWeight& w : lattice.weights(uvw)) {
            // Both sums in the same order: where every value is 1 they are the same numbers, and the node is exactly 1.
            weighted[w.node] += w.weight * at.value;
            weight[w.node] += w.weight;
        }
    }
    std::vector<double> field(n, 0.0);
    const std::vector<Vec3> rest = lattice.restNodes();
    for (std::size_t i = 0; i < n; ++i) {
        if (weight[i] > 0.0) {
            field[i] = weighted[i] / weight[i];
            continue;
        }
        double nearest = std::numeric_limits<double>::infinity();
        for (const PointValue& at : points)
            if (const double d = (at.point - rest[i]).squaredNorm(); d < nearest) {
                nearest = d;
                field[i] = at.value;
            }
    }
    return field;
}

}  // namespace softtouch

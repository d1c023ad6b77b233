#include "core/geometry/lattice.h"

#include <algorithm>
#include <cassert>
#include <string>

namespace softtouch {

Status LatticeShape::validate() const {
    static const char* axisName[3] = {"u", "v", "w"};
    for (int a = 0; a < 3; ++a) {
        const int n = nodes[std::size_t(a)];
        if (kind == LatticeKind::Bezier && (n < 2 || n > kMaxBasisOrder))
            return Status::error(std::string("a Bezier lattice needs 2 to 8 nodes along ") + axisName[a] +
                                 ", got " + std::to_string(n) + "; use a B-spline lattice for finer grids");
        if (kind == LatticeKind::BSpline && (n < 2 || n > 64))
            return Status::error(std::string("a B-spline lattice needs 2 to 64 nodes along ") + axisName[a] +
                                 ", got " + std::to_string(n));
    }
    return Status::success();
}

Result<Lattice> Lattice::create(const LatticeShape& shape, const OrientedBox& box) {
    if (Status s = shape.validate(); !s)
        return s;
    if (Status s = box.validate(); !s)
        return s;
    Lattice lattice;
    lattice.m_shape = shape;
    lattice.m_box = box;
    for (int a = 0; a < 3; ++a) {
        const int n = shape.nodes[std::size_t(a)];
        lattice.m_axes[std::size_t(a)] =
            shape.kind == LatticeKind::Bezier ? AxisBasis::bezier(n) : AxisBasis::bspline(n, std::min(3, n - 1));
    }
    return lattice;
}

std::array<int, 3> Lattice::coords(int index) const {
    const int i = index % count(0);
    const int j = (index / count(0)) % count(1);
    const int k = index / (count(0) * count(1));
    return {i, j, k};
}

Vec3 Lattice::restNodeParameters(int index) const {
    const auto c = coords(index);
    return {m_axes[0].greville(c[0]), m_axes[1].greville(c[1]), m_axes[2].greville(c[2])};
}

std::vector<Vec3> Lattice::restNodes() const {
    std::vector<Vec3> nodes(static_cast<std::size_t>(nodeCount()));
    for (int n = 0; n < nodeCount(); ++n)
        nodes[std::size_t(n)] = m_box.toWorld(restNodeParameters(n));
    return nodes;
}

std::vector<NodeWeight> Lattice::weights(const Vec3& uvw) const {
    const BasisSample su = m_axes[0].sample(uvw.x());
    const BasisSample sv = m_axes[1].sample(uvw.y());
    const BasisSample sw = m_axes[2].sample(uvw.z());
    std::vector<NodeWeight> out;
    out.reserve(std::size_t(su.order * sv.order * sw.order));
    for (int c = 0; c < sw.order; ++c)
        for (int b = 0; b < sv.order; ++b)
            for (int a = 0; a < su.order; ++a) {
                const double w = su.value[std::size_t(a)] * sv.value[std::size_t(b)] * sw.value[std::size_t(c)];
                out.push_back({std::uint32_t(index(su.first + a, sv.first + b, sw.first + c)), w});
            }
    return out;
}

Vec3 Lattice::evaluate(const Vec3& uvw, std::span<const Vec3> nodes) const {
    assert(int(nodes.size()) == nodeCount());
    Vec3 p = Vec3::Zero();
    for (const NodeWeight& w : weights(uvw))
        p += w.weight * nodes[w.node];
    return p;
}

}  // namespace softtouch

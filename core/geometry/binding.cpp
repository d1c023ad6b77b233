#include "core/geometry/binding.h"

#include "core/base/parallel.h"
#include "core/base/vector_clones.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

namespace softtouch {
namespace {

/// Vertices per work unit: the accumulators and basis rows of one chunk stay in L1.
constexpr std::uint32_t kChunk = 128;

}  // namespace

Binding Binding::create(const Lattice& lattice, std::span<const Vec3f> restPositions,
                        std::span<const Vec3f> restNormals) {
    assert(restNormals.size() == restPositions.size());
    Binding b;
    const std::size_t V = restPositions.size();
    for (int a = 0; a < 3; ++a) {
        b.m_order[std::size_t(a)] = lattice.axis(a).degree() + 1;
        b.m_counts[std::size_t(a)] = lattice.count(a);
    }
    const OrientedBox& box = lattice.box();
    b.m_parameters.resize(V);
    std::vector<std::array<int, 3>> span(V);
    for (std::size_t v = 0; v < V; ++v) {
        b.m_parameters[v] = box.toParameters(restPositions[v].cast<double>());
        for (int a = 0; a < 3; ++a)
            span[v][std::size_t(a)] = lattice.axis(a).spanOf(b.m_parameters[v][a]);
    }
    // Sort by cell (stable, so the order inside a cell is mesh order: deterministic).
    b.m_sortedToVertex.resize(V);
    std::iota(b.m_sortedToVertex.begin(), b.m_sortedToVertex.end(), 0u);
    std::stable_sort(b.m_sortedToVertex.begin(), b.m_sortedToVertex.end(), [&](std::uint32_t x, std::uint32_t y) {
        return std::tie(span[x][2], span[x][1], span[x][0]) < std::tie(span[y][2], span[y][1], span[y][0]);
    });

    const std::size_t rows = std::size_t(*std::max_element(b.m_order.begin(), b.m_order.end()));
    b.m_values.assign(3 * rows * V, 0.0f);
    b.m_slopes.assign(3 * rows * V, 0.0f);
    for (auto& component : b.m_restNormal)
        component.resize(V);
    const Mat3 A = box.parameterJacobian();
    const Mat3 cofactorA = A.determinant() * A.inverse().transpose();
    for (std::size_t s = 0; s < V; ++s) {
        const std::uint32_t v = b.m_sortedToVertex[s];
        for (int a = 0; a < 3; ++a) {
            const BasisSample sample = lattice.axis(a).sample(b.m_parameters[v][a]);
            for (int r = 0; r < sample.order; ++r) {
                b.m_values[(std::size_t(a) * rows + std::size_t(r)) * V + s] = float(sample.value[std::size_t(r)]);
                b.m_slopes[(std::size_t(a) * rows + std::size_t(r)) * V + s] = float(sample.slope[std::size_t(r)]);
            }
        }
        Vec3 m = cofactorA * restNormals[v].cast<double>();
        // Scale-free: only the direction of the result matters; keep magnitudes near 1 for float.
        const double len = m.norm();
        if (len > 0.0)
            m /= len;
        for (int a = 0; a < 3; ++a)
            b.m_restNormal[std::size_t(a)][s] = float(m[a]);
    }
    // Work units: runs of one cell, cut at kChunk vertices.
    for (std::uint32_t s = 0; s < V;) {
        const auto& cell = span[b.m_sortedToVertex[s]];
        std::uint32_t e = s;
        while (e < V && e - s < kChunk && span[b.m_sortedToVertex[e]] == cell)
            ++e;
        Chunk chunk;
        for (int a = 0; a < 3; ++a)
            chunk.firstNode[std::size_t(a)] = cell[std::size_t(a)];  // first node index = span index
        chunk.begin = s;
        chunk.end = e;
        b.m_chunks.push_back(chunk);
        s = e;
    }
    return b;
}

const float* Binding::basisRow(int axis, int r, bool slope) const {
    const std::size_t rows = std::size_t(*std::max_element(m_order.begin(), m_order.end()));
    const std::size_t offset = (std::size_t(axis) * rows + std::size_t(r)) * vertexCount();
    return (slope ? m_slopes.data() : m_values.data()) + offset;
}

void Binding::evaluate(std::span<const Vec3> nodes, std::span<Vec3f> positions, std::span<Vec3f> normals,
                       int threads) const {
    assert(positions.size() == vertexCount());
    assert(normals.empty() || normals.size() == vertexCount());
    // Evaluate relative to the node centroid so float keeps its precision far from the origin.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& n : nodes)
        centre += n;
    centre /= double(nodes.size());
    parallelFor(m_chunks.size(), threads, 64, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c)
            evaluateChunk(m_chunks[c], nodes, centre, positions, normals);
    });
}

// Vectorised across vertices, so AVX2 computes each vertex with exactly the operations SSE2 does (no FMA:
// -ffp-contract=off): clones only change speed, never results.
SOFTTOUCH_VECTOR_CLONES void Binding::evaluateChunk(const Chunk& chunk, std::span<const Vec3> nodes, const Vec3& centre,
                            std::span<Vec3f> positions, std::span<Vec3f> normals) const {
    const std::uint32_t n = chunk.end - chunk.begin;
    const std::uint32_t s0 = chunk.begin;
    const bool withNormals = !normals.empty();
    alignas(64) float X[kChunk] = {}, Y[kChunk] = {}, Z[kChunk] = {};
    // d/du, d/dv, d/dw of the map, x/y/z components each.
    alignas(64) float D[3][3][kChunk] = {};
    alignas(64) float vw[kChunk];
    alignas(64) float dvw[2][kChunk];  // (dv * w), (v * dw)
    // Node (a, b, c) of the chunk's cell block, relative to the centre, in float.
    auto localNode = [&](int a, int b, int c) {
        const int node = (chunk.firstNode[0] + a) +
                         m_counts[0] * ((chunk.firstNode[1] + b) + m_counts[1] * (chunk.firstNode[2] + c));
        return Vec3f((nodes[std::size_t(node)] - centre).cast<float>());
    };

    for (int c = 0; c < m_order[2]; ++c) {
        const float* bw = basisRow(2, c, false) + s0;
        const float* dw = basisRow(2, c, true) + s0;
        for (int b = 0; b < m_order[1]; ++b) {
            const float* bv = basisRow(1, b, false) + s0;
            const float* dv = basisRow(1, b, true) + s0;
            for (std::uint32_t v = 0; v < n; ++v)
                vw[v] = bv[v] * bw[v];
            if (withNormals) {
                for (std::uint32_t v = 0; v < n; ++v) {
                    dvw[0][v] = dv[v] * bw[v];
                    dvw[1][v] = bv[v] * dw[v];
                }
            }
            if (m_order[0] == 4 && !withNormals) {
                // Cubic rows, positions only: the four nodes of the row in one pass, so the running
                // sums are loaded and stored once per row instead of once per node.
                float px[4], py[4], pz[4];
                const float* bu[4];
                for (int a = 0; a < 4; ++a) {
                    const Vec3f local = localNode(a, b, c);
                    px[a] = local.x(), py[a] = local.y(), pz[a] = local.z();
                    bu[a] = basisRow(0, a, false) + s0;
                }
                for (std::uint32_t v = 0; v < n; ++v) {
                    const float w0 = bu[0][v] * vw[v], w1 = bu[1][v] * vw[v], w2 = bu[2][v] * vw[v], w3 = bu[3][v] * vw[v];
                    X[v] = (((X[v] + w0 * px[0]) + w1 * px[1]) + w2 * px[2]) + w3 * px[3];
                    Y[v] = (((Y[v] + w0 * py[0]) + w1 * py[1]) + w2 * py[2]) + w3 * py[3];
                    Z[v] = (((Z[v] + w0 * pz[0]) + w1 * pz[1]) + w2 * pz[2]) + w3 * pz[3];
                }
                continue;
            }
            for (int a = 0; a < m_order[0]; ++a) {
                const Vec3f local = localNode(a, b, c);
                const float px = local.x(), py = local.y(), pz = local.z();
                const float* bu = basisRow(0, a, false) + s0;
                for (std::uint32_t v = 0; v < n; ++v) {
                    const float w = bu[v] * vw[v];
                    X[v] += w * px;
                    Y[v] += w * py;
                    Z[v] += w * pz;
                }
                if (!withNormals)
                    continue;
                const float* du = basisRow(0, a, true) + s0;
                for (std::uint32_t v = 0; v < n; ++v) {
                    const float wu = du[v] * vw[v];
                    const float wv = bu[v] * dvw[0][v];
                    const float ww = bu[v] * dvw[1][v];
                    D[0][0][v] += wu * px; D[0][1][v] += wu * py; D[0][2][v] += wu * pz;
                    D[1][0][v] += wv * px; D[1][1][v] += wv * py; D[1][2][v] += wv * pz;
                    D[2][0][v] += ww * px; D[2][1][v] += ww * py; D[2][2][v] += ww * pz;
                }
            }
        }
    }
    const Vec3f origin = centre.cast<float>();
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t vertex = m_sortedToVertex[s0 + v];
        positions[vertex] = origin + Vec3f(X[v], Y[v], Z[v]);
        if (!withNormals)
            continue;
        const Vec3f qu(D[0][0][v], D[0][1][v], D[0][2][v]);
        const Vec3f qv(D[1][0][v], D[1][1][v], D[1][2][v]);
        const Vec3f qw(D[2][0][v], D[2][1][v], D[2][2][v]);
        const Vec3f nrm = qv.cross(qw) * m_restNormal[0][s0 + v] + qw.cross(qu) * m_restNormal[1][s0 + v] +
                          qu.cross(qv) * m_restNormal[2][s0 + v];
        const float len = nrm.norm();
        normals[vertex] = len > 0.0f ? Vec3f(nrm / len) : Vec3f::UnitZ();
    }
}

}  // namespace softtouch

#include "core/geometry/mesh_volume.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>

namespace softtouch {

namespace {

/// A surface crossing along a sample line: where (u) and which way (+1 entering, −1 leaving).
struct Crossing {
    double u = 0.0;
    int sign = 0;
};

/// The values of every node's basis function of one axis at the S sample centres, [s][node].
std::vector<std::vector<double>> axisValues(const AxisBasis& axis, int samples) {
    std::vector<std::vector<double>> values(std::size_t(samples), std::vector<double>(std::size_t(axis.count()), 0.0));
    for (int s = 0; s < samples; ++s) {
        const BasisSample b = axis.sample((s + 0.5) / samples);
        for (int r = 0; r < b.order; ++r)
            values[std::size_t(s)][std::size_t(b.first + r)] = b.value[std::size_t(r)];
    }
    return values;
}

/// Edges of the surface that no triangle closes: each edge a→b of a closed, consistently oriented surface
/// is matched by an edge b→a of its neighbour. Vertices at the same position count as one (importers
/// split vertices at seams of normals and texture coordinates).
int openEdges(const Mesh& mesh) {
    std::map<std::array<float, 3>, std::uint32_t> byPosition;
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::size_t i = 0; i < id.size(); ++i) {
        const Vec3f& p = mesh.positions[i];
        id[i] = byPosition.emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, std::uint32_t(byPosition.size())).first->second;
    }
    std::unordered_map<std::uint64_t, int> balance;  // +1 for a→b with a < b, −1 for b→a
    for (const auto& t : mesh.triangles) {
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = id[t[std::size_t(e)]], b = id[t[std::size_t((e + 1) % 3)]];
            if (a == b)
                continue;
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            balance[key] += a < b ? 1 : -1;
        }
    }
    int open = 0;
    for (const auto& [key, net] : balance)
        open += net != 0;
    return open;
}

}  // namespace

Result<MeshVolumeShares> meshVolumeShares(const Lattice& lattice, const Mesh& mesh, int samples, int occupancyCells) {
    if (samples < 4 || samples > 512)
        return Status::error("mesh volume samples must be in [4, 512], got " + std::to_string(samples));
    if (occupancyCells < 0 || occupancyCells > samples)
        return Status::error("occupancy cells must be in [0, samples], got " + std::to_string(occupancyCells));
    if (Status s = mesh.validate(); !s)
        return s;
    if (const int open = openEdges(mesh); open > 0)
        return Status::error("the mesh is not a closed surface (" + std::to_string(open) +
                             " edges border one triangle only), so it has no volume to share the mass by");
    const OrientedBox& box = lattice.box();
    std::vector<Vec3> p(mesh.positions.size());
    for (std::size_t i = 0; i < p.size(); ++i)
        p[i] = box.toParameters(mesh.positions[i].cast<double>());

    // Each triangle's crossings go to the lines (j, k) whose centre lies inside its (v, w) projection.
    const int S = samples;
    std::vector<std::vector<Crossing>> lines(std::size_t(S) * std::size_t(S));
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = p[t[0]], &b = p[t[1]], &c = p[t[2]];
        // Twice the signed area of the (v, w) projection: the u component of the normal (b−a)×(c−a).
        const double area = (b.y() - a.y()) * (c.z() - a.z()) - (b.z() - a.z()) * (c.y() - a.y());
        if (area == 0.0)
            continue;  // seen edge-on from the lines: crossed by none
        const int sign = area < 0.0 ? +1 : -1;  // normal against +u: the line enters the solid
        auto cellRange = [&](double lo, double hi) {
            const int first = std::max(0, int(std::ceil(lo * S - 0.5)));
            const int last = std::min(S - 1, int(std::floor(hi * S - 0.5)));
            return std::pair{first, last};
        };
        const auto [j0, j1] = cellRange(std::min({a.y(), b.y(), c.y()}), std::max({a.y(), b.y(), c.y()}));
        const auto [k0, k1] = cellRange(std::min({a.z(), b.z(), c.z()}), std::max({a.z(), b.z(), c.z()}));
        for (int k = k0; k <= k1; ++k) {
            for (int j = j0; j <= j1; ++j) {
                const double v = (j + 0.5) / S, w = (k + 0.5) / S;
                // Barycentric coordinates of (v, w) in the projected triangle (half-open edges so a line
                // through a shared edge counts it once).
                const double l1 = ((v - a.y()) * (c.z() - a.z()) - (w - a.z()) * (c.y() - a.y())) / area;
                const double l2 = ((b.y() - a.y()) * (w - a.z()) - (b.z() - a.z()) * (v - a.y())) / area;
                const double l0 = 1.0 - l1 - l2;
                if (l0 < 0.0 || l1 < 0.0 || l2 < 0.0 || l0 >= 1.0 || l1 >= 1.0 || l2 >= 1.0)
                    continue;
                lines[std::size_t(k) * std::size_t(S) + std::size_t(j)].push_back({l0 * a.x() + l1 * b.x() + l2 * c.x(), sign});
            }
        }
    }

    const auto nu = axisValues(lattice.axis(0), S), nv = axisValues(lattice.axis(1), S), nw = axisValues(lattice.axis(2), S);
    const int nx = lattice.count(0), ny = lattice.count(1), nz = lattice.count(2);
    const double cellVolume = box.size.prod() / (double(S) * S * S);
    MeshVolumeShares out;
    out.nodeVolume.assign(std::size_t(lattice.nodeCount()), 0.0);
    // Occupancy: inside samples per coarse cell over the samples the cell holds.
    const int G = occupancyCells;
    std::vector<int> cellOf(static_cast<std::size_t>(S)), perAxis(static_cast<std::size_t>(std::max(G, 1)), 0);
    for (int s = 0; s < S; ++s) {
        cellOf[std::size_t(s)] = G > 0 ? s * G / S : 0;
        ++perAxis[std::size_t(cellOf[std::size_t(s)])];
    }
    std::vector<double> insideCount(std::size_t(G) * std::size_t(G) * std::size_t(G), 0.0);
    std::vector<double> lineSum(static_cast<std::size_t>(nx), 0.0);
    for (int k = 0; k < S; ++k) {
        for (int j = 0; j < S; ++j) {
            auto& crossings = lines[std::size_t(k) * std::size_t(S) + std::size_t(j)];
            if (crossings.empty())
                continue;
            ++out.linesThroughMesh;
            std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) { return x.u < y.u; });
            int balance = 0;
            for (const Crossing& x : crossings)
                balance += x.sign;
            if (balance != 0) {
                ++out.openLines;
                continue;
            }
            // Σ over the inside samples of this line of each u-node's basis value.
            std::fill(lineSum.begin(), lineSum.end(), 0.0);
            int inside = 0, samplesInside = 0;
            std::size_t next = 0;
            for (int s = 0; s < S; ++s) {
                const double u = (s + 0.5) / S;
                while (next < crossings.size() && crossings[next].u <= u)
                    inside += crossings[next++].sign;
                if (inside <= 0)
                    continue;
                ++samplesInside;
                if (G > 0)
                    insideCount[std::size_t(cellOf[std::size_t(s)] + G * (cellOf[std::size_t(j)] + G * cellOf[std::size_t(k)]))] += 1.0;
                for (int i = 0; i < nx; ++i)
                    lineSum[std::size_t(i)] += nu[std::size_t(s)][std::size_t(i)];
            }
            out.volume += samplesInside * cellVolume;
            for (int kk = 0; kk < nz; ++kk) {
                const double fw = nw[std::size_t(k)][std::size_t(kk)];
                if (fw == 0.0)
                    continue;
                for (int jj = 0; jj < ny; ++jj) {
                    const double fvw = fw * nv[std::size_t(j)][std::size_t(jj)] * cellVolume;
                    if (fvw == 0.0)
                        continue;
                    for (int i = 0; i < nx; ++i)
                        out.nodeVolume[std::size_t(lattice.index(i, jj, kk))] += fvw * lineSum[std::size_t(i)];
                }
            }
        }
    }
    if (out.linesThroughMesh > 0 && out.openLines > 0.02 * out.linesThroughMesh)
        return Status::error("the mesh is not a closed surface (" + std::to_string(out.openLines) + " of " +
                             std::to_string(out.linesThroughMesh) +
                             " sample lines through it cross it unevenly), so it has no volume to share the mass by");
    if (!(out.volume > 0.0))
        return Status::error("the mesh encloses no volume inside its lattice box");
    if (G > 0) {
        out.occupancy.resize(insideCount.size());
        for (int ck = 0; ck < G; ++ck)
            for (int cj = 0; cj < G; ++cj)
                for (int ci = 0; ci < G; ++ci) {
                    const std::size_t c = std::size_t(ci + G * (cj + G * ck));
                    out.occupancy[c] = insideCount[c] / (double(perAxis[std::size_t(ci)]) * perAxis[std::size_t(cj)] *
                                                         perAxis[std::size_t(ck)]);
                }
    }
    return out;
}

std::vector<double> meshMassPerNode(const MeshVolumeShares& shares, const std::vector<std::uint8_t>& isVoid, double totalMass) {
    const std::size_t n = shares.nodeVolume.size();
    double solidShare = 0.0;
    int solidNodes = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!isVoid[i]) {
            solidShare += shares.nodeVolume[i];
            ++solidNodes;
        }
    }
    std::vector<double> mass(n, 0.0);
    if (solidNodes == 0)
        return mass;
    const double floor = kMeshMassFloor * totalMass / solidNodes;
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (isVoid[i])
            continue;
        mass[i] = std::max(floor, solidShare > 0.0 ? totalMass * shares.nodeVolume[i] / solidShare : 0.0);
        sum += mass[i];
    }
    for (double& m : mass)
        m *= totalMass / sum;  // the floors added a little: bring the total back
    return mass;
}

}  // namespace softtouch

#include "core/body/volume_preservation.h"

#include "core/body/body_model.h"
#include "core/body/forces.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

int volumeSampleCells(const Lattice& lattice) {
    return std::max({4, lattice.count(0), lattice.count(1), lattice.count(2)});
}

VolumeConstraint buildVolumeConstraint(const Lattice& lattice, const std::vector<double>& occupancy,
                                       std::span<const double> preservation, double modulus) {
    VolumeConstraint c;
    double largest = 0.0, smallest = 1.0;
    for (double p : preservation) {
        largest = std::max(largest, std::clamp(p, 0.0, 1.0));
        smallest = std::min(smallest, std::clamp(p, 0.0, 1.0));
    }
    c.preservation = largest;
    if (c.preservation == 0.0 || !(modulus > 0.0))
        return c;
    const int G = volumeSampleCells(lattice);
    c.cells = G;
    for (int a = 0; a < 3; ++a) {
        const int n = lattice.count(a);
        c.nodes[std::size_t(a)] = n;
        c.value[std::size_t(a)].assign(std::size_t(G * n), 0.0);
        c.slope[std::size_t(a)].assign(std::size_t(G * n), 0.0);
        for (int g = 0; g < G; ++g) {
            const BasisSample b = lattice.axis(a).sample((g + 0.5) / G);
            for (int r = 0; r < b.order; ++r) {
                c.value[std::size_t(a)][std::size_t(g * n + b.first + r)] = b.value[std::size_t(r)];
                c.slope[std::size_t(a)][std::size_t(g * n + b.first + r)] = b.slope[std::size_t(r)];
            }
        }
    }
    const std::size_t points = std::size_t(G) * std::size_t(G) * std::size_t(G);
    const bool wholeBox = occupancy.size() != points;
    c.weight.assign(points, 0.0);
    for (std::size_t q = 0; q < points; ++q)
        c.weight[q] = (wholeBox ? 1.0 : occupancy[q]) / double(points);  // of the unit parameter box
    if (smallest < largest && preservation.size() == std::size_t(lattice.nodeCount())) {
        // A painted map: each sample counts by the map carried to it through the lattice's basis,
        // p(u_q) = Σ_i N_i(u_q) p_i, over the largest p (the basis is a partition of unity, so a uniform
        // map leaves every weight as it is and is not applied at all).
        const int nu = c.nodes[0], nv = c.nodes[1], nw = c.nodes[2];
        const auto &tu = c.value[0], &tv = c.value[1], &tw = c.value[2];
        for (int gw = 0; gw < G; ++gw)
            for (int gv = 0; gv < G; ++gv)
                for (int gu = 0; gu < G; ++gu) {
                    double painted = 0.0;
                    for (int k = 0; k < nw; ++k) {
                        const double bw = tw[std::size_t(gw * nw + k)];
                        if (bw == 0.0)
                            continue;
                        for (int j = 0; j < nv; ++j) {
                            const double bv = tv[std::size_t(gv * nv + j)];
                            if (bv == 0.0)
                                continue;
                            for (int i = 0; i < nu; ++i)
                                painted += bw * bv * tu[std::size_t(gu * nu + i)] *
                                           preservation[std::size_t(lattice.index(i, j, k))];
                        }
                    }
                    c.weight[std::size_t(gu + G * (gv + G * gw))] *= std::clamp(painted / largest, 0.0, 1.0);
                }
    }
    c.restVolume = sampledVolume(c, lattice.restNodes());
    if (!(c.restVolume > 0.0)) {  // painted only where the mesh is not: nothing to keep
        c.weight.clear();
        return c;
    }
    // K = E p / (1 − p); α = V0 / K (0 when hard).
    c.compliance = c.preservation >= 1.0 ? 0.0 : c.restVolume * (1.0 - c.preservation) / (modulus * c.preservation);
    return c;
}

namespace {

/// out[g, rest] = Σ_i table[g * n + i] in[i, rest]: one axis of a tensor-product sum, the axis first.
/// `in` holds n blocks of `rest` vectors, `out` G blocks.
void contract(const std::vector<double>& table, int G, int n, std::size_t rest, const Vec3* in, Vec3* out) {
    for (int g = 0; g < G; ++g) {
        Vec3* o = out + std::size_t(g) * rest;
        std::fill(o, o + rest, Vec3::Zero());
        for (int i = 0; i < n; ++i) {
            const double t = table[std::size_t(g * n + i)];
            if (t == 0.0)
                continue;
            const Vec3* src = in + std::size_t(i) * rest;
            for (std::size_t r = 0; r < rest; ++r)
                o[r] += t * src[r];
        }
    }
}

/// The transpose: out[i, rest] += Σ_g table[g * n + i] in[g, rest].
void contractTransposed(const std::vector<double>& table, int G, int n, std::size_t rest, const Vec3* in, Vec3* out) {
    for (int i = 0; i < n; ++i) {
        Vec3* o = out + std::size_t(i) * rest;
        for (int g = 0; g < G; ++g) {
            const double t = table[std::size_t(g * n + i)];
            if (t == 0.0)
                continue;
            const Vec3* src = in + std::size_t(g) * rest;
            for (std::size_t r = 0; r < rest; ++r)
                o[r] += t * src[r];
        }
    }
}

/// Moves axis order (a, b, c) → (b, c, a) of a dense block of na × nb × nc vectors (a slowest).
void rotate(const std::vector<Vec3>& in, int na, int nb, int nc, std::vector<Vec3>& out) {
    out.resize(in.size());
    for (int a = 0; a < na; ++a)
        for (int b = 0; b < nb; ++b)
            for (int c = 0; c < nc; ++c)
                out[(std::size_t(b) * nc + c) * na + a] = in[(std::size_t(a) * nb + b) * nc + c];
}

}  // namespace

double sampledVolume(const VolumeConstraint& volume, std::span<const Vec3> x, std::span<Vec3> gradient) {
    const bool wantGradient = !gradient.empty();
    if (wantGradient)
        std::fill(gradient.begin(), gradient.end(), Vec3::Zero());
    const int G = volume.cells;
    if (G == 0)
        return 0.0;
    const int nu = volume.nodes[0], nv = volume.nodes[1], nw = volume.nodes[2];
    // Nodes as [w][v][u] (the lattice's order, u fastest) → work arrays with the contracted axis first.
    // Tangent k: 0 x_u, 1 x_v, 2 x_w.
    // Work arrays kept per thread: after the first call a substep allocates nothing.
    thread_local std::array<std::vector<Vec3>, 3> tangent;
    thread_local std::vector<Vec3> a, b, c;
    // Tangent k's table on `axis`: the slopes on axis k, the values on the others.
    const auto table = [&](int axis, int k) -> const std::vector<double>& {
        return axis == k ? volume.slope[std::size_t(axis)] : volume.value[std::size_t(axis)];
    };
    for (int k = 0; k < 3; ++k) {
        const auto &tu = table(0, k), &tv = table(1, k), &tw = table(2, k);
        a.assign(x.begin(), x.end());                       // [w][v][u]
        b.resize(std::size_t(G) * nv * nu);
        contract(tw, G, nw, std::size_t(nv) * nu, a.data(), b.data());  // [gw][v][u]
        rotate(b, G, nv, nu, a);                            // [v][u][gw]
        c.resize(std::size_t(G) * nu * G);
        contract(tv, G, nv, std::size_t(nu) * G, a.data(), c.data());   // [gv][u][gw]
        rotate(c, G, nu, G, a);                             // [u][gw][gv]
        tangent[std::size_t(k)].resize(std::size_t(G) * G * G);
        contract(tu, G, nu, std::size_t(G) * G, a.data(), tangent[std::size_t(k)].data());  // [gu][gw][gv]
    }
    // The samples, and the gradient's per-sample vectors (w_q times x_v × x_w, ...), in [gu][gw][gv].
    double total = 0.0;
    thread_local std::array<std::vector<Vec3>, 3> seed;
    if (wantGradient)
        for (auto& s : seed)
            s.assign(std::size_t(G) * G * G, Vec3::Zero());
    for (int gu = 0; gu < G; ++gu)
        for (int gw = 0; gw < G; ++gw)
            for (int gv = 0; gv < G; ++gv) {
                const std::size_t at = (std::size_t(gu) * G + gw) * G + gv;
                const double wq = volume.weight[std::size_t(gu + G * (gv + G * gw))];
                if (wq == 0.0)
                    continue;
                const Vec3 &xu = tangent[0][at], &xv = tangent[1][at], &xw = tangent[2][at];
                const Vec3 vw = xv.cross(xw);
                total += wq * xu.dot(vw);
                if (wantGradient) {
                    seed[0][at] = wq * vw;
                    seed[1][at] = wq * xw.cross(xu);
                    seed[2][at] = wq * xu.cross(xv);
                }
            }
    if (!wantGradient)
        return total;
    // ∂V/∂x_i = Σ_k Σ_q (tables of tangent k at q for node i) seed_k[q]: the contractions transposed, in
    // reverse order, back to [w][v][u].
    for (int k = 0; k < 3; ++k) {
        const auto &tu = table(0, k), &tv = table(1, k), &tw = table(2, k);
        a.assign(std::size_t(nu) * G * G, Vec3::Zero());
        contractTransposed(tu, G, nu, std::size_t(G) * G, seed[std::size_t(k)].data(), a.data());  // [u][gw][gv]
        rotate(a, nu, G, G, b);                             // [gw][gv][u]
        rotate(b, G, G, nu, c);                             // [gv][u][gw]
        a.assign(std::size_t(nv) * nu * G, Vec3::Zero());
        contractTransposed(tv, G, nv, std::size_t(nu) * G, c.data(), a.data());  // [v][u][gw]
        rotate(a, nv, nu, G, b);                            // [u][gw][v]
        rotate(b, nu, G, nv, c);                            // [gw][v][u]
        a.assign(std::size_t(nw) * nv * nu, Vec3::Zero());
        contractTransposed(tw, G, nw, std::size_t(nv) * nu, c.data(), a.data());  // [w][v][u]
        for (std::size_t i = 0; i < a.size(); ++i)
            gradient[i] += a[i];
    }
    return total;
}

double enforceVolume(const BodyModel& model, BodyState& state, double h, std::vector<Vec3>& scratch,
                     std::span<const CollisionPlane> planes) {
    const VolumeConstraint& c = model.volume;
    scratch.resize(model.nodeCount());
    const double alphaTilde = c.compliance / (h * h);
    double before = 0.0;
    // A hard constraint is nonlinear (V is cubic in x): Newton steps along its gradient (at most 8); a compliant
    // one takes XPBD's single step per substep.
    const int iterations = c.compliance == 0.0 ? 8 : 1;
    for (int it = 0; it < iterations; ++it) {
        const double v = sampledVolume(c, state.position, scratch);
        if (it == 0)
            before = v;
        const double violation = v - c.restVolume;
        if (c.compliance == 0.0 && std::abs(violation) < 1e-6 * c.restVolume)
            break;
        // Nodes on a plane: the correction moves node i along sign(Δλ) ∇_i C, Δλ = −C / (…) ; drop its part
        // into the plane (so the plane's reaction holds it, as contact does).
        const double direction = violation < 0.0 ? 1.0 : -1.0;
        for (const CollisionPlane& plane : planes)
            for (std::size_t i = 0; i < model.nodeCount(); ++i) {
                const double gap = (state.position[i] - plane.point).dot(plane.normal);
                const double into = direction * scratch[i].dot(plane.normal);
                if (gap <= 1e-9 * (1.0 + state.position[i].norm()) && into < 0.0)
                    scratch[i] -= (into * direction) * plane.normal;
            }
        double denominator = alphaTilde;
        for (std::size_t i = 0; i < model.nodeCount(); ++i)
            denominator += model.inverseMass[i] * scratch[i].squaredNorm();
        if (!(denominator > 0.0))
            break;
        const double dLambda = -violation / denominator;
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            const Vec3 dx = (model.inverseMass[i] * dLambda) * scratch[i];
            state.position[i] += dx;
            state.velocity[i] += dx / h;
        }
    }
    return before;
}

double enclosedVolume(std::span<const Vec3f> positions, std::span<const std::array<std::uint32_t, 3>> triangles) {
    double six = 0.0;
    for (const auto& t : triangles) {
        const Vec3 a = positions[t[0]].cast<double>(), b = positions[t[1]].cast<double>(), c = positions[t[2]].cast<double>();
        six += a.dot(b.cross(c));
    }
    return six / 6.0;
}

}  // namespace softtouch

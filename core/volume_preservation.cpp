#include "core/volume_preservation.h"

#include "core/body_model.h"
#include "core/forces.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

int volumeSampleCells(const Lattice& lattice) {
    return std::max({4, lattice.count(0), lattice.count(1), lattice.count(2)});
}

VolumeConstraint buildVolumeConstraint(const Lattice& lattice, const std::vector<double>& occupancy, double preservation,
                                       double modulus) {
    VolumeConstraint c;
    c.preservation = std::clamp(preservation, 0.0, 1.0);
    if (c.preservation == 0.0 || !(modulus > 0.0))
        return c;
    const int G = volumeSampleCells(lattice);
    const bool wholeBox = occupancy.size() != std::size_t(G) * std::size_t(G) * std::size_t(G);
    const double cellVolume = 1.0 / (double(G) * G * G);  // of the unit parameter box
    c.start.push_back(0);
    for (int k = 0; k < G; ++k) {
        const BasisSample w = lattice.axis(2).sample((k + 0.5) / G);
        for (int j = 0; j < G; ++j) {
            const BasisSample v = lattice.axis(1).sample((j + 0.5) / G);
            for (int i = 0; i < G; ++i) {
                const double inside = wholeBox ? 1.0 : occupancy[std::size_t(i + G * (j + G * k))];
                if (inside <= 0.0)
                    continue;
                const BasisSample u = lattice.axis(0).sample((i + 0.5) / G);
                for (int rk = 0; rk < w.order; ++rk)
                    for (int rj = 0; rj < v.order; ++rj)
                        for (int ri = 0; ri < u.order; ++ri) {
                            c.node.push_back(std::uint32_t(lattice.index(u.first + ri, v.first + rj, w.first + rk)));
                            c.slope.emplace_back(u.slope[std::size_t(ri)] * v.value[std::size_t(rj)] * w.value[std::size_t(rk)],
                                                 u.value[std::size_t(ri)] * v.slope[std::size_t(rj)] * w.value[std::size_t(rk)],
                                                 u.value[std::size_t(ri)] * v.value[std::size_t(rj)] * w.slope[std::size_t(rk)]);
                        }
                c.weight.push_back(cellVolume * inside);
                c.start.push_back(std::uint32_t(c.node.size()));
            }
        }
    }
    c.restVolume = sampledVolume(c, lattice.restNodes());
    // K = E p / (1 − p); α = V0 / K (0 when hard).
    c.compliance = c.preservation >= 1.0 ? 0.0 : c.restVolume * (1.0 - c.preservation) / (modulus * c.preservation);
    return c;
}

double sampledVolume(const VolumeConstraint& volume, std::span<const Vec3> x, std::span<Vec3> gradient) {
    const bool wantGradient = !gradient.empty();
    if (wantGradient)
        std::fill(gradient.begin(), gradient.end(), Vec3::Zero());
    double total = 0.0;
    for (std::size_t q = 0; q < volume.weight.size(); ++q) {
        Vec3 xu = Vec3::Zero(), xv = Vec3::Zero(), xw = Vec3::Zero();
        for (std::uint32_t t = volume.start[q]; t < volume.start[q + 1]; ++t) {
            const Vec3& p = x[volume.node[t]];
            const Vec3& d = volume.slope[t];
            xu += d.x() * p;
            xv += d.y() * p;
            xw += d.z() * p;
        }
        const Vec3 vw = xv.cross(xw), wu = xw.cross(xu), uv = xu.cross(xv);
        const double wq = volume.weight[q];
        total += wq * xu.dot(vw);
        if (wantGradient)
            for (std::uint32_t t = volume.start[q]; t < volume.start[q + 1]; ++t) {
                const Vec3& d = volume.slope[t];
                gradient[volume.node[t]] += wq * (d.x() * vw + d.y() * wu + d.z() * uv);
            }
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

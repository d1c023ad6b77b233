#include "core/body/lattice_body.h"

#include "core/body/material_channels.h"

#include "core/geometry/mesh_volume.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

namespace softtouch {

namespace {
// The bundled fish-body preset as a continuum (softtouch-cli upgrade on angelfish-swim.softtouch).
constexpr double kFishDensity = 2.64, kFishModulus = 1733.0, kFishViscosity = 4.334, kFishDampingRate = 1.28;
}  // namespace

LatticeMaterial uniformMaterial(const Lattice& lattice, double massPerNode, double stiffness, double damping) {
    const std::size_t n = std::size_t(lattice.nodeCount());
    LatticeMaterial m;
    for (const MaterialChannel& channel : materialChannels())
        (m.*channel.values).assign(n, 0.0);
    m.mass.assign(n, massPerNode);
    m.stiffness.assign(n, stiffness);
    m.damping.assign(n, damping);
    m.anchor.assign(n, AnchorMode::Free);
    m.isVoid.assign(n, 0);
    return m;
}

const MaterialRanges& materialRanges(MaterialModel model) {
    // File keys kept from earlier versions ("damping", "airDamping"); the labels say what each term is.
    static const MaterialRanges springs{"lattice-springs",
                                       {"mass", "mass", 1e-12, 1e12, "kg"},
                                       {"stiffness", "stiffness", 0.0, 1e9, "N/m"},
                                       {"damping", "spring damping", 0.0, 1e6, "N·s/m"},
                                       {"airDamping", "node damping", 0.0, 1e6, "N·s/m"}};
    static const MaterialRanges continuum{"continuum",
                                          {"density", "density", 1e-3, 1e6, "kg/m³"},
                                          {"modulus", "Young's modulus", 0.0, 1e12, "Pa"},
                                          {"viscosity", "spring viscosity", 0.0, 1e9, "Pa·s"},
                                          {"dampingRate", "node damping rate", 0.0, 1e4, "1/s"}};
    return model == MaterialModel::Continuum ? continuum : springs;
}

const DefaultMaterialValues& defaultMaterialValues(MaterialModel model) {
    // LatticeSprings: the values new objects had before version 3. Continuum: the bundled
    // "fish body" preset (presets/materials/fish-body.stpreset).
    static const DefaultMaterialValues springs{0.02, 80.0, 0.9, 0.0};
    static const DefaultMaterialValues continuum{kFishDensity, kFishModulus, kFishViscosity, kFishDampingRate};
    return model == MaterialModel::Continuum ? continuum : springs;
}

LatticeMaterial defaultMaterial(const Lattice& lattice, MaterialModel model) {
    const DefaultMaterialValues& d = defaultMaterialValues(model);
    LatticeMaterial m = uniformMaterial(lattice, d.mass, d.stiffness, d.damping);
    m.model = model;
    m.nodeDamping.assign(m.mass.size(), d.nodeDamping);
    return m;
}

LatticeMaterial continuumMaterial(const Lattice& lattice, double density, double modulus, double viscosity) {
    LatticeMaterial m = uniformMaterial(lattice, density, modulus, viscosity);
    m.model = MaterialModel::Continuum;
    return m;
}

namespace {

/// Rest spacing of the grid cells along each axis, metres (between neighbouring Greville points).
std::array<std::vector<double>, 3> cellSpacings(const Lattice& lattice) {
    std::array<std::vector<double>, 3> h;
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i + 1 < lattice.count(a); ++i)
            h[std::size_t(a)].push_back((lattice.axis(a).greville(i + 1) - lattice.axis(a).greville(i)) *
                                        lattice.box().size[a]);
    return h;
}

/// Young's modulus of the spring network per unit of spring coefficient, for cubic cells and equal
/// kind scales. A spring of rest length L gets k = E · share · V_cell / L² from every cell it crosses
/// (share: edge 1/4, face diagonal 1/2, body diagonal 1, so each cell counts once). Under a uniform
/// strain the 28 springs of a cell store the energy of a cubic solid with C11 = 22/9 E and
/// C12 = C44 = 17/18 E (central springs obey Cauchy's relation), whose Young's modulus along an axis is
/// (C11 − C12)(C11 + 2 C12)/(C11 + C12) = 117/61 E and Poisson's ratio C12/(C11 + C12) = 17/61 ≈ 0.28.
/// Scaling by 61/117 makes the painted value the solid's Young's modulus.
constexpr double kModulusPerCoefficient = 61.0 / 117.0;

}  // namespace

double largestVolumePreservation(const LatticeMaterial& material) {
    double largest = 0.0;
    for (double p : material.volumePreservation)
        largest = std::max(largest, p);
    return largest;
}

void setVolumePreservation(LatticeMaterial& material, double p) {
    material.volumePreservation.assign(material.mass.size(), p);
}

double solidMean(const std::vector<double>& values, const LatticeMaterial& material) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t n = 0; n < values.size(); ++n) {
        if (!material.isVoid[n]) {
            sum += values[n];
            ++count;
        }
    }
    return count > 0 ? sum / count : 0.0;
}

std::vector<double> nodeVolumes(const Lattice& lattice) {
    const auto h = cellSpacings(lattice);
    std::vector<double> volume(std::size_t(lattice.nodeCount()), 0.0);
    for (int node = 0; node < lattice.nodeCount(); ++node) {
        const auto c = lattice.coords(node);
        double v = 1.0;
        for (int a = 0; a < 3; ++a) {
            const auto& spacing = h[std::size_t(a)];
            const int i = c[std::size_t(a)];
            // Half of each adjacent cell along this axis.
            v *= 0.5 * ((i > 0 ? spacing[std::size_t(i - 1)] : 0.0) + (i < int(spacing.size()) ? spacing[std::size_t(i)] : 0.0));
        }
        volume[std::size_t(node)] = v;
    }
    return volume;
}

std::vector<double> nodeMasses(const Lattice& lattice, const LatticeMaterial& material) {
    if (material.model == MaterialModel::LatticeSprings)
        return material.mass;
    std::vector<double> mass = nodeVolumes(lattice);
    for (std::size_t n = 0; n < mass.size(); ++n)
        mass[n] *= material.mass[n];
    return mass;
}

std::vector<Spring> latticeSprings(const Lattice& lattice, const LatticeMaterial& material) {
    const int nx = lattice.count(0), ny = lattice.count(1), nz = lattice.count(2);
    const std::vector<Vec3> rest = lattice.restNodes();
    const Mat3 axes = lattice.box().axes;
    const auto spacing = cellSpacings(lattice);
    const bool continuum = material.model == MaterialModel::Continuum;
    // Σ share · V_cell / L² over the cells a spring crosses (see kModulusPerCoefficient), in metres.
    auto cellCoefficient = [&](const std::array<int, 3>& from, const std::array<int, 3>& to, double length) {
        // Lengths of the adjacent cells along each axis: the one crossed, or the (at most two) either side of
        // the node. Fixed arrays, not vectors: a paint dab rebuilds every spring.
        std::array<std::array<double, 2>, 3> extent{};
        std::array<int, 3> extents{};
        int spanned = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            if (from[a] != to[a]) {
                extent[a][std::size_t(extents[a]++)] = spacing[a][std::size_t(std::min(from[a], to[a]))];
                ++spanned;
            } else {
                if (from[a] > 0) extent[a][std::size_t(extents[a]++)] = spacing[a][std::size_t(from[a] - 1)];
                if (from[a] < int(spacing[a].size())) extent[a][std::size_t(extents[a]++)] = spacing[a][std::size_t(from[a])];
            }
        }
        const double share = spanned == 1 ? 0.25 : spanned == 2 ? 0.5 : 1.0;
        double volume = 0.0;  // Σ x·y·z over the adjacent cells, summed in this order (bakes stay bit-exact)
        for (int x = 0; x < extents[0]; ++x)
            for (int y = 0; y < extents[1]; ++y)
                for (int z = 0; z < extents[2]; ++z)
                    volume += extent[0][std::size_t(x)] * extent[1][std::size_t(y)] * extent[2][std::size_t(z)];
        return kModulusPerCoefficient * share * volume / (length * length);
    };
    std::vector<Spring> springs;
    auto add = [&](int i0, int j0, int k0, int i1, int j1, int k1, SpringKind kind) {
        const auto a = std::uint32_t(lattice.index(i0, j0, k0));
        const auto b = std::uint32_t(lattice.index(i1, j1, k1));
        Spring s;
        s.a = a;
        s.b = b;
        s.kind = kind;
        const Vec3 r = rest[b] - rest[a];
        s.restLength = r.norm();
        const Vec3 d = axes.transpose() * r / s.restLength;  // direction in the box frame
        const double anisotropy = d.cwiseProduct(d).dot(material.anisotropy);
        const double coefficient = continuum ? cellCoefficient({i0, j0, k0}, {i1, j1, k1}, s.restLength) : 1.0;
        s.stiffness = 0.5 * (material.stiffness[a] + material.stiffness[b]) *
                      material.kindScale[std::size_t(kind)] * anisotropy * coefficient;
        s.damping = 0.5 * (material.damping[a] + material.damping[b]) * coefficient;
        springs.push_back(s);
    };
    // Edges: from each node to its +u, +v, +w neighbour.
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                if (i + 1 < nx) add(i, j, k, i + 1, j, k, SpringKind::Edge);
                if (j + 1 < ny) add(i, j, k, i, j + 1, k, SpringKind::Edge);
                if (k + 1 < nz) add(i, j, k, i, j, k + 1, SpringKind::Edge);
            }
    // Face diagonals: both diagonals of each unique face, faces keyed by their lowest corner.
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                if (i + 1 < nx && j + 1 < ny) {  // uv face
                    add(i, j, k, i + 1, j + 1, k, SpringKind::FaceDiagonal);
                    add(i + 1, j, k, i, j + 1, k, SpringKind::FaceDiagonal);
                }
                if (i + 1 < nx && k + 1 < nz) {  // uw face
                    add(i, j, k, i + 1, j, k + 1, SpringKind::FaceDiagonal);
                    add(i + 1, j, k, i, j, k + 1, SpringKind::FaceDiagonal);
                }
                if (j + 1 < ny && k + 1 < nz) {  // vw face
                    add(i, j, k, i, j + 1, k + 1, SpringKind::FaceDiagonal);
                    add(i, j + 1, k, i, j, k + 1, SpringKind::FaceDiagonal);
                }
            }
    // Body diagonals: four per cell.
    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i) {
                add(i, j, k, i + 1, j + 1, k + 1, SpringKind::BodyDiagonal);
                add(i + 1, j, k, i, j + 1, k + 1, SpringKind::BodyDiagonal);
                add(i, j + 1, k, i + 1, j, k + 1, SpringKind::BodyDiagonal);
                add(i + 1, j + 1, k, i, j, k + 1, SpringKind::BodyDiagonal);
            }
    return springs;
}

SpringCounts countSprings(const std::vector<Spring>& springs) {
    SpringCounts c;
    for (const Spring& s : springs) {
        if (s.kind == SpringKind::Edge) ++c.edges;
        if (s.kind == SpringKind::FaceDiagonal) ++c.faceDiagonals;
        if (s.kind == SpringKind::BodyDiagonal) ++c.bodyDiagonals;
    }
    return c;
}

namespace {

Status validateMaterial(const Lattice& lattice, const LatticeMaterial& m) {
    const std::size_t n = std::size_t(lattice.nodeCount());
    auto sized = [&](std::size_t size, const char* field) -> Status {
        if (size != n)
            return Status::error(std::string(field) + " has " + std::to_string(size) + " values for " +
                                 std::to_string(n) + " lattice nodes");
        return Status::success();
    };
    const std::span<const MaterialChannel> channels = materialChannels();
    for (const MaterialChannel& channel : channels)
        if (const std::size_t size = (m.*channel.values).size(); size != 0 || !channel.optional)
            if (Status s = sized(size, channel.rangeFor(m.model).label); !s) return s;
    if (Status s = sized(m.anchor.size(), "anchor"); !s) return s;
    if (Status s = sized(m.isVoid.size(), "void"); !s) return s;
    auto formatNumber = [](double x) {
        std::ostringstream out;
        out << x;
        return out.str();
    };
    // "node (1,2,0) node damping (airDamping) -1 N·s/m is outside [0, 1e+06]": what it is and the file's key.
    auto check = [&](double x, const MaterialRange& r, const std::string& node) -> Status {
        if (r.contains(x))
            return Status::success();
        const std::string label = r.label;
        const std::string field = label == r.name ? label : label + " (" + r.name + ")";
        const std::string unit = *r.unit ? std::string(" ") + r.unit : std::string();
        return Status::error(node + " " + field + " " + formatNumber(x) + unit + " is outside [" +
                             formatNumber(r.low) + ", " + formatNumber(r.high) + "]");
    };
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = lattice.coords(int(i));
        const std::string node = "node (" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
        for (const MaterialChannel& channel : channels) {
            const std::vector<double>& values = m.*channel.values;
            if (!values.empty() && (channel.checkedOnVoidNodes || !m.isVoid[i]))
                if (Status s = check(values[i], channel.rangeFor(m.model), node); !s) return s;
        }
    }
    for (int a = 0; a < 3; ++a) {
        const double s = m.kindScale[std::size_t(a)];
        if (!(std::isfinite(s) && s >= 0.0 && s <= 1e3))
            return Status::error("spring kind scale " + std::to_string(s) + " is outside [0, 1e3]");
        const double an = m.anisotropy[a];
        if (!(std::isfinite(an) && an >= 1e-6 && an <= 1e6))
            return Status::error("anisotropy " + std::to_string(an) + " is outside [1e-6, 1e6]");
    }
    return Status::success();
}

}  // namespace

const char* bodyElementName(BodyElement element) { return element == BodyElement::Solid ? "solid" : "springs"; }

namespace {

/// The contact points of a body on `mesh`, computed once per mesh and lattice.
std::shared_ptr<const ContactPoints> contactPointsOf(const Lattice& lattice, const Mesh* mesh, MeshLatticeCache& derived) {
    if (!mesh || mesh->positions.empty())
        return nullptr;
    if (!derived.contactPoints)
        derived.contactPoints = std::make_shared<const ContactPoints>(meshContactPoints(lattice, *mesh));
    return derived.contactPoints;
}

/// buildLatticeBody() for BodyElement::Solid: the element instead of springs, anchors of either kind held.
Result<std::shared_ptr<const BodyModel>> buildElementLatticeBody(const Lattice& lattice, const LatticeMaterial& material,
                                                                 const Mesh* mesh, MeshLatticeCache& derived) {
    const char* refusal = material.model != MaterialModel::Continuum ? "needs a continuum material (upgrade the project)"
                          : std::any_of(material.isVoid.begin(), material.isVoid.end(), [](std::uint8_t v) { return v != 0; })
                              ? "fills the whole lattice box, so it takes no void nodes"
                          : material.strainLimits.any()              ? "has no springs for strain limits to hold"
                          : largestVolumePreservation(material) > 0.0 ? "does not keep volume yet (set volume preservation to 0)"
                                                                       : nullptr;
    if (refusal)
        return Status::error(std::string("the solid element ") + refusal + "; use \"element\": \"springs\" for this material");
    const std::size_t n = std::size_t(lattice.nodeCount());
    std::vector<std::uint8_t> held(n, 0);
    for (std::size_t i = 0; i < n; ++i)
        held[i] = material.anchor[i] != AnchorMode::Free;
    auto element = buildElementBody(lattice, material, held);
    if (!element)
        return element.status();
    BodyDescription d;
    d.restPositions = lattice.restNodes();
    d.mass.resize(n);
    d.anchor.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        d.mass[i] = element.value()->mass.row(Eigen::Index(i)).sum();  // ∫ρ N_i: the basis sums to 1
        d.anchor[i] = held[i] ? AnchorMode::Pinned : AnchorMode::Free;
    }
    d.contactPoints = contactPointsOf(lattice, mesh, derived);
    d.element = element.value();
    return buildBodyModel(d);
}

}  // namespace

Result<std::shared_ptr<const BodyModel>> buildLatticeBody(const Lattice& lattice, const LatticeMaterial& material,
                                                          const Mesh* mesh, MeshLatticeCache* cache) {
    MeshLatticeCache local;
    MeshLatticeCache& derived = cache ? *cache : local;
    if (Status s = validateMaterial(lattice, material); !s)
        return s;
    if (material.element == BodyElement::Solid)
        return buildElementLatticeBody(lattice, material, mesh, derived);
    BodyDescription d;
    d.restPositions = lattice.restNodes();
    d.mass = nodeMasses(lattice, material);
    d.anchor = material.anchor;
    d.isVoid = material.isVoid;
    d.springs = latticeSprings(lattice, material);
    d.heavyAnchorRatio = material.heavyAnchorRatio;
    d.strainLimits = material.strainLimits;
    if (material.model == MaterialModel::Continuum) {
        // Each node's rate times its mass: mass-proportional, the same ζ at every resolution.
        d.nodeDamping = d.mass;
        for (std::size_t i = 0; i < d.nodeDamping.size(); ++i)
            d.nodeDamping[i] *= material.nodeDamping[i];
    } else {
        d.nodeDamping = material.nodeDamping;
    }
    // Void nodes follow already-resolved 26-neighbours, resolved ring by ring outward from the body.
    const int n = lattice.nodeCount();
    std::vector<std::uint8_t> resolved(std::size_t(n), 0);
    for (int i = 0; i < n; ++i)
        resolved[std::size_t(i)] = material.isVoid[std::size_t(i)] == 0;
    for (bool progress = true; progress;) {
        progress = false;
        std::vector<VoidFollower> ring;
        for (int node = 0; node < n; ++node) {
            if (resolved[std::size_t(node)])
                continue;
            const auto c = lattice.coords(node);
            VoidFollower f;
            f.node = std::uint32_t(node);
            for (int dk = -1; dk <= 1; ++dk)
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
                        if (i < 0 || j < 0 || k < 0 || i >= lattice.count(0) || j >= lattice.count(1) || k >= lattice.count(2))
                            continue;
                        const int other = lattice.index(i, j, k);
                        if (other != node && resolved[std::size_t(other)])
                            f.donors.push_back(std::uint32_t(other));
                    }
            if (!f.donors.empty())
                ring.push_back(std::move(f));
        }
        for (const VoidFollower& f : ring) {
            resolved[f.node] = 1;
            d.voidFollowers.push_back(f);
            progress = true;
        }
    }
    d.contactPoints = contactPointsOf(lattice, mesh, derived);
    if (largestVolumePreservation(material) > 0.0) {
        // The springs' modulus E = mean k / L (a spring of stiffness k and length L across an L² face).
        double modulus = 0.0;
        int counted = 0;
        for (const Spring& s : d.springs)
            if (s.restLength > 0.0 && !material.isVoid[s.a] && !material.isVoid[s.b]) {
                modulus += s.stiffness / s.restLength;
                ++counted;
            }
        if (!derived.volumeOccupancy) {
            derived.volumeOccupancy.emplace();  // empty: the box's volume
            if (mesh && !mesh->triangles.empty())
                if (auto shares = meshVolumeShares(lattice, *mesh, kMeshVolumeSamples, volumeSampleCells(lattice)))
                    *derived.volumeOccupancy = std::move(shares.value().occupancy);
        }
        d.volume = buildVolumeConstraint(lattice, *derived.volumeOccupancy, material.volumePreservation,
                                         counted > 0 ? modulus / counted : 0.0);
    }
    return buildBodyModel(d);
}

namespace {

/// The node index along `axis` whose rest parameter is nearest to t.
int nearest(const Lattice& lattice, int axis, double t) {
    int best = 0;
    for (int i = 1; i < lattice.count(axis); ++i) {
        if (std::abs(lattice.axis(axis).greville(i) - t) < std::abs(lattice.axis(axis).greville(best) - t))
            best = i;
    }
    return best;
}

/// Anchor and void flags carried to another lattice. A node of `to` takes a flag only where every node of
/// `from` around it has one (the source nodes of the grid cell, face, edge or node its rest parameters lie
/// in), so a flagged region keeps its extent in the material: the pinned face u = 1 of a 4x4x4 lattice
/// pins the face u = 1 of an 8x8x8 one, not the slab of material whose nearest 4x4x4 node lies on it
/// (which clamped a sixth of the body more on 7x7x7 and 8x8x8 and moved the modes). So that no flag is
/// lost, each flagged node of `from` also flags the node of `to` nearest to it. The flag taken is that of
/// the nearest flagged source node.
template <typename Flag>
void resampleNodeFlags(const Lattice& from, const std::vector<Flag>& source, const Lattice& to, std::vector<Flag>& out,
                       Flag none) {
    constexpr double kSame = 1e-9;
    // The source nodes bracketing t along one axis: one where t sits on a node, else the two around it.
    auto bracket = [&](int axis, double t) {
        const int n = from.count(axis);
        int i = 0;
        while (i + 1 < n && from.axis(axis).greville(i + 1) <= t + kSame)
            ++i;
        if (std::abs(from.axis(axis).greville(i) - t) <= kSame || i + 1 == n)
            return std::array<int, 2>{i, i};
        return std::array<int, 2>{i, i + 1};
    };
    out.assign(std::size_t(to.nodeCount()), none);
    for (int node = 0; node < to.nodeCount(); ++node) {
        const Vec3 p = to.restNodeParameters(node);
        const auto bu = bracket(0, p.x()), bv = bracket(1, p.y()), bw = bracket(2, p.z());
        bool all = true;
        for (int i : bu)
            for (int j : bv)
                for (int k : bw)
                    all = all && source[std::size_t(from.index(i, j, k))] != none;
        if (all)
            out[std::size_t(node)] = source[std::size_t(from.index(nearest(from, 0, p.x()), nearest(from, 1, p.y()), nearest(from, 2, p.z())))];
    }
    for (int node = 0; node < from.nodeCount(); ++node) {
        const Flag flag = source[std::size_t(node)];
        if (flag == none)
            continue;
        const Vec3 p = from.restNodeParameters(node);
        Flag& target = out[std::size_t(to.index(nearest(to, 0, p.x()), nearest(to, 1, p.y()), nearest(to, 2, p.z())))];
        if (target == none)
            target = flag;
    }
}

}  // namespace

LatticeMaterial resampleMaterial(const Lattice& from, const LatticeMaterial& material, const Lattice& to,
                                 bool keepContinuum) {
    LatticeMaterial out = material;
    const std::size_t n = std::size_t(to.nodeCount());
    for (const MaterialChannel& channel : materialChannels())
        (out.*channel.values).assign(n, 0.0);
    out.anchor.assign(n, AnchorMode::Free);
    out.isVoid.assign(n, 0);
    // Spacing ratio (geometric mean over the axes) and volume share ratio of one node.
    // A continuum's values are per volume or per area already: nothing to rescale.
    keepContinuum = keepContinuum && material.model == MaterialModel::LatticeSprings;
    double spacing = 1.0, volume = 1.0;
    for (int a = 0; a < 3; ++a) {
        spacing *= double(from.count(a) - 1) / double(to.count(a) - 1);
        volume *= double(from.count(a)) / double(to.count(a));
    }
    spacing = std::cbrt(spacing);
    for (int node = 0; node < to.nodeCount(); ++node) {
        const Vec3 p = to.restNodeParameters(node);
        const auto source = std::size_t(from.index(nearest(from, 0, p.x()), nearest(from, 1, p.y()), nearest(from, 2, p.z())));
        for (const MaterialChannel& channel : materialChannels()) {
            const std::vector<double>& values = material.*channel.values;
            if (values.empty())  // an optional channel the material has none of: 0 everywhere
                continue;
            const double scale = !keepContinuum                                      ? 1.0
                                 : channel.scaling == ChannelScaling::NodeVolume ? volume
                                 : channel.scaling == ChannelScaling::Spacing    ? spacing
                                                                                 : 1.0;
            (out.*channel.values)[std::size_t(node)] = values[source] * scale;
        }
    }
    resampleNodeFlags(from, material.anchor, to, out.anchor, AnchorMode::Free);
    resampleNodeFlags(from, material.isVoid, to, out.isVoid, std::uint8_t(0));
    return out;
}

std::vector<std::uint8_t> findEmptyNodes(const Lattice& lattice, const Mesh& mesh) {
    // Grid cells lie between neighbouring nodes' rest parameters (Greville points), nx-1 per axis.
    std::array<std::vector<double>, 3> grid;
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < lattice.count(a); ++i)
            grid[std::size_t(a)].push_back(lattice.axis(a).greville(i));
    const int cx = lattice.count(0) - 1, cy = lattice.count(1) - 1, cz = lattice.count(2) - 1;
    std::vector<std::uint8_t> occupied(std::size_t(cx * cy * cz), 0);
    auto mark = [&](const Vec3& world) {
        const Vec3 uvw = lattice.box().toParameters(world);
        int cell[3];
        for (int a = 0; a < 3; ++a) {
            const auto& g = grid[std::size_t(a)];
            const auto it = std::upper_bound(g.begin(), g.end(), uvw[a]);
            cell[a] = std::clamp(int(it - g.begin()) - 1, 0, int(g.size()) - 2);
        }
        occupied[std::size_t(cell[0] + cx * (cell[1] + cy * cell[2]))] = 1;
    };
    for (const Vec3f& p : mesh.positions)
        mark(p.cast<double>());
    for (const auto& t : mesh.triangles)
        mark((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]).cast<double>() / 3.0);
    std::vector<std::uint8_t> empty(std::size_t(lattice.nodeCount()), 1);
    for (int node = 0; node < lattice.nodeCount(); ++node) {
        const auto c = lattice.coords(node);
        for (int dk = -1; dk <= 0; ++dk)
            for (int dj = -1; dj <= 0; ++dj)
                for (int di = -1; di <= 0; ++di) {
                    const int i = c[0] + di, j = c[1] + dj, k = c[2] + dk;
                    if (i < 0 || j < 0 || k < 0 || i >= cx || j >= cy || k >= cz)
                        continue;
                    if (occupied[std::size_t(i + cx * (j + cy * k))])
                        empty[std::size_t(node)] = 0;
                }
    }
    return empty;
}

}  // namespace softtouch

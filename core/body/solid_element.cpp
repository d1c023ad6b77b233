#include "core/body/solid_element.h"

#include <algorithm>
#include <string>

namespace softtouch {

Eigen::Matrix<double, 9, 9> gradientElasticity(const Eigen::Matrix<double, 6, 6>& c) {
    Eigen::Matrix<double, 6, 9> p = Eigen::Matrix<double, 6, 9>::Zero();
    const auto g = [](int alpha, int k) { return 3 * alpha + k; };
    p(0, g(0, 0)) = 1.0;
    p(1, g(1, 1)) = 1.0;
    p(2, g(2, 2)) = 1.0;
    p(3, g(1, 2)) = p(3, g(2, 1)) = 1.0;
    p(4, g(0, 2)) = p(4, g(2, 0)) = 1.0;
    p(5, g(0, 1)) = p(5, g(1, 0)) = 1.0;
    return p.transpose() * c * p;
}

SolidElement bernsteinElement(int degree) {
    SolidElement element;
    element.axes.fill(AxisBasis::bezier(degree + 1));
    return element;
}

SolidElement latticeElement(const Lattice& lattice) {
    SolidElement element;
    for (int a = 0; a < 3; ++a)
        element.axes[std::size_t(a)] = lattice.axis(a);
    return element;
}

SolidElement simulatedElement(const Lattice& lattice) {
    SolidElement element = latticeElement(lattice);
    element.reduced = true;
    element.exactShare = kElementExactShare;
    return element;
}

NetworkElasticity materialElasticity(const Lattice& lattice, const LatticeMaterial& material) {
    if (material.model != MaterialModel::Continuum)
        return networkElasticity(lattice, material);
    // One cubic cell, aligned with the box: the spring coefficients' 61/117 makes the painted value its Young's
    // modulus along every axis. Its size does not matter (a uniform strain stores energy per volume).
    OrientedBox cell = lattice.box();
    cell.size = Vec3::Constant(cell.size.minCoeff());
    const Lattice one = Lattice::create({LatticeKind::Bezier, {2, 2, 2}}, cell).value();  // a sub-box of a valid box
    LatticeMaterial cellMaterial = continuumMaterial(one, 1.0, solidMean(material.stiffness, material), 0.0);
    cellMaterial.kindScale = material.kindScale;
    cellMaterial.anisotropy = material.anisotropy;
    return networkElasticity(one, cellMaterial);
}

Result<SolidField> materialSolid(const Lattice& lattice, const LatticeMaterial& material, int degree) {
    if (degree < 1 || degree > kMaxSolidDegree)
        return Status::error("the reference solid's degree must be 1 to " + std::to_string(kMaxSolidDegree) + ", not " +
                             std::to_string(degree));
    const std::size_t n = std::size_t(lattice.nodeCount());
    if (std::any_of(material.isVoid.begin(), material.isVoid.end(), [](std::uint8_t v) { return v != 0; }))
        return Status::error("the body has void nodes; the reference solid fills the whole lattice box");
    if (material.stiffness.size() != n || material.mass.size() != n)
        return Status::error("the material has " + std::to_string(material.stiffness.size()) + " stiffness values for " +
                             std::to_string(n) + " nodes");

    // The springs' elasticity per unit of the painted stiffness: every spring's k is linear in its two nodes'.
    LatticeMaterial unit = material;
    std::fill(unit.stiffness.begin(), unit.stiffness.end(), 1.0);
    const NetworkElasticity network = materialElasticity(lattice, unit);
    if (!network.resistsEveryStrain)
        return Status::error("the springs do not resist every uniform strain (a spring kind scaled to 0), so they "
                             "describe no solid");

    auto reference = Lattice::create({LatticeKind::Bezier, {degree + 1, degree + 1, degree + 1}}, lattice.box());
    if (!reference)
        return reference.status();
    const LatticeMaterial carried = resampleMaterial(lattice, material, reference.value(), true);

    const std::vector<double> masses = nodeMasses(lattice, material);
    const std::vector<double> volumes = nodeVolumes(lattice);
    std::vector<double> density(n);
    for (std::size_t i = 0; i < n; ++i)
        density[i] = masses[i] / volumes[i];
    const auto interpolate = [lattice](std::vector<double> values) {
        return [lattice, values = std::move(values)](const Vec3& s) {
            double sum = 0.0;
            for (const NodeWeight& w : lattice.weights(s))
                sum += w.weight * values[w.node];
            return sum;
        };
    };

    SolidField solid;
    solid.size = lattice.box().size;
    solid.elasticity = network.stiffness;
    solid.modulus = interpolate(material.stiffness);
    solid.density = interpolate(std::move(density));
    solid.pinned.resize(std::size_t(reference->nodeCount()), 0);
    for (std::size_t i = 0; i < carried.anchor.size() && i < solid.pinned.size(); ++i)
        solid.pinned[i] = carried.anchor[i] != AnchorMode::Free;
    return solid;
}

}  // namespace softtouch

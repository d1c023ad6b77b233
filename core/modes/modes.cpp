#include "core/modes/modes.h"

#include "core/body/forces.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <string>

namespace softtouch {

double VibrationMode::dampedFrequencyHz() const {
    return dampingRatio < 1.0 ? frequencyHz * std::sqrt(1.0 - dampingRatio * dampingRatio) : 0.0;
}

namespace {

/// Adds w · n nᵀ to the 3x3 blocks (a,a), (b,b) and −w · n nᵀ to (a,b), (b,a) of a dense matrix over
/// free-node unknowns; a node with slot −1 is fixed and contributes nothing.
void addSpringBlock(Eigen::MatrixXd& matrix, int a, int b, const Mat3& block) {
    if (a >= 0)
        matrix.block<3, 3>(3 * a, 3 * a) += block;
    if (b >= 0)
        matrix.block<3, 3>(3 * b, 3 * b) += block;
    if (a >= 0 && b >= 0) {
        matrix.block<3, 3>(3 * a, 3 * b) -= block;
        matrix.block<3, 3>(3 * b, 3 * a) -= block;
    }
}

/// A mode of mass-normalised shape φ (φᵀMφ = 1) over the free nodes (`slot`), its shape per node with void
/// nodes filled the way the simulator fills them, scaled to a largest node displacement of 1.
VibrationMode makeMode(const BodyModel& model, const std::vector<int>& slot, const Eigen::VectorXd& phi, double omega,
                       double nodeDampingRatio, double springDampingRatio) {
    const std::size_t n = model.nodeCount();
    VibrationMode mode;
    mode.frequencyHz = omega / (2.0 * std::numbers::pi);
    mode.nodeDampingRatio = nodeDampingRatio;
    mode.springDampingRatio = springDampingRatio;
    mode.dampingRatio = nodeDampingRatio + springDampingRatio;
    BodyState state = restState(model);
    double largest = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        if (slot[i] >= 0)
            largest = std::max(largest, phi.segment<3>(3 * slot[i]).norm());
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (slot[i] >= 0)
            state.position[i] += phi.segment<3>(3 * slot[i]) / largest;
    }
    updateVoidNodes(model, state);
    mode.shape.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        mode.shape[i] = state.position[i] - model.restPositions[i];
    return mode;
}

/// analyseModes() of a solid element body: its stiffness and viscosity at rest and its consistent mass and node
/// damping (every component alike), K φ = ω² M φ through M = L Lᵀ. The element's free nodes are the body's.
Result<ModalAnalysis> analyseElementModes(const BodyModel& model, int count, const NodeSprings& springs,
                                          const std::vector<int>& slot, ModalAnalysis result) {
    const ElementBody& e = *model.element;
    const int dof = result.unknowns;
    Eigen::MatrixXd stiffness = elementRestStiffness(e);
    const Eigen::MatrixXd viscosity = elementRestViscosity(e);
    const Eigen::MatrixXd mass = elementFreeMatrix(e, e.mass);
    Eigen::MatrixXd damping = elementFreeMatrix(e, e.nodeDamping);
    for (std::size_t a = 0; a < e.freeNodes.size(); ++a) {
        const std::uint32_t i = e.freeNodes[a];
        for (int c = 0; c < 3; ++c) {
            if (i < springs.stiffness.size())
                stiffness(Eigen::Index(3 * a) + c, Eigen::Index(3 * a) + c) += springs.stiffness[i];
            if (i < springs.damping.size())
                damping(Eigen::Index(3 * a) + c, Eigen::Index(3 * a) + c) += springs.damping[i];
        }
    }
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, mass);
    if (solver.info() != Eigen::Success)
        return Status::error("the eigenvalue solver did not converge on this body's solid element");
    const Eigen::VectorXd& lambda = solver.eigenvalues();  // ascending; eigenvectors M-normalised
    const int first = rigidModeCount(lambda);
    result.rigidModes = first;
    for (int m = first; m < dof && int(result.modes.size()) < count; ++m) {
        const Eigen::VectorXd phi = solver.eigenvectors().col(m);
        const double twoOmega = 2.0 * std::sqrt(lambda[m]);
        result.modes.push_back(makeMode(model, slot, phi, std::sqrt(lambda[m]), phi.dot(damping * phi) / twoOmega,
                                        phi.dot(viscosity * phi) / twoOmega));
    }
    return result;
}

}  // namespace

Result<ModalAnalysis> analyseModes(const BodyModel& model, int count, const NodeSprings& springs) {
    const std::size_t n = model.nodeCount();
    std::vector<int> slot(n, -1);
    int freeNodes = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (model.inverseMass[i] > 0.0)
            slot[i] = freeNodes++;
    }
    ModalAnalysis result;
    result.unknowns = 3 * freeNodes;
    if (freeNodes == 0)
        return Status::error("no node is free to move (every node is pinned or void), so the body has no modes");
    if (result.unknowns > kMaxModalUnknowns)
        return Status::error("modal analysis of " + std::to_string(freeNodes) + " free nodes (" +
                             std::to_string(result.unknowns) + " unknowns) is beyond the " +
                             std::to_string(kMaxModalUnknowns) + " SoftTouch solves; analyse a coarser lattice");

    const int dof = result.unknowns;
    if (model.element)
        return analyseElementModes(model, count, springs, slot, std::move(result));
    Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(dof, dof);
    Eigen::MatrixXd springDamping = Eigen::MatrixXd::Zero(dof, dof);
    for (const Spring& s : model.springs) {
        const int a = slot[s.a], b = slot[s.b];
        if ((a < 0 && b < 0) || s.restLength <= 0.0)
            continue;
        const Vec3 r = (model.restPositions[s.b] - model.restPositions[s.a]) / s.restLength;
        const Mat3 nn = r * r.transpose();
        addSpringBlock(stiffness, a, b, s.stiffness * nn);
        addSpringBlock(springDamping, a, b, s.damping * nn);
    }
    Eigen::VectorXd invSqrtMass(dof), nodeDamping(dof);
    for (std::size_t i = 0; i < n; ++i) {
        if (slot[i] < 0)
            continue;
        for (int c = 0; c < 3; ++c) {
            invSqrtMass[3 * slot[i] + c] = std::sqrt(model.inverseMass[i]);
            nodeDamping[3 * slot[i] + c] = model.nodeDamping[i] + (i < springs.damping.size() ? springs.damping[i] : 0.0);
            if (i < springs.stiffness.size())
                stiffness(3 * slot[i] + c, 3 * slot[i] + c) += springs.stiffness[i];
        }
    }
    // K φ = ω² M φ  <=>  (M^-½ K M^-½) ψ = ω² ψ with φ = M^-½ ψ, ψ orthonormal (so φᵀ M φ = 1).
    const Eigen::MatrixXd symmetric = invSqrtMass.asDiagonal() * stiffness * invSqrtMass.asDiagonal();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(symmetric);
    if (solver.info() != Eigen::Success)
        return Status::error("the eigenvalue solver did not converge on this body's stiffness");
    const Eigen::VectorXd& lambda = solver.eigenvalues();  // ascending
    const int first = rigidModeCount(lambda);
    result.rigidModes = first;

    for (int m = first; m < dof && int(result.modes.size()) < count; ++m) {
        const Eigen::VectorXd phi = invSqrtMass.asDiagonal() * solver.eigenvectors().col(m);
        const double omega = std::sqrt(lambda[m]);
        const double twoOmega = 2.0 * omega;
        result.modes.push_back(makeMode(model, slot, phi, omega, phi.cwiseProduct(nodeDamping).dot(phi) / twoOmega,
                                        phi.dot(springDamping * phi) / twoOmega));
    }
    return result;
}

int rigidModeCount(const Eigen::VectorXd& ascending) {
    const Eigen::Index n = ascending.size();
    if (n == 0)
        return 0;
    // Rigid motions have ω² = 0 up to round-off, which scales with the largest eigenvalue.
    const double rigidBelow = 1e-9 * std::max(std::abs(ascending[n - 1]), 1e-300);
    int first = 0;
    while (first < n && ascending[first] <= rigidBelow)
        ++first;
    return first;
}

std::vector<Vec3> modePose(std::span<const Vec3> rest, const VibrationMode& mode, double amplitude) {
    assert(rest.size() == mode.shape.size());
    std::vector<Vec3> pose(rest.begin(), rest.end());
    for (std::size_t i = 0; i < pose.size() && i < mode.shape.size(); ++i)
        pose[i] += amplitude * mode.shape[i];
    return pose;
}

}  // namespace softtouch

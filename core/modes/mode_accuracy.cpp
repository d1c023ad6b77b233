#include "core/modes/mode_accuracy.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace softtouch {

namespace {

/// One step of `kind` on the unit-mass oscillator q̈ = −ω² q − (a + s) q̇, where a is the rate of node
/// (absolute) damping and s that of spring (relative) damping, mirroring each scheme's code. The explicit
/// schemes solve with a mass 1 + h·stepMassRate (a viscous solid element's, elementStepViscosity()).
Eigen::Vector2d stepOscillator(IntegratorKind kind, double omega, double a, double s, double stepMassRate, double h,
                               Eigen::Vector2d state) {
    const double q = state[0], v = state[1];
    const double k = omega * omega;
    const double mass = 1.0 + h * stepMassRate;
    switch (kind) {
    case IntegratorKind::SymplecticEuler: {  // explicit_integrators.cpp: v += h f(x, v); x += h v
        const double vNext = v + h * (-k * q - (a + s) * v) / mass;
        return {q + h * vNext, vNext};
    }
    case IntegratorKind::Verlet: {  // central differences, node damping central, spring damping backward
        const double previous = q - h * v;
        const double c = 0.5 * h * a / mass;
        const double next = (2.0 * q - previous + h * h * (-k * q - s * v) / mass + c * previous) / (1.0 + c);
        return {next, (next - q) / h};
    }
    case IntegratorKind::ImplicitEuler: {  // v' = v + h f(x', v'), x' = x + h v' (exact for a linear body)
        const double vNext = (v - h * k * q) / (1.0 + h * (a + s) + h * h * k);
        return {q + h * vNext, vNext};
    }
    case IntegratorKind::Xpbd: {  // prediction with node damping as a force, then one compliant projection
        const double vPredicted = v - h * a * v;
        const double predicted = q + h * vPredicted;
        const double compliance = 1.0 / (k * h * h);
        const double gamma = s / (k * h);
        const double dlambda = (-predicted - gamma * (predicted - q)) / ((1.0 + gamma) + compliance);
        const double next = predicted + dlambda;
        return {next, (next - q) / h};
    }
    }
    return state;
}

/// The roots of λ² − trace·λ + determinant = 0 (the eigenvalues of a 2x2 step matrix, or of a two-term
/// recurrence's characteristic polynomial) as an oscillation: a complex pair r e^{±iθ} decays by r a
/// sample and turns by θ, so it keeps r^(2π/θ) per period.
struct RootPair {
    bool complex = false;    ///< A complex pair: the motion oscillates.
    double modulus = 0.0;    ///< r for a complex pair; the larger |root| otherwise.
    double angle = 0.0;      ///< θ, radians per sample (complex pair only).
    double perPeriod() const { return std::pow(modulus, 2.0 * std::numbers::pi / angle); }
};

RootPair rootsOf(double trace, double determinant) {
    RootPair r;
    const double halfTrace = 0.5 * trace;
    const double discriminant = halfTrace * halfTrace - determinant;
    if (discriminant < 0.0) {
        r.complex = true;
        r.modulus = std::sqrt(determinant);
        r.angle = std::atan2(std::sqrt(-discriminant), halfTrace);
    } else {
        const double root = std::sqrt(discriminant);
        r.modulus = std::max(std::abs(halfTrace + root), std::abs(halfTrace - root));
    }
    return r;
}

}  // namespace

ModeAccuracy modeAccuracy(IntegratorKind kind, const VibrationMode& mode, double h, double stepMassRate) {
    ModeAccuracy r;
    r.stepSeconds = h;
    const double omega = 2.0 * std::numbers::pi * mode.frequencyHz;
    const double a = 2.0 * mode.nodeDampingRatio * omega;
    const double s = 2.0 * mode.springDampingRatio * omega;
    Eigen::Matrix2d A;
    A.col(0) = stepOscillator(kind, omega, a, s, stepMassRate, h, {1.0, 0.0});
    A.col(1) = stepOscillator(kind, omega, a, s, stepMassRate, h, {0.0, 1.0});
    const double zeta = mode.dampingRatio;
    r.exactAmplitudePerPeriod = zeta < 1.0 ? std::exp(-2.0 * std::numbers::pi * zeta / std::sqrt(1.0 - zeta * zeta)) : 0.0;
    const RootPair roots = rootsOf(A.trace(), A.determinant());
    const double dampedHz = mode.dampedFrequencyHz();
    r.oscillates = roots.complex;
    r.stable = roots.modulus <= 1.0;
    if (roots.complex) {
        r.amplitudePerPeriod = roots.perPeriod();
        r.dampingRatio = dampingRatioKeeping(r.amplitudePerPeriod);
        r.frequencyHz = roots.angle / (2.0 * std::numbers::pi * h);
        r.frequencyError = dampedHz > 0.0 ? r.frequencyHz / dampedHz - 1.0 : 0.0;
    } else {
        // Two real eigenvalues: the numerical mode creeps or flips sign each step, it no longer swings.
        const double period = mode.frequencyHz > 0.0 ? 1.0 / mode.frequencyHz : 0.0;
        r.amplitudePerPeriod = std::pow(roots.modulus, period / h);
        r.dampingRatio = r.stable ? 1.0 : dampingRatioKeeping(r.amplitudePerPeriod);
        r.frequencyHz = 0.0;
        r.frequencyError = dampedHz > 0.0 ? -1.0 : 0.0;
    }
    return r;
}

FittedOscillation fitOscillation(const std::vector<double>& samples, double sampleSeconds) {
    FittedOscillation fit;
    if (samples.size() < 4)
        return fit;
    const Eigen::Index rows = Eigen::Index(samples.size()) - 2;
    Eigen::MatrixXd A(rows, 2);
    Eigen::VectorXd b(rows);
    for (Eigen::Index r = 0; r < rows; ++r) {
        A(r, 0) = samples[std::size_t(r + 1)];
        A(r, 1) = samples[std::size_t(r)];
        b[r] = samples[std::size_t(r + 2)];
    }
    const Eigen::Vector2d c = A.colPivHouseholderQr().solve(b);  // q_{n+1} = c0 q_n + c1 q_{n-1}
    const RootPair roots = rootsOf(c[0], -c[1]);
    if (!roots.complex)
        return fit;
    const double sigma = -std::log(roots.modulus) / sampleSeconds;
    const double omega = roots.angle / sampleSeconds;
    fit.oscillates = true;
    fit.frequencyHz = omega / (2.0 * std::numbers::pi);
    fit.dampingRatio = sigma / std::sqrt(sigma * sigma + omega * omega);
    fit.amplitudePerPeriod = roots.perPeriod();
    return fit;
}

std::vector<double> bakeModeProjection(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                                       const VibrationMode& mode, double amplitude, double seconds, int sampleEvery) {
    SimulationSettings quiet = settings;
    quiet.sleep = false;
    Simulator simulator(model, quiet);
    BodyState state = restState(*model);
    for (std::size_t i = 0; i < model->nodeCount(); ++i) {
        if (model->inverseMass[i] > 0.0)
            state.position[i] += amplitude * mode.shape[i];
    }
    updateVoidNodes(*model, state);
    simulator.restoreState(state, 0);
    std::vector<Vec3> displacement(model->nodeCount());
    auto project = [&](const BodyState& s) {
        for (std::size_t i = 0; i < model->nodeCount(); ++i)
            displacement[i] = s.position[i] - model->restPositions[i];
        return massInnerProduct(*model, mode.shape, displacement);
    };
    const long long steps = std::llround(seconds / settings.dt);
    std::vector<double> samples(std::size_t(steps / sampleEvery) + 1, 0.0);
    samples[0] = project(simulator.state());
    std::size_t written = 1;
    // By the simulator's clock: a rollback of the energy guard rewinds it, and the span is stepped again
    // over the samples it had taken.
    while (simulator.stepCount() < steps) {
        if (simulator.step({}).refused)
            break;  // the guard stopped the body: the samples end at its last accepted state
        const long long n = simulator.stepCount();
        if (n % sampleEvery == 0) {
            samples[std::size_t(n / sampleEvery)] = project(simulator.state());
            written = std::size_t(n / sampleEvery) + 1;
        }
    }
    samples.resize(written);
    return samples;
}

double spinKeptPerSecond(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings) {
    const std::size_t n = model->nodeCount();
    if (std::any_of(model->inverseMass.begin(), model->inverseMass.end(), [](double w) { return w == 0.0; }))
        return 1.0;  // anchored: it cannot spin freely
    // The centre of mass: each node's share of the mass (a consistent mass's row sums, ∫ρ N_i), as linearMomentum().
    double total = 0.0;
    for (const double m : model->mass)
        total += m;
    const auto centre = [&](const std::vector<Vec3>& x) {
        Vec3 c = Vec3::Zero();
        for (std::size_t i = 0; i < n; ++i)
            c += model->mass[i] * x[i];
        return Vec3(c / total);
    };
    const auto swirl = [&](const Vec3& axis, const std::vector<Vec3>& x) {  // axis × (x − c) at every node
        const Vec3 c = centre(x);
        std::vector<Vec3> u(n);
        for (std::size_t i = 0; i < n; ++i)
            u[i] = axis.cross(x[i] - c);
        return u;
    };
    // The principal axis of largest inertia (I_ab = <e_a × r, e_b × r> in the body's mass): a spin about it is stable.
    std::array<std::vector<Vec3>, 3> turned;
    for (int a = 0; a < 3; ++a)
        turned[std::size_t(a)] = swirl(Vec3::Unit(a), model->restPositions);
    Mat3 tensor;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            tensor(a, b) = massInnerProduct(*model, turned[std::size_t(a)], turned[std::size_t(b)]);
    const Eigen::SelfAdjointEigenSolver<Mat3> principal(tensor);
    const Vec3 axis = principal.eigenvectors().col(2);
    const double inertia = principal.eigenvalues()[2];
    if (!(inertia > 0.0))
        return 1.0;
    const double omega = 2.0 * std::numbers::pi;  // one turn a second: a tumble, not a blur
    SimulationSettings quiet = settings;
    quiet.sleep = false;
    Simulator simulator(model, quiet);
    BodyState state = restState(*model);
    const std::vector<Vec3> u = swirl(axis, state.position);
    for (std::size_t i = 0; i < n; ++i)
        state.velocity[i] = omega * u[i];
    simulator.restoreState(state, 0);
    const double start = omega * inertia;
    const long long steps = std::max(1LL, std::llround(1.0 / settings.dt));
    while (simulator.stepCount() < steps)
        if (simulator.step({}).refused)
            return 0.0;
    const BodyState& end = simulator.state();
    return massInnerProduct(*model, swirl(axis, end.position), end.velocity) / start;
}

std::string describeSpinKept(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings) {
    if (settings.integrator == IntegratorKind::Verlet)
        return {};
    SimulationSettings verlet = settings;
    verlet.integrator = IntegratorKind::Verlet;
    const double kept = spinKeptPerSecond(model, settings), material = spinKeptPerSecond(model, verlet);
    if (!(kept < material - kSpinLossShown))
        return {};
    char text[240];
    std::snprintf(text, sizeof text,
                  "%s at %.0f steps/s slows a free spin: one of a turn a second keeps %.1f%% of its angular momentum "
                  "after a second (the material alone: %.1f%%)",
                  std::string(integratorName(settings.integrator)).c_str(), 1.0 / settings.dt, 100.0 * kept, 100.0 * material);
    return text;
}

namespace {

/// The largest distance of a rest node from the first (a corner of the lattice): the body's size, which
/// the measuring runs' small displacements are fractions of.
double restExtent(const BodyModel& model) {
    double extent = 0.0;
    for (const Vec3& p : model.restPositions)
        extent = std::max(extent, (p - model.restPositions.front()).norm());
    return std::max(extent, 1e-9);
}

/// The substeps XPBD's energy guard settles on for `model`: a run from a small displacement of every free
/// node (every mode at once, as a drag or a collision starts them), long enough for growth to show (two
/// periods at `frequencyHz`, the body's lowest, and at least 256 steps). Its figures are measured there,
/// as the clip runs.
int guardedXpbdSubsteps(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                        double frequencyHz) {
    SimulationSettings quiet = settings;
    quiet.sleep = false;
    Simulator simulator(model, quiet);
    if (quiet.energyCheckSteps <= 0)
        return simulator.substepsFor({});
    const double extent = restExtent(*model);
    BodyState state = restState(*model);
    for (std::size_t i = 0; i < model->nodeCount(); ++i) {
        if (model->inverseMass[i] > 0.0) {
            const double k = double(i);
            state.position[i] += 1e-3 * extent * Vec3(std::sin(3.0 * k), std::cos(5.0 * k), std::sin(7.0 * k + 1.0));
        }
    }
    updateVoidNodes(*model, state);
    simulator.restoreState(state, 0);
    const double periods = frequencyHz > 0.0 ? 2.0 / (frequencyHz * settings.dt) : 0.0;
    const long long steps = std::max<long long>(256, std::llround(std::min(periods, 1e5)));
    while (simulator.stepCount() < steps)
        if (simulator.step({}).refused)
            break;
    return simulator.substepsFor({});
}

/// XPBD's figures for `mode`, measured on the scheme at `substeps` (the guard's): two periods (at least 8
/// steps) from a small displacement, 1e-4 of the body's size, fitted.
ModeAccuracy measuredXpbd(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                          const VibrationMode& mode, int substeps) {
    SimulationSettings guarded = settings;
    guarded.xpbdSubsteps = substeps;
    ModeAccuracy r = modeAccuracy(settings.integrator, mode, settings.dt / substeps);
    r.guardSubsteps = substeps > settings.xpbdSubsteps;
    const double seconds = std::max(2.0 / mode.frequencyHz, 8.0 * settings.dt);
    const FittedOscillation fit =
        fitOscillation(bakeModeProjection(model, guarded, mode, 1e-4 * restExtent(*model), seconds), settings.dt);
    r.oscillates = fit.oscillates;
    r.stable = !fit.oscillates || fit.amplitudePerPeriod <= 1.0;
    r.amplitudePerPeriod = fit.oscillates ? fit.amplitudePerPeriod : 0.0;
    r.dampingRatio = fit.oscillates ? dampingRatioKeeping(fit.amplitudePerPeriod) : 1.0;
    r.frequencyHz = fit.frequencyHz;
    const double damped = mode.dampedFrequencyHz();
    r.frequencyError = fit.oscillates && damped > 0.0 ? fit.frequencyHz / damped - 1.0 : -1.0;
    return r;
}

/// φᵀK̃_s φ / φᵀMφ for the mode's shape φ, 1/s: on a viscous solid element an explicit substep of h solves with
/// M + h K̃_s (elementStepViscosity()), so the mode moves as if 1 + h times this heavier; 0 otherwise.
double stepMassRate(const BodyModel& model, const SimulationSettings& settings, const VibrationMode& mode, double h) {
    const bool explicitScheme = settings.integrator == IntegratorKind::SymplecticEuler || settings.integrator == IntegratorKind::Verlet;
    if (!explicitScheme || !model.element || !model.element->viscous)
        return 0.0;
    const double mass = massInnerProduct(model, mode.shape, mode.shape);
    return mass > 0.0 ? elementStepViscosityProduct(*model.element, model.elementViscosityModes(), h, mode.shape) / mass : 0.0;
}

}  // namespace

std::vector<ModeAccuracy> schemeAccuracies(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                                           std::span<const VibrationMode> modes) {
    const double h = integrationStep(Simulator(model, settings));
    const bool xpbd = settings.integrator == IntegratorKind::Xpbd;
    // XPBD: the guard's substeps are the body's, found once from its lowest mode that vibrates.
    int substeps = 0;
    std::vector<ModeAccuracy> out;
    for (const VibrationMode& mode : modes) {
        if (!xpbd || mode.frequencyHz <= 0.0) {
            out.push_back(modeAccuracy(settings.integrator, mode, h, stepMassRate(*model, settings, mode, h)));
            continue;
        }
        if (substeps == 0)
            substeps = guardedXpbdSubsteps(model, settings, mode.frequencyHz);
        out.push_back(measuredXpbd(model, settings, mode, substeps));
    }
    return out;
}

ModeAccuracy schemeAccuracy(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                            const VibrationMode& mode) {
    return schemeAccuracies(model, settings, std::span(&mode, 1)).front();
}

double integrationStep(const Simulator& simulator, const ExternalForces& external) {
    const int substeps = std::max(1, simulator.substepsFor(external));
    return simulator.settings().dt / substeps;
}

double dampingRatioKeeping(double perPeriod) {
    if (!(perPeriod > 0.0))
        return 1.0;  // nothing kept: at least critically damped
    const double l = -std::log(perPeriod);  // negative for a growing mode, and so is ζ
    return l / std::sqrt(4.0 * std::numbers::pi * std::numbers::pi + l * l);
}

std::string describeModeAccuracy(const SimulationSettings& settings, const VibrationMode& mode, const ModeAccuracy& a) {
    const std::string name(integratorName(settings.integrator));
    const int substeps = int(std::lround(settings.dt / a.stepSeconds));
    char scheme[200];
    if (a.guardSubsteps)
        std::snprintf(scheme, sizeof scheme,
                      "%s at %.4g steps/s (%d substeps or more: at the project's %d this body gains energy, and the "
                      "energy guard substeps it)",
                      name.c_str(), 1.0 / settings.dt, substeps, settings.xpbdSubsteps);
    else if (substeps > 1)
        std::snprintf(scheme, sizeof scheme, "%s at %.4g steps/s (%d substeps)", name.c_str(), 1.0 / settings.dt, substeps);
    else
        std::snprintf(scheme, sizeof scheme, "%s at %.4g steps/s", name.c_str(), 1.0 / settings.dt);
    char text[480];
    if (!a.stable) {
        std::snprintf(text, sizeof text, "%s makes the %.3g Hz mode grow (x%.3g per period)", scheme, mode.frequencyHz,
                      a.amplitudePerPeriod);
    } else if (!a.oscillates) {
        std::snprintf(text, sizeof text, "%s no longer swings the %.3g Hz mode (it creeps back)", scheme, mode.frequencyHz);
    } else {
        std::snprintf(text, sizeof text,
                      "%s: the %.3g Hz mode damps as ζ %.3g in the clip (the material's %.3g), keeping %.1f%% per period "
                      "(the material alone: %.1f%%), frequency %+.1f%%",
                      scheme, mode.frequencyHz, a.dampingRatio, mode.dampingRatio, 100.0 * a.amplitudePerPeriod,
                      100.0 * a.exactAmplitudePerPeriod, 100.0 * a.frequencyError);
    }
    return text;
}

}  // namespace softtouch

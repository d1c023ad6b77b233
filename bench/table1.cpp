#include "bench/table1.h"

#include "bench/bullet_peer.h"
#include "bench/static_response.h"
#include "bench/surface_transfer.h"
#include "analysis/timer.h"
#include "analysis/trajectory_error.h"
#include "core/solver/integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <tuple>

namespace softtouch::bench {
namespace {

/// Below this error (fraction of the diagonal: 2.6 mm on these 1.3 m meshes) two runs look the same on
/// screen, so XPBD need not be more accurate than this even where implicit Euler is.
constexpr double kAccuracyFloor = 0.002;
/// Errors within this factor count as the same accuracy: the global mass-spring's converged runs
/// themselves differ by 0.5–1% of the diagonal (at 2,160 triangles: XPBD at 64 and 256 substeps, implicit
/// Euler at dt/16 and Verlet), because its wrinkles make it chaotic.
constexpr double kComparable = 1.25;
/// XPBD substeps tried on the local mass-spring (few nodes: even 128 is cheap) and on the global one, whose
/// converged run is XPBD at 4x the most tried.
constexpr int kMaxXpbdSubstepsLocal = 128;
constexpr int kMaxXpbdSubstepsGlobal = 32;
/// The global mass-spring's converged run. Verlet (below its stability bound), which converges fastest,
/// would take ~5 min at 24,928 triangles (its bound on the light nodes), implicit Euler at dt/16 longer still.
constexpr int kGlobalReferenceSubsteps = 4 * kMaxXpbdSubstepsGlobal;
/// The lattice's and the local mass-spring's converged run: Verlet at dt/4, substepped below its
/// stability bound (second order; at 2,160 triangles within 0.01% of implicit Euler at dt/16).
constexpr SolverSetting kVerletReference{IntegratorKind::Verlet, 1, 4};
constexpr int kBulletIterationLadder[] = {1, 2, 4, 8, 16};
constexpr double kBulletIterationTolerance = 0.01;
constexpr int kBulletReferenceFactor = 8;

double firstScale(const Table1Size* previous, Contender c) {
    const Table1Contender* before = previous ? previous->about(c) : nullptr;
    return before && before->calibration.scale > 0.0 ? before->calibration.scale : 1.0;
}

double prefixError(const ContenderRun& run, const ContenderRun& reference, int frames, std::size_t vertices,
                   double diagonal) {
    const std::size_t n = std::size_t(std::min({frames, run.framesRun, reference.framesRun})) * vertices;
    return analysis::trajectoryError(std::span<const Vec3f>(run.frames.data(), n), std::span<const Vec3f>(reference.frames.data(), n),
                           diagonal);
}

/// One contender's runs and their shared facts.
class RunRecorder {
public:
    RunRecorder(Table1Size& size, Contender contender, const ContenderRun& reference, const std::vector<Vec3f>& solid,
                double scale, double displacement)
        : m_size(size), m_contender(contender), m_reference(reference), m_solid(solid), m_scale(scale),
          m_displacement(displacement) {}

    Table1Run& add(const ContenderRun& run, std::string solver, int iterations, std::string role) {
        Table1Run row;
        row.contender = m_contender;
        row.solver = std::move(solver);
        row.iterations = iterations;
        row.seconds = run.scenarioSeconds();
        row.stopped = run.stopped();
        row.scale = m_scale;
        row.displacement = m_displacement;
        row.error = prefixError(run, m_reference, run.framesRun, m_size.vertices, m_size.diagonal);
        row.finite = run.finite;
        row.role = std::move(role);
        const bool whole = !run.stopped() && run.finite;
        row.solidError = whole ? analysis::trajectoryError(run.frames, m_solid, m_size.diagonal)
                               : std::numeric_limits<double>::quiet_NaN();
        m_size.runs.push_back(row);
        m_size.runFrames.push_back(whole ? run.frames : std::vector<Vec3f>{});
        return m_size.runs.back();
    }

private:
    Table1Size& m_size;
    Contender m_contender;
    const ContenderRun& m_reference;
    const std::vector<Vec3f>& m_solid;
    double m_scale, m_displacement;
};

Calibration calibrateOurs(const InteractionScenario& s, Contender c, double target, double first) {
    std::vector<Vec3> equilibrium;  // each settle starts where the last ended
    const StaticDisplacement settle = [&](double scale) {
        const OurBody body(s, c, scale);
        const StaticResponse r = settleOurs(s, body, &equilibrium);
        return CalibrationStep{scale, r.displacement, r.steps};
    };
    return calibrate(settle, target, s.dragOffset.norm(), first, kEqualResponseTolerance, kEqualResponseEvaluations);
}

void lattice(const InteractionScenario& s, Table1Size& size, const Table1Size* previous, const std::vector<Vec3f>& solid) {
    Table1Contender about{Contender::Lattice, calibrateOurs(s, Contender::Lattice, size.target, firstScale(previous, Contender::Lattice)),
                          "verlet dt/4", 0.0, true, 0, {}};
    const OurBody body(s, Contender::Lattice, about.calibration.scale);
    const ContenderRun reference = runContender(s, body, kVerletReference);
    RunRecorder record(size, Contender::Lattice, reference, solid, about.calibration.scale, about.calibration.displacement);
    record.add(runContender(s, body, {IntegratorKind::ImplicitEuler, 1, 1}), "implicit-euler", 1, "paper").best = true;
    record.add(runContender(s, body, {IntegratorKind::Xpbd, 8, 1}), "xpbd", 8, "other");
    record.add(runContender(s, body, {IntegratorKind::Verlet, 1, 1}), "verlet", 1, "other");
    size.contenders.push_back(std::move(about));
}

/// A mass-spring on the mesh: implicit Euler, then XPBD with doubling substeps until it is as accurate
/// (on the frames implicit Euler reached, when that was stopped); the cheaper of the two is its time.
/// Where no substep count tried is as accurate, the cheaper of implicit Euler and the most accurate XPBD
/// is its time, marked as not matched: a peer's time is never overstated, so the lattice's ratio is then
/// a lower bound.
void massSpring(const InteractionScenario& s, Contender c, Table1Size& size, const Table1Size* previous,
                const Table1Options& options, const std::vector<Vec3f>& solid) {
    Table1Contender about{c, calibrateOurs(s, c, size.target, firstScale(previous, c)), "", 0.0, false, 0, {}};
    const OurBody body(s, c, about.calibration.scale);
    const SolverSetting referenceSetting =
        c == Contender::Global ? SolverSetting{IntegratorKind::Xpbd, kGlobalReferenceSubsteps, 1} : kVerletReference;
    about.reference = c == Contender::Global ? "xpbd x" + std::to_string(kGlobalReferenceSubsteps) : "verlet dt/4";
    const ContenderRun reference = runContender(s, body, referenceSetting);
    RunRecorder record(size, c, reference, solid, about.calibration.scale, about.calibration.displacement);

    const double budget = c == Contender::Global ? options.implicitBudgetSeconds : 0.0;
    const ContenderRun implicitRun = runContender(s, body, {IntegratorKind::ImplicitEuler, 1, 1}, budget);
    const std::size_t implicitIndex = size.runs.size();
    record.add(implicitRun, "implicit-euler", 1, "implicit");
    about.accuracyGoal = std::max(size.runs[implicitIndex].error, kAccuracyFloor);

    std::size_t xpbdIndex = 0;
    const int maxSubsteps = c == Contender::Global ? kMaxXpbdSubstepsGlobal : kMaxXpbdSubstepsLocal;
    for (int substeps = 1; substeps <= maxSubsteps; substeps *= 2) {
        const ContenderRun xpbd = runContender(s, body, {IntegratorKind::Xpbd, substeps, 1});
        const double comparable = prefixError(xpbd, reference, implicitRun.framesRun, size.vertices, size.diagonal);
        about.accuracyMatched = comparable <= kComparable * about.accuracyGoal;
        xpbdIndex = size.runs.size();
        record.add(xpbd, "xpbd", substeps, about.accuracyMatched ? "matched" : "ladder");
        if (about.accuracyMatched)
            break;
    }
    if (!about.accuracyMatched)
        size.runs[xpbdIndex].role = "most accurate";
    const bool xpbdCheaper = size.runs[xpbdIndex].seconds < size.runs[implicitIndex].seconds;
    size.runs[xpbdCheaper ? xpbdIndex : implicitIndex].best = true;
    size.contenders.push_back(std::move(about));
}

/// Bullet: the iteration count its static displacement converges at, calibrated there; also its default
/// of one iteration at the same stiffness.
void bullet(const InteractionScenario& s, Table1Size& size, const Table1Size* previous, const std::vector<Vec3f>& solid) {
    Table1Contender about{Contender::Bullet, {}, "", 0.0, true, 0, {}};
    std::map<std::pair<int, double>, CalibrationStep> settled;  // (iterations, scale) -> result
    const auto settle = [&](int iterations, double scale) {
        const auto key = std::make_pair(iterations, scale);
        if (auto it = settled.find(key); it != settled.end())
            return it->second;
        const std::optional<StaticResponse> r = settleBullet(s, {scale, iterations});
        const CalibrationStep step{scale, r ? r->displacement : 0.0, r ? r->steps : 0};
        settled[key] = step;
        return step;
    };
    const double first = firstScale(previous, Contender::Bullet);
    for (int iterations : kBulletIterationLadder) {
        CalibrationStep step = settle(iterations, first);
        if (!(step.displacement > 0.0))
            return;  // Bullet cannot take this mesh
        step.scale = iterations;
        about.iterationCheck.push_back(step);
    }
    // The converged count: the first whose displacement is within 1% of every larger count's.
    about.bulletIterations = kBulletIterationLadder[std::size(kBulletIterationLadder) - 1];
    for (std::size_t i = 0; i < about.iterationCheck.size(); ++i) {
        const double d = about.iterationCheck[i].displacement;
        const bool settledHere = std::all_of(about.iterationCheck.begin() + std::ptrdiff_t(i), about.iterationCheck.end(),
                                             [&](const CalibrationStep& later) {
                                                 return std::abs(later.displacement - d) <= kBulletIterationTolerance * d;
                                             });
        if (settledHere) {
            about.bulletIterations = int(about.iterationCheck[i].scale);
            break;
        }
    }
    const int n = about.bulletIterations;
    about.calibration = calibrate([&](double scale) { return settle(n, scale); }, size.target, s.dragOffset.norm(), first,
                                  kEqualResponseTolerance, kEqualResponseEvaluations);
    const double scale = about.calibration.scale;
    const int referenceIterations = kBulletReferenceFactor * n;
    about.reference = "bullet x" + std::to_string(referenceIterations);
    const std::optional<ContenderRun> reference = runBullet(s, {scale, referenceIterations});
    const std::optional<ContenderRun> converged = runBullet(s, {scale, n});
    const std::optional<ContenderRun> defaultRun = runBullet(s, {scale, 1});
    if (!reference || !converged || !defaultRun)
        return;
    RunRecorder record(size, Contender::Bullet, *reference, solid, scale, about.calibration.displacement);
    record.add(*converged, "bullet", n, "converged").best = true;
    record.add(*defaultRun, "bullet", 1, "default").displacement = settle(1, scale).displacement;
    size.contenders.push_back(std::move(about));
}

/// Every run of this size, and every whole run of the mesh bodies on the smaller sizes carried onto this mesh,
/// against the solid.
void grade(Table1Size& size, std::span<const Table1Size> smaller, const std::vector<Vec3f>& solid) {
    for (const Table1Run& r : size.runs) {
        if (std::isfinite(r.solidError))
            size.graded.push_back({r.contender, size.triangles, r.solver, r.iterations, r.scale, r.seconds, 0.0, r.solidError});
    }
    for (const Table1Size& coarse : smaller) {
        const SurfaceTransfer carry(coarse.mesh, size.mesh.positions);
        for (std::size_t i = 0; i < coarse.runs.size(); ++i) {
            // The lattice deforms the user's mesh whatever its size, so only the mesh bodies, which simulate
            // the mesh itself, may run a coarser one.
            if (coarse.runFrames[i].empty() || coarse.runs[i].contender == Contender::Lattice)
                continue;
            const Table1Run& r = coarse.runs[i];
            analysis::Stopwatch watch;
            const std::vector<Vec3f> frames = carry.apply(coarse.runFrames[i], coarse.mesh.positions);
            const double carrying = watch.seconds();
            size.graded.push_back({r.contender, coarse.triangles, r.solver, r.iterations, r.scale, r.seconds + carrying,
                                   carrying, analysis::trajectoryError(frames, solid, size.diagonal)});
        }
    }
}

/// One setting run again on its own mesh: its time, without carrying.
double rerun(const Table1Graded& g) {
    const InteractionScenario s = makeScenario(makeEllipsoid(g.triangles));
    if (g.contender == Contender::Bullet) {
        const std::optional<ContenderRun> run = runBullet(s, {g.scale, g.iterations});
        return run ? run->scenarioSeconds() : std::numeric_limits<double>::infinity();
    }
    const OurBody body(s, g.contender, g.scale);
    return runContender(s, body, {parseIntegratorKind(g.solver).value(), g.iterations, 1}).seconds;
}

/// Each setting timed `timings` times in all, the time it was measured at first among them, and once per
/// size: a run the equal-response table shows and the same run picked at equal accuracy have one time.
class Timings {
public:
    explicit Timings(int timings) : m_timings(timings) {}
    /// The fastest and slowest time of `g`'s setting, its carrying added.
    std::pair<double, double> of(const Table1Graded& g) {
        const auto key = std::make_tuple(g.contender, g.triangles, g.solver, g.iterations);
        auto it = m_done.find(key);
        if (it == m_done.end()) {
            double fastest = g.seconds - g.carrying, slowest = fastest;
            for (int i = 1; i < m_timings; ++i) {
                const double t = rerun(g);
                fastest = std::min(fastest, t);
                slowest = std::max(slowest, t);
            }
            it = m_done.emplace(key, std::make_pair(fastest, slowest)).first;
        }
        return {it->second.first + g.carrying, it->second.second + g.carrying};
    }

private:
    int m_timings;
    std::map<std::tuple<Contender, int, std::string, int>, std::pair<double, double>> m_done;
};

/// Each contender's cheapest graded run at least as close to the solid as the lattice's paper row (its most
/// accurate when none is), timed best of the timings.
void pick(Table1Size& size, Timings& timings) {
    const Table1Run* paper = size.find(Contender::Lattice, "paper");
    size.accuracyGoal = paper ? paper->solidError : 0.0;
    for (const Table1Contender& c : size.contenders) {
        const Table1Graded* cheapest = nullptr;
        const Table1Graded* closest = nullptr;
        for (const Table1Graded& g : size.graded) {
            if (g.contender != c.contender)
                continue;
            if (g.solidError <= size.accuracyGoal && (!cheapest || g.seconds < cheapest->seconds))
                cheapest = &g;
            if (!closest || g.solidError < closest->solidError)
                closest = &g;
        }
        if (!closest)
            continue;
        Table1Pick p;
        p.reached = cheapest != nullptr;
        p.run = p.reached ? *cheapest : *closest;
        std::tie(p.fastest, p.slowest) = timings.of(p.run);
        size.picks.push_back(p);
    }
}

/// The runs the equal-response table shows (each contender's best, Bullet's default) timed best of the
/// timings. A stopped run keeps its extrapolation.
void retimeBest(Table1Size& size, Timings& timings) {
    for (Table1Run& r : size.runs) {
        if ((!r.best && r.role != "default") || r.stopped)
            continue;
        r.seconds = timings.of({r.contender, size.triangles, r.solver, r.iterations, r.scale, r.seconds, 0.0, r.solidError}).first;
    }
}

void logCalibration(const Table1Contender& c, std::ostream& log) {
    char line[200];
    std::snprintf(line, sizeof line, "    %-7s scale %9.4g  displacement %.4f m  %s in %zu settles (",
                  std::string(contenderName(c.contender)).c_str(), c.calibration.scale, c.calibration.displacement,
                  c.calibration.converged ? "converged" : c.calibration.saturated ? "SATURATED" : "NOT converged", c.calibration.steps.size());
    log << line;
    for (std::size_t i = 0; i < c.calibration.steps.size(); ++i) {
        std::snprintf(line, sizeof line, "%s%.3g -> %.4f", i ? ", " : "", c.calibration.steps[i].scale,
                      c.calibration.steps[i].displacement);
        log << line;
    }
    log << ")";
    if (c.bulletIterations > 0) {
        log << "; iterations:";
        for (const CalibrationStep& step : c.iterationCheck) {
            std::snprintf(line, sizeof line, " %g -> %.4f", step.scale, step.displacement);
            log << line;
        }
        log << ", converged at " << c.bulletIterations;
    }
    log << "\n" << std::flush;
}

}  // namespace

const Table1Run* Table1Size::best(Contender contender) const {
    for (const Table1Run& r : runs) {
        if (r.contender == contender && r.best)
            return &r;
    }
    return nullptr;
}

const Table1Run* Table1Size::find(Contender contender, const std::string& role) const {
    for (const Table1Run& r : runs) {
        if (r.contender == contender && r.role == role)
            return &r;
    }
    return nullptr;
}

const Table1Pick* Table1Size::pick(Contender contender) const {
    for (const Table1Pick& p : picks) {
        if (p.run.contender == contender)
            return &p;
    }
    return nullptr;
}

const Table1Contender* Table1Size::about(Contender contender) const {
    for (const Table1Contender& c : contenders) {
        if (c.contender == contender)
            return &c;
    }
    return nullptr;
}

Table1Size measureTable1Size(int triangles, const Table1Options& options, std::span<const Table1Size> smaller,
                             std::ostream& log) {
    const InteractionScenario s = makeScenario(makeEllipsoid(triangles));
    const Table1Size* previous = smaller.empty() ? nullptr : &smaller.back();
    Table1Size size;
    size.triangles = triangles;
    size.vertices = s.mesh.positions.size();
    size.diagonal = s.mesh.bounds().diagonal();
    size.target = options.targetFraction * size.diagonal;
    size.mesh = s.mesh;
    char line[120];
    std::snprintf(line, sizeof line, "  %d triangles: target %.4f m; the common reference:\n", triangles, size.target);
    log << line << std::flush;
    const double firstSolid =
        previous && previous->reference.calibration.scale > 0.0 ? previous->reference.calibration.scale : 1.0;
    size.reference = solidReference(s, size.target, firstSolid, options.reference, log);
    const std::vector<Vec3f>& solid = size.reference.frames;
    log << "    calibration:\n" << std::flush;
    lattice(s, size, previous, solid);
    logCalibration(size.contenders.back(), log);
    massSpring(s, Contender::Global, size, previous, options, solid);
    logCalibration(size.contenders.back(), log);
    massSpring(s, Contender::Local, size, previous, options, solid);
    logCalibration(size.contenders.back(), log);
    if (options.bullet && bulletAvailable()) {
        bullet(s, size, previous, solid);
        if (size.about(Contender::Bullet))
            logCalibration(size.contenders.back(), log);
    }
    grade(size, smaller, solid);
    Timings timings(options.timings);
    pick(size, timings);
    retimeBest(size, timings);
    return size;
}

}  // namespace softtouch::bench

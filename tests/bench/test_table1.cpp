// Table 1 at equal response (bench/table1.h): the calibration brings every contender to the same static
// displacement, and every run reports a finite error against its own converged run. Timings are
// measured but never asserted (they are too noisy; docs/measurements/performance.md compares them).
#include "bench/bullet_peer.h"
#include "bench/equal_response.h"
#include "bench/table1.h"
#include "bench/table1_report.h"
#include "analysis/trajectory_error.h"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

using namespace softtouch;
using namespace softtouch::bench;
using softtouch::analysis::trajectoryError;

namespace {

/// The mesh the calibration is checked on: small enough for seconds, fine enough to wrinkle.
constexpr int kTriangles = 832;
constexpr double kEqualResponse = 0.05;  ///< The brief's "same static displacement (±5%)".

std::string name(Contender c) { return std::string(contenderName(c)); }

}  // namespace

class TestTable1 : public QObject {
    Q_OBJECT
private slots:
    void calibrateSolvesASeriesSpringInOneStep();
    void calibrateStopsWhereStiffeningNoLongerHelps();
    void trajectoryErrorOfAUniformShiftIsTheShift();
    void everyContenderIsCalibrated();
    void calibratedDisplacementsAgreeWithinFivePercent();
    void everyRunReportsAFiniteErrorAgainstItsOwnConvergedRun();
    void eachMassSpringIsTimedWithBothSolversAndOneIsBest();
    void bulletReportsItsConvergedAndDefaultIterations();
    void jsonCarriesWhatTheDocsList();

private:
    /// One size, measured on first use (about three seconds; each test function runs in its own process).
    const Table1Size& size();

    std::optional<Table1Size> m_size;
    Table1Options m_options;
};

const Table1Size& TestTable1::size() {
    if (!m_size) {
        std::ostringstream log;
        m_size = measureTable1Size(kTriangles, m_options, nullptr, log);
        qInfo("%s", log.str().c_str());
    }
    return *m_size;
}

void TestTable1::calibrateSolvesASeriesSpringInOneStep() {
    // A linear body k_b·scale in series with the drag spring Ks: the first step's model is exact.
    const double reach = 0.25, ks = 50.0, kb = 40.0, target = 0.1;
    int calls = 0;
    const Calibration c = calibrate(
        [&](double scale) {
            ++calls;
            return CalibrationStep{scale, reach * ks / (ks + kb * scale), 0};
        },
        target, reach, 1.0);
    QVERIFY(c.converged);
    QCOMPARE(calls, 2);
    QVERIFY(std::abs(c.displacement / target - 1.0) < 1e-9);
    QVERIFY(std::abs(c.scale - ks * (reach / target - 1.0) / kb) < 1e-9);
}

void TestTable1::calibrateStopsWhereStiffeningNoLongerHelps() {
    // A displacement that cannot fall below 0.2 however stiff (Bullet's links at full projection).
    const Calibration c = calibrate(
        [](double scale) { return CalibrationStep{scale, 0.2 + 0.05 / (1.0 + scale), 0}; }, 0.15, 0.25, 1.0);
    QVERIFY(!c.converged);
    QVERIFY(c.saturated);
    QVERIFY(c.steps.size() < 8);
    QVERIFY(c.displacement < 0.21);  // the closest it got is what is reported
}

void TestTable1::trajectoryErrorOfAUniformShiftIsTheShift() {
    const std::vector<Vec3f> reference(100, Vec3f(1.0f, 2.0f, 3.0f));
    std::vector<Vec3f> run = reference;
    for (Vec3f& p : run)
        p += Vec3f(0.0f, 0.03f, 0.04f);  // 0.05 m everywhere
    QVERIFY(std::abs(trajectoryError(run, reference, 2.0) - 0.025) < 1e-6);
    QCOMPARE(trajectoryError(reference, reference, 2.0), 0.0);
}

void TestTable1::everyContenderIsCalibrated() {
    QVERIFY(size().about(Contender::Lattice));
    QVERIFY(size().about(Contender::Global));
    QVERIFY(size().about(Contender::Local));
    QCOMPARE(size().about(Contender::Bullet) != nullptr, bulletAvailable());
    for (const Table1Contender& c : size().contenders) {
        QVERIFY2(!c.calibration.steps.empty(), name(c.contender).c_str());
        QVERIFY2(c.calibration.scale > 0.0 && std::isfinite(c.calibration.scale), name(c.contender).c_str());
    }
}

void TestTable1::calibratedDisplacementsAgreeWithinFivePercent() {
    QVERIFY(size().target > 0.0);
    for (const Table1Contender& c : size().contenders) {
        const double off = c.calibration.displacement / size().target - 1.0;
        QVERIFY2(std::abs(off) <= kEqualResponse,
                 qPrintable(QString("%1: %2 m against the target %3 m (%4%)")
                                .arg(name(c.contender).c_str())
                                .arg(c.calibration.displacement)
                                .arg(size().target)
                                .arg(100.0 * off)));
    }
    // Every timed run of a calibrated body reports that body's displacement, except Bullet's default (it
    // keeps the converged count's stiffness: its own displacement is reported, not calibrated).
    for (const Table1Run& r : size().runs) {
        if (r.role == "default")
            continue;
        QVERIFY2(std::abs(r.displacement / size().target - 1.0) <= kEqualResponse, (name(r.contender) + " " + r.solver).c_str());
    }
}

void TestTable1::everyRunReportsAFiniteErrorAgainstItsOwnConvergedRun() {
    QVERIFY(!size().runs.empty());
    for (const Table1Run& r : size().runs) {
        const std::string what = name(r.contender) + " " + r.solver + " x" + std::to_string(r.iterations);
        QVERIFY2(r.finite, what.c_str());
        QVERIFY2(std::isfinite(r.error) && r.error >= 0.0, what.c_str());
        // An error above the whole drag would mean the run and its reference are not the same body.
        QVERIFY2(r.error < 0.2, what.c_str());
        QVERIFY2(r.seconds > 0.0, what.c_str());
    }
    for (const Table1Contender& c : size().contenders)
        QVERIFY2(!c.reference.empty(), name(c.contender).c_str());
}

void TestTable1::eachMassSpringIsTimedWithBothSolversAndOneIsBest() {
    for (Contender c : {Contender::Global, Contender::Local}) {
        QVERIFY2(size().find(c, "implicit"), name(c).c_str());
        bool xpbd = false;
        int best = 0;
        for (const Table1Run& r : size().runs) {
            if (r.contender != c)
                continue;
            xpbd = xpbd || r.solver == "xpbd";
            best += r.best ? 1 : 0;
        }
        QVERIFY2(xpbd, name(c).c_str());
        QCOMPARE(best, 1);
        // The best is implicit Euler, or an XPBD run as accurate; or, where no substep count tried was, the
        // cheaper of implicit Euler and the most accurate XPBD (so the lattice's ratio is a lower bound).
        const Table1Run* b = size().best(c);
        const Table1Contender* about = size().about(c);
        QVERIFY(b->role == "implicit" || (about->accuracyMatched ? b->role == "matched" : b->role == "most accurate"));
    }
    QVERIFY(size().best(Contender::Lattice));
    QCOMPARE(size().best(Contender::Lattice)->solver, std::string("implicit-euler"));
}

void TestTable1::bulletReportsItsConvergedAndDefaultIterations() {
    if (!bulletAvailable())
        QSKIP("built without Bullet");
    const Table1Contender* bullet = size().about(Contender::Bullet);
    QVERIFY(bullet);
    QVERIFY(bullet->bulletIterations >= 1);
    QVERIFY(!bullet->iterationCheck.empty());
    // The count chosen is within 1% of every larger count tried.
    for (const CalibrationStep& step : bullet->iterationCheck) {
        if (int(step.scale) < bullet->bulletIterations)
            continue;
        const double chosen = std::find_if(bullet->iterationCheck.begin(), bullet->iterationCheck.end(), [&](const auto& s) {
                                  return int(s.scale) == bullet->bulletIterations;
                              })->displacement;
        QVERIFY(std::abs(step.displacement - chosen) <= 0.01 * chosen);
    }
    const Table1Run* converged = size().find(Contender::Bullet, "converged");
    const Table1Run* defaultRun = size().find(Contender::Bullet, "default");
    QVERIFY(converged && defaultRun);
    QCOMPARE(converged->iterations, bullet->bulletIterations);
    QCOMPARE(defaultRun->iterations, 1);
    QCOMPARE(defaultRun->scale, converged->scale);
    QVERIFY(std::isfinite(defaultRun->displacement) && defaultRun->displacement > 0.0);
}

void TestTable1::jsonCarriesWhatTheDocsList() {
    const nlohmann::json row = table1Json(size(), m_options);
    for (const char* key : {"triangles", "target_m", "target_fraction", "lattice_s", "global_s", "local_s",
                            "bullet_s", "bullet_default_s", "ratios", "contenders", "runs", "finite"})
        QVERIFY2(row.contains(key), key);
    for (const auto& run : row["runs"]) {
        for (const char* key : {"contender", "solver", "iterations", "seconds", "extrapolated", "scale",
                                "displacement_m", "error", "role", "best"})
            QVERIFY2(run.contains(key), key);
    }
    for (const char* contender : {"lattice", "global", "local"}) {
        QVERIFY2(row["contenders"].contains(contender), contender);
        for (const char* key : {"scale", "displacement_m", "calibrated", "calibration", "reference"})
            QVERIFY2(row["contenders"][contender].contains(key), key);
    }
}

QTEST_GUILESS_MAIN(TestTable1)
#include "test_table1.moc"

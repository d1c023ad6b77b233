// The speed/accuracy study measures what it claims: integrator character, convergence, Pareto front.
#include "bench/study.h"
#include "io/project_file.h"

#include <QtTest>
#include <sstream>

using namespace softtouch;
using namespace softtouch::bench;

class TestStudy : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void everyRowIsFiniteAndPriced();
    void implicitEulerDampsAndSymplecticDoesNot();
    void smallerStepsAreMoreAccurate();
    void paretoFrontIsNotDominated();
    void targetPicksTheCheapestAccurateSetting();
    void csvAndMarkdownHoldEveryRow();

private:
    const StudyRow& row(IntegratorKind kind, double dt, const std::string& resolution) const;
    StudyResult m_result;
};

void TestStudy::initTestCase() {
    auto project = io::loadProject(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-swim.softtouch");
    QVERIFY2(project.ok(), project.message().c_str());
    StudyOptions options;
    options.quick = true;
    std::ostringstream log;
    m_result = runStudy(project->scene, options, log);
    QCOMPARE(int(m_result.rows.size()), 4 * 3 * 3);  // integrators x dt x resolutions (quick)
}

const StudyRow& TestStudy::row(IntegratorKind kind, double dt, const std::string& resolution) const {
    for (const StudyRow& r : m_result.rows) {
        if (r.integrator == kind && std::abs(r.dt - dt) < 1e-12 && r.resolution == resolution)
            return r;
    }
    qFatal("no study row for %s", resolution.c_str());
}

void TestStudy::everyRowIsFiniteAndPriced() {
    QVERIFY(m_result.referenceUncertainty < 1e-3);
    for (const StudyRow& r : m_result.rows) {
        QVERIFY(r.finite);
        QVERIFY(r.costPerSecond > 0.0);
        QVERIFY(r.rmsError > 0.0 && r.rmsError <= r.maxError);
        QVERIFY(std::isfinite(r.energyDrift));
    }
}

void TestStudy::implicitEulerDampsAndSymplecticDoesNot() {
    // Implicit Euler's numerical damping grows with the step; symplectic Euler and Verlet lose
    // (next to) nothing beyond what the converged motion loses.
    for (const std::string res : {"3x3x3 bezier", "4x4x4 bezier"}) {
        const StudyRow& fine = row(IntegratorKind::ImplicitEuler, 1.0 / 240, res);
        const StudyRow& coarse = row(IntegratorKind::ImplicitEuler, 1.0 / 24, res);
        QVERIFY2(coarse.amplitudeLoss > 0.2 && coarse.amplitudeLoss > fine.amplitudeLoss + 0.1,
                 qPrintable(QString("%1: loss %2 at 1/24 vs %3 at 1/240").arg(QString::fromStdString(res)).arg(coarse.amplitudeLoss).arg(fine.amplitudeLoss)));
        QVERIFY(coarse.energyDrift < -0.5);
        for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet}) {
            for (double dt : {1.0 / 240, 1.0 / 60, 1.0 / 24})
                QVERIFY2(std::abs(row(k, dt, res).amplitudeLoss) < 0.05,
                         qPrintable(QString("%1 loses %2 per period").arg(QString::fromLatin1(integratorName(k).data())).arg(row(k, dt, res).amplitudeLoss)));
        }
        // Its frequency error has the sign of numerical damping (slower) and grows with dt.
        QVERIFY(coarse.frequencyError < fine.frequencyError);
    }
}

void TestStudy::smallerStepsAreMoreAccurate() {
    for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                             IntegratorKind::Xpbd}) {
        const double fine = row(k, 1.0 / 240, "4x4x4 bezier").timeError;
        const double coarse = row(k, 1.0 / 24, "4x4x4 bezier").timeError;
        QVERIFY2(fine < coarse, qPrintable(QString("%1: time error %2 at 1/240 vs %3 at 1/24")
                                               .arg(QString::fromLatin1(integratorName(k).data())).arg(fine).arg(coarse)));
    }
}

void TestStudy::paretoFrontIsNotDominated() {
    int front = 0;
    for (const StudyRow& a : m_result.rows) {
        if (!a.pareto)
            continue;
        ++front;
        for (const StudyRow& b : m_result.rows)
            QVERIFY(!(b.costPerSecond < a.costPerSecond && b.rmsError < a.rmsError));
    }
    QVERIFY(front >= 1);
    // The cheapest row overall is always on the front.
    const auto cheapest = std::min_element(m_result.rows.begin(), m_result.rows.end(),
                                           [](const StudyRow& a, const StudyRow& b) { return a.costPerSecond < b.costPerSecond; });
    QVERIFY(cheapest->pareto);
}

void TestStudy::targetPicksTheCheapestAccurateSetting() {
    double best = 1e300;
    for (const StudyRow& r : m_result.rows)
        best = std::min(best, r.rmsError);
    QVERIFY(cheapestWithin(m_result, best * 0.5) == nullptr);
    const double target = best * 1.5;
    const StudyRow* pick = cheapestWithin(m_result, target);
    QVERIFY(pick != nullptr);
    QVERIFY(pick->rmsError <= target);
    for (const StudyRow& r : m_result.rows) {
        if (r.rmsError <= target)
            QVERIFY(r.costPerSecond >= pick->costPerSecond);
    }
}

void TestStudy::csvAndMarkdownHoldEveryRow() {
    const std::string csv = studyCsv(m_result);
    QCOMPARE(int(std::count(csv.begin(), csv.end(), '\n')), int(m_result.rows.size()) + 1);
    QVERIFY(csv.rfind("integrator,dt_s,resolution", 0) == 0);
    const std::string md = studyMarkdown(m_result, "softtouch-cli study X --quick");
    QVERIFY(md.find("softtouch-cli study X --quick") != std::string::npos);
    QVERIFY(md.find("## Pareto front") != std::string::npos);
}

QTEST_GUILESS_MAIN(TestStudy)
#include "test_study.moc"

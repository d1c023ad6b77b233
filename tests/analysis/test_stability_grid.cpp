// Stability at the extremes: the quick grid of analysis/stability_grid.h, asserted cell by cell. The full
// grid is docs/measurements/stability.md (softtouch-cli stability --out docs/measurements/stability.md).
#include "analysis/stability_grid.h"

#include <QtTest>

#include <algorithm>
#include <cstdio>
#include <string>

using namespace softtouch;
using namespace softtouch::analysis;
using Outcome = StabilityCell::Outcome;

namespace {

constexpr IntegratorKind kAll[] = {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet,
                                   IntegratorKind::ImplicitEuler, IntegratorKind::Xpbd};

std::string describe(const StabilityCell& c) {
    char text[200];
    std::snprintf(text, sizeof text, "%s k=%g r=%g m=%g c=%g %s (dt %.3g s): %s, ",
                  std::string(integratorName(c.integrator)).c_str(), c.stiffness, c.massRatio, c.nodeMass,
                  c.damping, c.dtLabel.c_str(), c.dt, std::string(outcomeName(c.outcome)).c_str());
    return text + c.note;
}

/// One line per offending cell (at most 20), or empty.
template <typename Predicate>
std::string offenders(const std::vector<StabilityCell>& cells, Predicate bad) {
    std::string text;
    int count = 0;
    for (const StabilityCell& c : cells) {
        if (!bad(c))
            continue;
        if (++count <= 20)
            text += "\n  " + describe(c);
    }
    if (count > 20)
        text += "\n  ... and " + std::to_string(count - 20) + " more";
    return count ? std::to_string(count) + " cells:" + text : std::string();
}

}  // namespace

class TestStabilityGrid : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void everyRunIsThere();
    void noExportedFrameIsNonFinite();
    void implicitEulerIsStableEverywhere();
    void noExplicitRunFails();
    void noXpbdRunFails();
    void noRunGainsEnergyUnreported();
    void classificationIsNotTrivial();
    void markdownNamesEveryIntegratorAndAddsUp();

private:
    std::vector<StabilityCell> m_cells;  ///< The quick grid, run once per process.
};

void TestStabilityGrid::initTestCase() {
    StabilityGridOptions options;
    options.quick = true;
    m_cells = runStabilityGrid(options);
    QVERIFY(!m_cells.empty());
}

void TestStabilityGrid::everyRunIsThere() {
    // Quick grid: 3 stiffnesses x 2 mass ratios x 2 node masses x (2 dampings + the undamped large
    // deformation + the undamped drag let go halfway) x 4 steps, per integrator.
    QCOMPARE(m_cells.size(), std::size_t(4 * 3 * 2 * 2 * 4 * 4));
    for (IntegratorKind kind : kAll)
        QCOMPARE(countOutcomes(m_cells, kind).total(), 3 * 2 * 2 * 4 * 4);
    const auto released = std::count_if(m_cells.begin(), m_cells.end(), [](const StabilityCell& c) {
        return c.dragReleased && c.damping == 0.0 && c.perturbation == 0.01;
    });
    QCOMPARE(released, std::ptrdiff_t(4 * 3 * 2 * 2 * 4));
    for (const StabilityCell& c : m_cells) {
        QVERIFY2(c.dt > 0.0 && c.dt <= 0.1, describe(c).c_str());
        QVERIFY2(c.stableStep > 0.0, describe(c).c_str());
    }
}

void TestStabilityGrid::noExportedFrameIsNonFinite() {
    const std::string bad = offenders(m_cells, [](const StabilityCell& c) { return !c.outputFinite; });
    QVERIFY2(bad.empty(), bad.c_str());
}

void TestStabilityGrid::implicitEulerIsStableEverywhere() {
    const std::string bad = offenders(m_cells, [](const StabilityCell& c) {
        return c.integrator == IntegratorKind::ImplicitEuler && c.outcome != Outcome::Stable;
    });
    QVERIFY2(bad.empty(), bad.c_str());
    for (const StabilityCell& c : m_cells) {
        if (c.integrator == IntegratorKind::ImplicitEuler)
            QVERIFY2(c.maxSubsteps == 1, describe(c).c_str());  // one solve per step, whatever dt
    }
}

void TestStabilityGrid::noExplicitRunFails() {
    // The guard must substep, refuse or roll back, and say so, before the energy grows.
    const std::string bad = offenders(m_cells, [](const StabilityCell& c) {
        return (c.integrator == IntegratorKind::SymplecticEuler || c.integrator == IntegratorKind::Verlet) &&
               c.outcome == Outcome::Failed;
    });
    QVERIFY2(bad.empty(), bad.c_str());
}

void TestStabilityGrid::noXpbdRunFails() {
    const std::string bad = offenders(m_cells, [](const StabilityCell& c) {
        return c.integrator == IntegratorKind::Xpbd && c.outcome == Outcome::Failed;
    });
    QVERIFY2(bad.empty(), bad.c_str());
}

void TestStabilityGrid::noRunGainsEnergyUnreported() {
    // Bounded is energy from nowhere that stopped growing, with nothing said: XPBD's runs at 1/24 s on stiff,
    // light bodies ended so (E up to 90x its start) before its guard; every scheme's guard now catches it.
    const std::string bad = offenders(m_cells, [](const StabilityCell& c) { return c.outcome == Outcome::Bounded; });
    QVERIFY2(bad.empty(), bad.c_str());
}

void TestStabilityGrid::classificationIsNotTrivial() {
    auto any = [&](auto predicate) { return std::any_of(m_cells.begin(), m_cells.end(), predicate); };
    auto isExplicit = [](const StabilityCell& c) {
        return c.integrator == IntegratorKind::SymplecticEuler || c.integrator == IntegratorKind::Verlet;
    };
    // Far above the bound an explicit scheme is substepped (the step is below 0.1 s so it is not clamped)...
    QVERIFY(any([&](const StabilityCell& c) {
        return isExplicit(c) && c.dtLabel == "10x bound" && c.outcome == Outcome::Caught && c.maxSubsteps > 1 &&
               c.refusedSteps == 0 && c.rolledBackSteps == 0;
    }));
    // ...and never left alone.
    QVERIFY(!any([&](const StabilityCell& c) {
        return isExplicit(c) && c.dtLabel == "10x bound" && c.dt < 0.1 && c.outcome == Outcome::Stable;
    }));
    // Well below it, it runs as it is.
    QVERIFY(any([&](const StabilityCell& c) {
        return isExplicit(c) && c.dtLabel == "0.1x bound" && c.outcome == Outcome::Stable && c.maxSubsteps == 1;
    }));
    // Some film-rate explicit runs on stiff, light bodies need more than maxSubsteps and are refused.
    QVERIFY(any([&](const StabilityCell& c) {
        return isExplicit(c) && c.dtLabel == "1/24 s" && c.refusedSteps > 0 && c.outcome == Outcome::Caught;
    }));
}

void TestStabilityGrid::markdownNamesEveryIntegratorAndAddsUp() {
    const std::string md = stabilityMarkdown(m_cells, "softtouch-cli stability --quick");
    QVERIFY(md.find("softtouch-cli stability --quick") != std::string::npos);
    OutcomeCounts all;
    for (IntegratorKind kind : kAll) {
        const std::string name(integratorName(kind));
        QVERIFY2(md.find("### " + name) != std::string::npos, name.c_str());
        const OutcomeCounts c = countOutcomes(m_cells, kind);
        QCOMPARE(c.stable + c.bounded + c.caught + c.failed, c.total());
        // The summary row of this integrator carries its counts.
        const std::string row = "| " + name + " | " + std::to_string(c.stable) + " | " + std::to_string(c.bounded) +
                                " | " + std::to_string(c.caught) +
                                " | " + std::to_string(c.failed) + " | " + std::to_string(c.total()) + " |";
        QVERIFY2(md.find(row) != std::string::npos, row.c_str());
        all.stable += c.stable;
        all.bounded += c.bounded;
        all.caught += c.caught;
        all.failed += c.failed;
    }
    QCOMPARE(std::size_t(all.total()), m_cells.size());
    const std::string total = "| **all** | " + std::to_string(all.stable) + " | " + std::to_string(all.bounded) +
                              " | " + std::to_string(all.caught) +
                              " | " + std::to_string(all.failed) + " | " + std::to_string(m_cells.size()) + " |";
    QVERIFY2(md.find(total) != std::string::npos, total.c_str());
    // Every run appears as one letter in the per-integrator tables.
    const std::size_t begin = md.find("## Every run"), end = md.find("## Failed runs");
    QVERIFY(begin < end && end != std::string::npos);
    std::size_t letters = 0;
    bool inCode = false;
    for (std::size_t i = begin; i < end; ++i) {
        if (md[i] == '`')
            inCode = !inCode;
        else if (inCode)
            letters += md[i] == 'S' || md[i] == 'B' || md[i] == 'C' || md[i] == 'F';
    }
    QCOMPARE(letters, m_cells.size());
}

QTEST_GUILESS_MAIN(TestStabilityGrid)
#include "test_stability_grid.moc"

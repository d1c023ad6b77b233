#include "bench/table1_report.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace softtouch::bench {
namespace {

using nlohmann::json;

constexpr Contender kContenders[] = {Contender::Lattice, Contender::Global, Contender::Local, Contender::Bullet};

/// The global mass-spring's implicit Euler takes ~50 s at 8,640 triangles, ~70 s at 11,660 and over 4 min
/// at 24,928: past this it is stopped and its time extrapolated, so that the whole bench stays near 10
/// minutes. Only the largest size is stopped.
constexpr double kImplicitBudgetSeconds = 90.0;

json orNull(const Table1Run* run) { return run ? json(run->seconds) : json(nullptr); }

json nanToNull(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

std::string setting(const Table1Graded& g) {
    std::string text = g.solver;
    if (g.solver == "xpbd" || g.solver == "bullet")
        text += " x" + std::to_string(g.iterations);
    return text + " on " + std::to_string(g.triangles);
}

void printPicks(const Table1Size& size, std::ostream& out) {
    char line[300];
    std::snprintf(line, sizeof line,
                  "    common reference: %s, E %.4g Pa (static %.4f m); %.3g%% of the diagonal from the limit\n"
                  "    at equal accuracy (as close to the solid as the lattice's paper row, %.3f%%; best of the timings):\n",
                  size.reference.description.c_str(), size.reference.material.modulus, size.reference.calibration.displacement,
                  100.0 * size.reference.uncertainty.total, 100.0 * size.accuracyGoal);
    out << line;
    const Table1Pick* lattice = size.pick(Contender::Lattice);
    for (const Table1Pick& p : size.picks) {
        std::snprintf(line, sizeof line, "      %-8s %-26s %9.4f s (to %.4f)  %7.3f%%  %s", std::string(contenderName(p.run.contender)).c_str(),
                      setting(p.run).c_str(), p.fastest, p.slowest, 100.0 * p.run.solidError,
                      p.reached ? "" : "never as close: its closest");
        out << line;
        if (p.reached && lattice && p.run.contender != Contender::Lattice) {
            std::snprintf(line, sizeof line, "  %.1fx the lattice", p.fastest / lattice->fastest);
            out << line;
        }
        out << "\n";
    }
    out << std::flush;
}

void printSize(const Table1Size& size, std::ostream& out) {
    char line[240];
    out << "    contender  solver            iter     scale  static_m   seconds  error_%  solid_%\n";
    for (const Table1Run& r : size.runs) {
        if (r.role == "ladder")
            continue;  // in the JSON; the table shows what was compared
        std::snprintf(line, sizeof line, "    %-9s  %-16s %5d  %8.4g  %8.4f  %8.4f%s %7.3f  %7.3f  %s%s\n",
                      std::string(contenderName(r.contender)).c_str(), r.solver.c_str(), r.iterations, r.scale,
                      r.displacement, r.seconds, r.stopped ? "*" : " ", 100.0 * r.error, 100.0 * r.solidError,
                      r.role.c_str(), r.best ? ", best" : "");
        out << line;
    }
    const Table1Run* lattice = size.best(Contender::Lattice);
    if (!lattice)
        return;
    out << "    ratios to the lattice:";
    for (Contender c : {Contender::Global, Contender::Local, Contender::Bullet}) {
        if (const Table1Run* r = size.best(c)) {
            const Table1Contender* about = size.about(c);
            std::snprintf(line, sizeof line, " %s %s%.1fx (%s)", std::string(contenderName(c)).c_str(),
                          about && !about->accuracyMatched ? ">=" : "", r->seconds / lattice->seconds, r->solver.c_str());
            out << line;
        }
    }
    if (const Table1Run* r = size.find(Contender::Bullet, "default")) {
        std::snprintf(line, sizeof line, ", bullet default %.1fx", r->seconds / lattice->seconds);
        out << line;
    }
    out << "\n" << std::flush;
    printPicks(size, out);
}

}  // namespace

json table1Json(const Table1Size& size, const Table1Options& options) {
    json contenders = json::object();
    for (const Table1Contender& c : size.contenders) {
        json evaluations = json::array();
        for (const CalibrationStep& step : c.calibration.steps)
            evaluations.push_back({{"scale", step.scale}, {"displacement_m", step.displacement}, {"steps", step.settleSteps}});
        json entry = {{"scale", c.calibration.scale},
                      {"displacement_m", c.calibration.displacement},
                      {"calibrated", c.calibration.converged},
                      {"saturated", c.calibration.saturated},
                      {"calibration", evaluations},
                      {"reference", c.reference}};
        if (c.contender == Contender::Global || c.contender == Contender::Local) {
            entry["accuracy_goal"] = c.accuracyGoal;
            entry["accuracy_matched"] = c.accuracyMatched;
        }
        if (c.contender == Contender::Bullet) {
            entry["iterations"] = c.bulletIterations;
            json check = json::array();
            for (const CalibrationStep& step : c.iterationCheck)
                check.push_back({{"iterations", int(step.scale)}, {"displacement_m", step.displacement}, {"steps", step.settleSteps}});
            entry["iteration_check"] = check;
        }
        contenders[std::string(contenderName(c.contender))] = entry;
    }
    json runs = json::array();
    bool finite = true;
    for (const Table1Run& r : size.runs) {
        finite = finite && r.finite;
        runs.push_back({{"contender", contenderName(r.contender)}, {"solver", r.solver}, {"iterations", r.iterations},
                        {"seconds", r.seconds}, {"extrapolated", r.stopped}, {"scale", r.scale},
                        {"displacement_m", r.displacement}, {"error", r.error}, {"finite", r.finite},
                        {"role", r.role}, {"best", r.best}, {"solid_error", nanToNull(r.solidError)}});
    }
    json row = {{"triangles", size.triangles}, {"vertices", size.vertices}, {"diagonal_m", size.diagonal},
                {"target_m", size.target}, {"target_fraction", options.targetFraction}, {"contenders", contenders},
                {"runs", runs}, {"finite", finite}};
    const Table1Run* lattice = size.best(Contender::Lattice);
    json ratios = json::object();
    for (Contender c : kContenders) {
        const Table1Run* best = size.best(c);
        const std::string name(contenderName(c));
        row[name + "_s"] = orNull(best);
        if (best && c != Contender::Lattice) {
            row[name + "_solver"] = best->solver;
            row[name + "_iterations"] = best->iterations;
            if (lattice)
                ratios[name] = best->seconds / lattice->seconds;
        }
    }
    const Table1Run* bulletDefault = size.find(Contender::Bullet, "default");
    row["bullet_default_s"] = orNull(bulletDefault);
    if (bulletDefault && lattice)
        ratios["bullet_default"] = bulletDefault->seconds / lattice->seconds;
    row["ratios"] = ratios;

    json levels = json::array();
    for (const analysis::ReferenceLevel& level : size.reference.levels)
        levels.push_back({{"what", level.what}, {"seconds", level.seconds}, {"change", nanToNull(level.change)}});
    row["reference"] = {{"description", size.reference.description},
                        {"modulus_pa", size.reference.material.modulus},
                        {"scale", size.reference.calibration.scale},
                        {"displacement_m", size.reference.calibration.displacement},
                        {"calibrated", size.reference.calibration.converged},
                        {"uncertainty", size.reference.uncertainty.total},
                        {"space_uncertainty", size.reference.uncertainty.space},
                        {"time_uncertainty", size.reference.uncertainty.time},
                        {"space_converging", size.reference.uncertainty.spaceConverging},
                        {"levels", levels}};
    row["accuracy_goal"] = size.accuracyGoal;
    json picks = json::object();
    json equalAccuracy = json::object();
    const Table1Pick* latticePick = size.pick(Contender::Lattice);
    for (const Table1Pick& p : size.picks) {
        const std::string name(contenderName(p.run.contender));
        picks[name] = {{"triangles", p.run.triangles}, {"solver", p.run.solver},   {"iterations", p.run.iterations},
                       {"seconds", p.fastest},         {"slowest_s", p.slowest},   {"carrying_s", p.run.carrying},
                       {"solid_error", p.run.solidError}, {"reached", p.reached}};
        if (p.run.contender != Contender::Lattice && latticePick)
            equalAccuracy[name] = p.reached ? json(p.fastest / latticePick->fastest) : json(nullptr);
    }
    row["picks"] = picks;
    row["equal_accuracy_ratios"] = equalAccuracy;
    row["graded"] = size.graded.size();
    return row;
}

json table1Section(bool quick, std::ostream& out) {
    std::vector<int> sizes = {208, 832, 2160, 8640, 11660, 24928};
    if (quick)
        sizes = {208, 832, 2160};
    Table1Options options;
    options.implicitBudgetSeconds = quick ? 0.0 : kImplicitBudgetSeconds;
    char header[600];
    std::snprintf(header, sizeof header,
                  "\nTable 1 at equal response: one second of dragging (dt 1/240 s, mesh at 60 Hz, one thread).\n"
                  "  Every body's stiffness and damping are scaled until what its drag holds settles %.0f%% of the\n"
                  "  diagonal from rest. Seconds per simulated second; error = RMS against the same body's converged\n"
                  "  run, solid = RMS against the common reference (the converged solid), %% of the diagonal%s.\n"
                  "  docs/measurements/performance.md says why.\n",
                  100.0 * options.targetFraction, quick ? "" : " (*: stopped at the time budget, time extrapolated)");
    out << header;
    json rows = json::array();
    std::vector<Table1Size> done;
    for (int triangles : sizes) {
        done.push_back(measureTable1Size(triangles, options, done, out));
        printSize(done.back(), out);
        rows.push_back(table1Json(done.back(), options));
    }
    out << "\n  triangles   lattice_s   global_s (solver)        local_s (solver)         bullet_s (iter)   bullet_1_s"
           "   global/lattice  bullet/lattice\n  (>=: no XPBD tried was as accurate as implicit Euler; its most accurate"
           " is shown, so the ratio is a lower bound)\n";
    for (const Table1Size& size : done) {
        const Table1Run* lattice = size.best(Contender::Lattice);
        const Table1Run* global = size.best(Contender::Global);
        const Table1Run* local = size.best(Contender::Local);
        const Table1Run* bullet = size.best(Contender::Bullet);
        const Table1Run* bulletDefault = size.find(Contender::Bullet, "default");
        char line[260];
        auto solver = [](const Table1Run* r) {
            return r ? r->solver + (r->solver == "xpbd" ? " x" + std::to_string(r->iterations) : "") : std::string("n/a");
        };
        const Table1Contender* aboutGlobal = size.about(Contender::Global);
        std::snprintf(line, sizeof line, "  %9d  %10.4f  %9.4f %-14s %9.4f %-14s %9.4f (%2d)  %10.4f  %2s%12.1fx  %13.1fx\n",
                      size.triangles, lattice ? lattice->seconds : 0.0, global ? global->seconds : 0.0,
                      ("(" + solver(global) + ")").c_str(), local ? local->seconds : 0.0, ("(" + solver(local) + ")").c_str(),
                      bullet ? bullet->seconds : 0.0, bullet ? bullet->iterations : 0,
                      bulletDefault ? bulletDefault->seconds : 0.0,
                      aboutGlobal && !aboutGlobal->accuracyMatched ? ">=" : "",
                      lattice && global ? global->seconds / lattice->seconds : 0.0,
                      lattice && bullet ? bullet->seconds / lattice->seconds : 0.0);
        out << line;
    }
    out << "\n  At equal accuracy: each contender's cheapest run at least as close to the converged solid as the\n"
           "  lattice's paper row (goal), on any mesh size up to the row's; ratio to the lattice's, or its closest\n"
           "  distance where no run gets that close.\n"
           "  triangles  solid_unc_%  goal_%   lattice_s  global                 local                  bullet\n";
    for (const Table1Size& size : done) {
        const Table1Pick* lattice = size.pick(Contender::Lattice);
        char line[300];
        std::snprintf(line, sizeof line, "  %9d  %11.3f  %6.3f  %9.4f", size.triangles, 100.0 * size.reference.uncertainty.total,
                      100.0 * size.accuracyGoal, lattice ? lattice->fastest : 0.0);
        out << line;
        for (Contender c : {Contender::Global, Contender::Local, Contender::Bullet}) {
            const Table1Pick* p = size.pick(c);
            if (!p)
                std::snprintf(line, sizeof line, "  %-21s", "n/a");
            else if (p->reached && lattice)
                std::snprintf(line, sizeof line, "  %-20.1fx", p->fastest / lattice->fastest);
            else
                std::snprintf(line, sizeof line, "  never (closest %.2f%%)", 100.0 * p->run.solidError);
            out << line;
        }
        out << "\n";
    }
    out << std::flush;
    return rows;
}

}  // namespace softtouch::bench

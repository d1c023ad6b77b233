#pragma once
/// Time integration schemes behind one interface. Each call advances the body by one (sub)step h;
/// the Simulator decides how many substeps a frame step needs and applies contacts and voids.

#include "core/body/body_model.h"
#include "core/body/forces.h"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace softtouch {

/// The available schemes.
enum class IntegratorKind : std::uint8_t {
    SymplecticEuler, ///< Explicit, first order; v += h a(x,v), x += h v.
    Verlet,          ///< Explicit central difference (the paper's), air damping central in time.
    ImplicitEuler,   ///< Linearised backward Euler, unconditionally stable, numerically damped.
    Xpbd,            ///< Extended position-based dynamics, one iteration per substep.
};

/// What the program knows about a scheme, in one row: every list of schemes (the study, the stability grid, the
/// bench, the editor's menu and legends, the messages that name them) iterates kIntegrators. A kind added to the
/// enum without its row stops the build (integrator.cpp's rowOf()); test_core_integrators checks each row against
/// the scheme itself.
struct IntegratorInfo {
    IntegratorKind kind;
    std::string_view name;        ///< In files and on the command line: "implicit-euler".
    std::string_view label;       ///< In the editor's menu: "Implicit Euler (stable, damps)".
    std::string_view shortLabel;  ///< In a chart's legend: "implicit".
    bool isExplicit;              ///< Stable only below a step bound: the Simulator substeps it.
    bool runsElement;             ///< Runs the solid element (XPBD's constraints act on springs and node masses).
};

inline constexpr IntegratorInfo kIntegrators[] = {
    {IntegratorKind::SymplecticEuler, "symplectic-euler", "Symplectic Euler", "sympl.", true, true},
    {IntegratorKind::Verlet, "verlet", "Verlet (the paper's)", "Verlet", true, true},
    {IntegratorKind::ImplicitEuler, "implicit-euler", "Implicit Euler (stable, damps)", "implicit", false, true},
    {IntegratorKind::Xpbd, "xpbd", "XPBD (fast, softer)", "XPBD", false, false},
};

/// Every kind, in the table's order.
constexpr std::array<IntegratorKind, std::size(kIntegrators)> integratorKinds() {
    std::array<IntegratorKind, std::size(kIntegrators)> kinds{};
    for (std::size_t r = 0; r < kinds.size(); ++r)
        kinds[r] = kIntegrators[r].kind;
    return kinds;
}

/// The row of `kind`.
const IntegratorInfo& integratorInfo(IntegratorKind kind);
/// Stable name used in files and on the command line ("implicit-euler", …).
std::string_view integratorName(IntegratorKind kind);
/// Parses a name written by integratorName().
std::optional<IntegratorKind> parseIntegratorKind(std::string_view name);
/// The names of the schemes `which` accepts, quoted and joined for a message: "\"verlet\", … or \"xpbd\"".
std::string integratorNames(bool (*which)(const IntegratorInfo&));

/// How an implicit scheme solved its last step's linear system.
struct LinearSolveStats {
    int iterations = 0;   ///< Conjugate-gradient iterations (0: nothing to solve, or not implicit).
    bool direct = false;  ///< CG did not converge and the system was factorised and solved directly.
};

/// Energy that crossed the body's boundary during one step(), measured by the explicit schemes (and XPBD) for
/// the Simulator's energy account. Each force g that is not a spring's elastic pull is held over the
/// substep and does the work h g·(v + v')/2 on the body: the exact change of the scheme's modified
/// energy E + (h/2) vᵀf for linear springs (docs/design/lattice.md, "The energy guard").
struct StepWork {
    double external = 0.0;   ///< J, the drags' work on the body (drivers are drags), either sign.
    double dissipated = 0.0; ///< J, what node damping and spring damping took out; >= 0 below the bound.
};

/// One time-integration scheme.
class Integrator {
public:
    virtual ~Integrator() = default;
    /// Which scheme this is.
    virtual IntegratorKind kind() const = 0;
    /// Explicit schemes are only stable below a step bound and get substeps from the Simulator.
    virtual bool isExplicit() const = 0;
    /// Advances `state` by h seconds. Pinned nodes keep their position with zero velocity; void
    /// nodes are left to updateVoidNodes().
    virtual void step(const BodyModel& model, const ExternalForces& external, BodyState& state, double h) = 0;
    /// How the last step's linear system was solved; all zero for schemes that solve none.
    virtual LinearSolveStats lastSolve() const { return {}; }
    /// Asks the scheme to measure each step's StepWork (off by default: it costs a pass over the
    /// damped springs). The explicit schemes and XPBD measure; implicit Euler ignores it.
    virtual void setMeasuresWork(bool /*measure*/) {}
    /// The last step's StepWork; zero unless measuring.
    virtual StepWork lastWork() const { return {}; }
};

/// Creates an integrator of the given kind.
std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind);

}  // namespace softtouch

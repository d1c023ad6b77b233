#pragma once
/// Time integration schemes behind one interface. Each call advances the body by one (sub)step h;
/// the Simulator decides how many substeps a frame step needs and applies contacts and voids.

#include "core/body_model.h"
#include "core/forces.h"

#include <memory>
#include <optional>
#include <string_view>

namespace softtouch {

/// The available schemes.
enum class IntegratorKind : std::uint8_t {
    SymplecticEuler, ///< Explicit, first order; v += h a(x,v), x += h v.
    Verlet,          ///< Explicit central difference (the paper's), air damping central in time.
    ImplicitEuler,   ///< Linearised backward Euler, unconditionally stable, numerically damped.
    Xpbd,            ///< Extended position-based dynamics, one iteration per substep.
};

/// Stable name used in files and on the command line ("implicit-euler", …).
std::string_view integratorName(IntegratorKind kind);
/// Parses a name written by integratorName().
std::optional<IntegratorKind> parseIntegratorKind(std::string_view name);

/// How an implicit scheme solved its last step's linear system.
struct LinearSolveStats {
    int iterations = 0;   ///< Conjugate-gradient iterations (0: nothing to solve, or not implicit).
    bool direct = false;  ///< CG did not converge and the system was factorised and solved directly.
};

/// Energy that crossed the body's boundary during one step(), measured by the explicit schemes (and XPBD) for
/// the Simulator's energy account. Each force g that is not a spring's elastic pull is held over the
/// substep and does the work h g·(v + v')/2 on the body: the exact change of the scheme's modified
/// energy E + (h/2) vᵀf for linear springs (docs/lattice.md, "The energy guard").
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

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
};

/// Creates an integrator of the given kind.
std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind);

}  // namespace softtouch

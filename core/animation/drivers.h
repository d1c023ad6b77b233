#pragma once
/// Drivers move a body without an input device: each turns time into drag springs. Both pull a
/// material point (lattice parameters u,v,w), or the ball of material around it, towards its rest position
/// plus an offset.

#include "core/base/ranges.h"
#include "core/body/forces.h"
#include "core/geometry/lattice.h"

#include <variant>
#include <vector>

namespace softtouch {

/// One key of a scripted path.
struct PathKey {
    double time = 0.0;             ///< Seconds, increasing.
    Vec3 offset = Vec3::Zero();    ///< Metres from the point's rest position.
    bool operator==(const PathKey&) const = default;
};

/// A point of the object follows a keyed path (Catmull-Rom through the keys; held before the first
/// key and after the last).
struct ScriptedDrag {
    Vec3 point{0.5, 0.5, 0.5};  ///< Material point, lattice parameters in [0,1]^3.
    std::vector<PathKey> keys;  ///< At least one key.
    double stiffness = 50.0;    ///< Ks, N/m, (0, 1e9].
    double damping = 1.0;       ///< Kd, N·s/m, [0, 1e6].
    double releaseTime = -1.0;  ///< Seconds after which the drag lets go (< 0: never).
    double radius = 0.0;        ///< Metres, [0, 1e3]: the drag holds the ball of this radius around the point (DriverGrip).
    bool operator==(const ScriptedDrag&) const = default;
};

/// A sinusoidal sideways pull of a region (a tail), the headless way to make a swim cycle.
struct SwimDriver {
    Vec3 point{0.1, 0.5, 0.5};        ///< Material point, lattice parameters in [0,1]^3.
    Vec3 direction = Vec3::UnitZ();   ///< Unit pull direction, world.
    double frequencyHz = 1.0;         ///< Beats per second, (0, 100].
    double amplitude = 0.1;           ///< Metres, [0, 1e3].
    double phase = 0.0;               ///< Radians.
    double rampSeconds = 0.0;         ///< Amplitude fades in over this time, seconds, >= 0.
    double stiffness = 50.0;          ///< Ks, N/m, (0, 1e9].
    double damping = 1.0;             ///< Kd, N·s/m, [0, 1e6].
    double radius = 0.0;              ///< Metres, [0, 1e3]: the pull holds the ball of this radius around the point (DriverGrip).
    bool operator==(const SwimDriver&) const = default;
};

/// Any driver.
using Driver = std::variant<ScriptedDrag, SwimDriver>;

/// A driver's settings as files name them, each range declared once: validateDriver() checks them and
/// the project reader reads them by these.
inline constexpr FieldRange kDriverStiffness{"stiffness", "stiffness", 0.0, 1e9, "N/m", false};
inline constexpr FieldRange kDriverDamping{"damping", "damping", 0.0, 1e6, "N·s/m"};
inline constexpr FieldRange kDragRelease{"release", "release time", 0.0, 1e9, "s"};  ///< When given (< 0: never).
inline constexpr FieldRange kSwimFrequency{"frequency", "frequency", 0.0, 100.0, "Hz", false};
inline constexpr FieldRange kSwimAmplitude{"amplitude", "amplitude", 0.0, 1e3, "m"};
inline constexpr FieldRange kSwimPhase{"phase", "phase", -1e6, 1e6, "rad"};
inline constexpr FieldRange kSwimRamp{"ramp", "ramp", 0.0, 1e6, "s"};
inline constexpr FieldRange kDriverRadius{"radius", "radius", 0.0, 1e3, "m"};

/// Checks a driver's fields; the message names the field.
Status validateDriver(const Driver& driver);

/// The radius of the ball a driver holds (0: the point alone).
inline double driverRadius(const Driver& driver) {
    return std::visit([](const auto& d) { return d.radius; }, driver);
}

/// Where a driver holds the body: the node weights of the material it pulls, and where that material is at rest.
///
/// Radius 0 holds the point alone, through the lattice's basis there. A lattice of higher degree or more nodes
/// has narrower basis functions, so a point's pull concentrates as the lattice is refined, and an elastic solid
/// answers an ever more concentrated pull with an ever deeper local dent (under a point load the displacement
/// has no bound): a point-driven clip has no converged solid to be graded against. A radius holds the mean of a
/// ball of material instead (clipped to the lattice's box), as a fin or a hand pushes over an area: a load the
/// solid converges under (docs/design/lattice.md, "Drivers carried to another lattice").
struct DriverGrip {
    std::vector<NodeWeight> support;  ///< Node weights, summing to 1.
    Vec3 rest = Vec3::Zero();         ///< The held material's mean rest position, world.
};
DriverGrip driverGrip(const Driver& driver, const Lattice& lattice);

/// The grip on the ball of material of `radius` metres around `point` (box parameters, inside the box), clipped to
/// the box; radius 0 holds the point alone. driverGrip() is this at the driver's point and radius.
DriverGrip materialGrip(const Lattice& lattice, const Vec3& point, double radius);

/// The drag spring a driver applies at time t through its grip, or nothing (a released scripted drag).
std::optional<DragSpring> driverDrag(const Driver& driver, const DriverGrip& grip, double seconds);

}  // namespace softtouch

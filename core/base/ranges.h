#pragma once
/// The accepted range of every setting that decides how much work a run is, in one place: core's
/// validate(), the project reader and the CLI all check against these, and docs/design/reliability.md lists
/// them. Together they bound the work of any accepted input by what it asks for: a frame is at most
/// 1/kMinFps simulated seconds, a second at most 1/kMinDt steps, and a clip starts at most
/// kMaxClipStart seconds in.

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <string>

namespace softtouch {

/// A setting's name in files, what it is in words, its valid range and its unit, declared once: core's
/// validate() checks it (problem()), the project reader reads its key by it (io::JsonValue::field), the
/// writer writes that key, and the CLI and the editor take their limits from it. Before, each range was
/// written in three places and two of them had drifted apart (a collider's radius: (0, 1e6] in core,
/// [1e-6, 1e6] in the reader).
struct FieldRange {
    const char* name = "";      ///< The key in project files ("dt", "restitution", "density", …).
    const char* label = "";     ///< What it is, as messages and the editor say it ("time step dt", …).
    double low = 0.0;
    double high = 0.0;
    const char* unit = "";      ///< "s", "m", "kg/m³", … or "".
    bool lowIncluded = true;    ///< False: low itself is out ("(0, 1e6]").
    bool whole = false;         ///< Whole numbers only.

    /// True when x is finite, within the range, and whole if it must be (NaN fails).
    bool contains(double x) const {
        return std::isfinite(x) && (lowIncluded ? x >= low : x > low) && x <= high && (!whole || std::floor(x) == x);
    }
    /// "a number in [1e-05, 0.1] (s)", "a whole number in [1, 10000]", "a number in (0, 1000000] (m)"; an
    /// infinite bound is left out: "a number > 0", "a whole number >= 1".
    std::string describe() const;
    /// Empty when contains(x), else "LABEL must be DESCRIBE, got X".
    std::string problem(double x) const;
};

/// A setting's value beside its range.
struct RangedValue {
    const FieldRange& range;
    double value;
};

/// The first of `fields` out of its range, as problem() says it; empty when every one is in range.
std::string firstProblem(std::initializer_list<RangedValue> fields);

}  // namespace softtouch

namespace softtouch::ranges {

/// True when x is a finite number in [lo, hi]: the check every setting's validation makes (NaN fails it).
inline bool finiteIn(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

/// Fixed step, seconds. Below 1e-5 s a one-second clip is over 100,000 steps (the study's converged
/// reference runs at 1/4000 s); above 0.1 s no scheme follows a wobble.
inline constexpr double kMinDt = 1e-5;
inline constexpr double kMaxDt = 0.1;
/// Frames per second of clips, bakes and renders. Below one frame a second each frame would be
/// minutes of simulation for a picture no animation plays.
inline constexpr double kMinFps = 1.0;
inline constexpr double kMaxFps = 1000.0;
/// Frames of a clip, a bake or a render.
inline constexpr int kMaxFrames = 1000000;
/// Where a clip starts on its take, seconds: the simulation runs up to it before the first frame.
inline constexpr double kMaxClipStart = 3600.0;
/// Largest gravity, m/s² (a thousand g): 1e30 used to pass and overflowed the energy account.
inline constexpr double kMaxGravity = 1e4;
/// Largest drag offset a driver key moves its point by, metres.
inline constexpr double kMaxDragOffset = 1e4;
/// Size of a mesh (its bounding box's diagonal), metres: SoftTouch works in metres, and a mesh of 1e30 m
/// (or 1e-30 m) left the lattice's springs with rest lengths that round to nothing.
inline constexpr double kMinMeshSize = 1e-4;
inline constexpr double kMaxMeshSize = 1e5;
/// How far outside its lattice box a mesh vertex may lie, in box lengths along each axis. Outside the
/// box the lattice map is extrapolated, and its weights grow as the distance to the power of the
/// degree: a guppy bound to a 1 mm box 1 km away baked non-finite frames. No deformer setup puts a vertex
/// ten box lengths out.
inline constexpr double kMaxOutsideBox = 10.0;
/// Lattice nodes implicit Euler factorises: its sparse LDLT fills in as the lattice grows (a 16x16x16
/// B-spline's first step takes 4 s, 24x24x24 70 s and 0.6 GB; 64x64x64 ran out of memory). Larger
/// lattices run with the explicit schemes or XPBD, whose cost is linear in the springs.
inline constexpr std::size_t kMaxImplicitNodes = 4096;
/// Triangles of a mesh collider, refused before its surface is built: FCL's OBB-RSS hierarchy is most of
/// the build and of its memory (about 0.8 kB a triangle), so a 1,001,112-triangle rock took 6.2 s and 931 MB
/// to validate, 199,080 triangles 1.5 s and 212 MB. A rock needs a few thousand; bodies' own surfaces (body
/// contacts) are not colliders and not held to it.
inline constexpr std::size_t kMaxColliderTriangles = 200000;

/// The settings a project's world, simulation and clip hold, and its colliders' (core/scene/scene.h,
/// core/solver/simulator.h, core/body/colliders.h, core/body/body_contacts.h).
inline constexpr FieldRange kDt{"dt", "time step dt", kMinDt, kMaxDt, "s"};
inline constexpr FieldRange kXpbdSubsteps{"xpbdSubsteps", "XPBD substeps", 1, 10000, "", true, true};
/// Steps between the energy guard's regular checks (explicit schemes); 0 turns the guard off.
inline constexpr FieldRange kEnergyCheckSteps{"energyCheckSteps", "energy check interval", 0, 1e6, "steps", true, true};
inline constexpr FieldRange kFrames{"frames", "frames", 1, kMaxFrames, "", true, true};
inline constexpr FieldRange kFps{"fps", "fps", kMinFps, kMaxFps, "frames per second"};
inline constexpr FieldRange kClipStart{"start", "start", 0.0, kMaxClipStart, "s"};
inline constexpr FieldRange kRestitution{"restitution", "restitution", 0.0, 1.0, ""};
inline constexpr FieldRange kFriction{"friction", "friction", 0.0, 10.0, "Coulomb coefficient"};
inline constexpr FieldRange kColliderRadius{"radius", "radius", 0.0, 1e6, "m", false};
inline constexpr FieldRange kCapsuleHalfLength{"halfLength", "halfLength", 0.0, 1e6, "m"};
inline constexpr FieldRange kMeshColliderScale{"scale", "scale", 0.0, 1e6, "", false};

}  // namespace softtouch::ranges

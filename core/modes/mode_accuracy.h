#pragma once
/// What a time-integration scheme does to one vibration mode: how much amplitude it keeps per period
/// and how far off it runs in frequency, at the step the simulator actually takes.
///
/// A mode of the linearised body is the damped oscillator  q̈ + 2ζω q̇ + ω² q = 0. Every scheme here
/// is linear on it, so one step is a 2x2 amplification matrix A(h) acting on (q, q̇); its eigenvalues
/// λ, λ̄ give the numerical oscillation: per step the amplitude shrinks by |λ| and the phase advances
/// by arg λ, so per (numerical) period the amplitude kept is |λ|^(2π/arg λ) and the frequency is
/// arg λ / (2π h). The exact motion keeps exp(−2πζ/√(1−ζ²)) per period at ω√(1−ζ²). A is built by
/// running the scheme's own update rule on the unit states (1,0) and (0,1), so the figures follow the
/// code (node damping central in time for Verlet, explicit in XPBD's prediction, and so on).
/// XPBD is not linear per mode: its one Gauss-Seidel pass per substep moves energy between modes and
/// loses some (on a pinned bar at 24 steps/s it keeps 67% per period where a converged solve would
/// keep 72%), so for XPBD the figures are measured: the scheme itself runs two periods from the mode
/// shape and the motion projected on the mode is fitted (fitOscillation).

#include "core/modes/modes.h"
#include "core/solver/integrator.h"
#include "core/solver/simulator.h"

#include <span>
#include <string>
#include <vector>

namespace softtouch {

/// The numerical behaviour of one mode under one scheme and step.
struct ModeAccuracy {
    double stepSeconds = 0.0;          ///< The (sub)step the scheme takes, s.
    bool stable = true;                ///< |λ| <= 1 (the mode does not grow).
    bool oscillates = true;            ///< λ is complex: the numerical mode still oscillates.
    double amplitudePerPeriod = 0.0;   ///< Amplitude kept after one numerical period, [0, ∞); >1 grows.
    double exactAmplitudePerPeriod = 0.0; ///< What the damped mode itself keeps per period.
    double frequencyHz = 0.0;          ///< Frequency of the numerical oscillation, Hz.
    double frequencyError = 0.0;       ///< frequencyHz / damped frequency − 1.
    /// The damping ratio the clip shows: the material's and the scheme's together, the ζ of the exact
    /// oscillator that keeps amplitudePerPeriod per period (dampingRatioKeeping()); 1 where the numerical
    /// mode no longer swings, negative where it grows. What an animator reads beside the material's ζ.
    double dampingRatio = 0.0;
    /// XPBD: at the project's xpbdSubsteps the body gains energy, so the energy guard substeps it further
    /// (stepSeconds is the substep it takes for the body's free motion; a drag may need more), and these
    /// figures are measured there, as the clip runs.
    bool guardSubsteps = false;
};

/// The damping ratio ζ of the oscillator q̈ + 2ζω q̇ + ω² q = 0 that keeps `perPeriod` of its amplitude
/// per period: exp(−2πζ/√(1−ζ²)) = perPeriod, so ζ = L/√(4π² + L²) with L = −ln perPeriod.
double dampingRatioKeeping(double perPeriod);

/// Analyses one mode under `kind` at (sub)step h (Simulator::substepsFor() says how many a step takes),
/// in closed form (for XPBD: as if each substep were solved exactly). `stepMassRate` (1/s): on a viscous solid
/// element, the explicit schemes' substep moves the mode as if 1 + h times it heavier (schemeAccuracies() gives it).
ModeAccuracy modeAccuracy(IntegratorKind kind, const VibrationMode& mode, double stepSeconds, double stepMassRate = 0.0);

/// The figures the editor and `softtouch-cli modes` show for one mode of `model` under `settings`:
/// modeAccuracy() at the scheme's (sub)step, or for XPBD measured on the scheme (see above), at the
/// substeps its energy guard runs the body at.
ModeAccuracy schemeAccuracy(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                            const VibrationMode& mode);
/// schemeAccuracy() of each of `modes`, lowest first (as analyseModes lists them): for XPBD the substeps its
/// guard settles on are the body's, found once from the lowest, and every mode is measured there.
std::vector<ModeAccuracy> schemeAccuracies(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                                           std::span<const VibrationMode> modes);

/// How much of a free spin the scheme keeps over a second: `model` turned rigidly at one turn a second about its
/// principal axis of largest inertia through its centre of mass, no force, run for one second under `settings`;
/// the angular momentum about that axis at the end over the start. Node damping (on absolute velocity) takes its
/// share under every scheme; Verlet keeps the rest, while implicit Euler's damping of the stretch the spin
/// excites takes more, which a thrown or tumbling body shows as a spin that slows. Only a free body (no anchors)
/// can spin: 1 otherwise.
double spinKeptPerSecond(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings);
/// When the scheme keeps this much less of a spin per second than Verlet (the material alone), `modes` and the
/// editor say that a free spin slows.
inline constexpr double kSpinLossShown = 0.01;
/// What the scheme does to a free spin, in words, where it takes kSpinLossShown more than the material alone:
/// "implicit-euler at 240 steps/s slows a free spin: one of a turn a second keeps 93.1% of its angular momentum
/// after a second (the material alone: 99.2%)"; empty otherwise, and for a body that cannot spin.
std::string describeSpinKept(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings);

/// A damped oscillation fitted to samples taken every `sampleSeconds` (Prony's method: for one
/// damped mode q_n = A r^n cos(nθ + φ) the recurrence q_{n+1} = 2r cos θ q_n − r² q_{n−1} holds
/// exactly, so a least-squares fit of its two coefficients gives r and θ with no peak picking).
struct FittedOscillation {
    bool oscillates = false;          ///< A complex pair was found.
    double frequencyHz = 0.0;         ///< θ / (2π · sampleSeconds).
    double dampingRatio = 0.0;        ///< From the decay rate −ln r / sampleSeconds and the frequency.
    double amplitudePerPeriod = 0.0;  ///< r^(2π/θ).
};
/// Fits `samples` (at least 4).
FittedOscillation fitOscillation(const std::vector<double>& samples, double sampleSeconds);

/// Starts `model` at rest + amplitude · mode.shape, runs `seconds` under `settings` with no external
/// force, and returns the motion projected on the mode (q = φᵀ M Δx), sampled every `sampleEvery` steps.
std::vector<double> bakeModeProjection(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                                       const VibrationMode& mode, double amplitude, double seconds, int sampleEvery = 1);

/// The (sub)step h a simulator's scheme takes under `external`: dt over its substeps.
double integrationStep(const Simulator& simulator, const ExternalForces& external = {});

/// One line for a person: "implicit-euler at 240 steps/s: the 0.991 Hz mode damps as ζ 0.124 in the clip (the
/// material's 0.110), keeping 45.8% per period (the material alone: 49.7%), frequency −0.3%".
std::string describeModeAccuracy(const SimulationSettings& settings, const VibrationMode& mode,
                                 const ModeAccuracy& accuracy);

}  // namespace softtouch

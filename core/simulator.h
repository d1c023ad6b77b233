#pragma once
/// Runs a body with a fixed time step and the guards that keep it sane: explicit schemes are
/// substepped below their stability bound, a non-finite result is rolled back to the last good state
/// and reported with its cause, and a body at rest sleeps (costs nothing) until something changes.

#include "core/body_model.h"
#include "core/forces.h"
#include "core/integrator.h"

#include <memory>
#include <string>

namespace softtouch {

/// Per-simulator settings.
struct SimulationSettings {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler; ///< Scheme.
    double dt = 1.0 / 240.0;      ///< Fixed step, seconds. Range (0, 0.1].
    int xpbdSubsteps = 8;         ///< Substeps per step for XPBD. Range [1, 10000].
    double stabilitySafety = 0.8; ///< Fraction of the explicit stability bound used. Range (0, 1]. Above
                                  ///< ~0.85 undamped bodies can grow slowly without a report (docs/stability.md).
    int maxSubsteps = 200000;     ///< Cap on explicit substeps per step; beyond it the step is refused.
    bool sleep = true;            ///< Let a body at rest sleep.
    double sleepSpeed = 1e-4;     ///< Below this node speed (m/s) for sleepSteps steps, the body sleeps.
    int sleepSteps = 60;          ///< Consecutive quiet steps before sleeping.
    /// Checks every field against its range.
    Status validate() const;
};

/// What happened in one step.
struct StepReport {
    int substeps = 0;          ///< Integrator calls made (0 when asleep or refused).
    bool sleeping = false;     ///< The body was asleep: nothing was computed.
    bool rolledBack = false;   ///< The step produced a non-finite state and was undone.
    std::string problem;       ///< Empty, or what went wrong and how to fix it.
};

/// Fixed-step simulation of one body.
class Simulator {
public:
    /// Starts at the model's rest state.
    Simulator(std::shared_ptr<const BodyModel> model, const SimulationSettings& settings);

    const BodyModel& model() const { return *m_model; }
    const SimulationSettings& settings() const { return m_settings; }
    const BodyState& state() const { return m_state; }
    /// Simulated time, seconds (step count × dt).
    double time() const { return double(m_stepCount) * m_settings.dt; }
    long long stepCount() const { return m_stepCount; }
    bool isSleeping() const { return m_sleeping; }

    /// A copy of the full state (for scrubbing, caching and round trips).
    BodyState saveState() const { return m_state; }
    /// Replaces the state (same node count) and wakes the body; the step count (time) is kept.
    void restoreState(const BodyState& state);
    /// Replaces the state and the step count (simulated time = stepCount × dt): scrubbing and replays.
    void restoreState(const BodyState& state, long long stepCount);

    /// Advances one step of dt under the given forces.
    StepReport step(const ExternalForces& external);

    /// Largest stable explicit substep for these forces, seconds: safety × 2/ω_max × (√(1+ζ²) − ζ),
    /// with ω_max² the largest eigenvalue of M⁻¹K (springs plus drags) and ζ its damping ratio.
    double stableStep(const ExternalForces& external) const;
    /// Substeps a step of dt takes with these forces.
    int substepsFor(const ExternalForces& external) const;

private:
    bool forcesChanged(const ExternalForces& external) const;

    std::shared_ptr<const BodyModel> m_model;
    SimulationSettings m_settings;
    std::unique_ptr<Integrator> m_integrator;
    BodyState m_state;
    BodyState m_lastGood;
    std::vector<Vec3> m_substepStart;  ///< Positions before the current substep (contact history).
    long long m_stepCount = 0;
    bool m_sleeping = false;
    int m_quietSteps = 0;
    ExternalForces m_sleepForces;  ///< Forces when the body fell asleep; any change wakes it.
};

}  // namespace softtouch

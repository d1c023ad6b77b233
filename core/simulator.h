#pragma once
/// Runs a body with a fixed time step and the guards that keep it sane: explicit schemes are
/// substepped below their stability bound, energy that appears from nowhere (more than the drags put
/// in) makes the simulator roll back to its last checked state and take finer substeps from then on,
/// a non-finite result is rolled back the same way and reported with its cause, and a body at rest
/// sleeps (costs nothing) until something changes.
///
/// The energy account: E = kinetic + spring + gravity may grow by the work the drags did (∫ F·dp, trapezoidal per step) since the account started (the last restore, rollback or
/// gravity change) and otherwise only fall (damping, contacts), so slow growth adds up and is seen. For
/// the explicit schemes E is their modified energy (see accountedEnergy). A growth of more than
/// energyTolerance of the body's elastic and kinetic energy is "from nowhere". Checks run every
/// energyCheckSteps steps, so a rollback loses at most that many steps, and the state rolled back to
/// is always one that passed the check (never one that was already bad). Not accounted yet: the
/// energy a plane contact's position correction adds (bodies on planes may see rare false reports).

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
    int energyCheckSteps = 8;     ///< Steps between energy checks (explicit schemes); 0 turns the guard off. [0, 1e6].
    double energyTolerance = 0.05; ///< Growth beyond the drags' work, as a fraction of kinetic + spring energy,
                                   ///< that counts as energy from nowhere. (0, 1].
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
    bool rolledBack = false;   ///< The step produced a non-finite state or energy from nowhere and was undone.
    double energyGrowth = 0.0; ///< At a failed energy check: growth beyond the drags' work, fraction of the body's energy.
    std::string problem;       ///< Empty, or what went wrong and how to fix it.
};

/// Fixed-step simulation of one body.
class Simulator {
public:
    /// Most the energy guard multiplies substeps by.
    static constexpr int kMaxGuardFactor = 64;

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
    /// Substeps a step of dt takes with these forces (the energy guard may have multiplied them).
    int substepsFor(const ExternalForces& external) const;
    /// Factor the energy guard has multiplied the substeps by (1 until it first caught growth).
    int guardSubstepFactor() const { return m_guardFactor; }

private:
    bool forcesChanged(const ExternalForces& external) const;
    /// The energy the account compares (an explicit scheme's modified energy: kinetic + spring +
    /// gravity + (h/2) vᵀf), and the kinetic + spring part.
    double accountedEnergy(const ExternalForces& external, double* elasticAndKinetic);
    /// A drag's pull and the share-weighted position of the free nodes it pulls.
    struct DragPull {
        Vec3 force = Vec3::Zero();
        Vec3 sharedPosition = Vec3::Zero();
    };
    DragPull dragPull(const DragSpring& drag) const;
    /// Notes each drag's pull before a step.
    void beginDragWork(const ExternalForces& external);
    /// Work the drags did over the step since beginDragWork() (trapezoidal).
    double dragWork(const ExternalForces& external) const;
    /// Compares the energy with the account's start plus the drags' work since; on growth rolls back,
    /// raises the substep factor and fills the report. Returns false when it rolled back.
    bool checkEnergy(const ExternalForces& external, StepReport& report);
    /// Takes the current state as the known-good checkpoint.
    void checkpoint();
    /// The energy guard runs: an explicit scheme with checks on.
    bool accountsEnergy() const;
    /// Takes a checkpoint and starts the energy account afresh from the current state (restore,
    /// rollback, gravity change, sleep).
    void resetEnergyAccount(const ExternalForces& external);

    std::shared_ptr<const BodyModel> m_model;
    SimulationSettings m_settings;
    std::unique_ptr<Integrator> m_integrator;
    BodyState m_state;
    BodyState m_lastGood;          ///< The last state that passed every check (finite, energy).
    long long m_lastGoodStep = 0;
    std::vector<DragPull> m_dragStart; ///< Each drag's pull at the start of the current step.
    double m_accountEnergy = 0.0;   ///< Energy when the account started, J.
    Vec3 m_accountGravity = Vec3::Zero(); ///< Gravity the account's potential was measured with.
    double m_accountScale = 0.0;    ///< Kinetic + spring energy when the account started, J.
    double m_accountWork = 0.0;     ///< Work the drags did since the account started, J.
    double m_peakScale = 0.0;       ///< Largest kinetic + spring energy since the last restore, J.
    int m_stepsSinceCheckpoint = 0;
    int m_guardFactor = 1;
    std::vector<Vec3> m_zeroVelocity;      ///< Scratch of the energy account (no allocation once warm).
    std::vector<Vec3> m_conservativeForce;
    SpringScratch m_scratch;
    std::vector<Vec3> m_substepStart;  ///< Positions before the current substep (contact history).
    long long m_stepCount = 0;
    bool m_sleeping = false;
    int m_quietSteps = 0;
    ExternalForces m_sleepForces;  ///< Forces when the body fell asleep; any change wakes it.
};

}  // namespace softtouch

#pragma once
/// Runs a body with a fixed time step and the guards that keep it sane: explicit schemes are
/// substepped below their stability bound (from the rest state and, as the body deforms, from the
/// current one), energy that appears from nowhere makes the simulator roll back to its last checked
/// state and take finer substeps from then on, a non-finite result is rolled back the same way and
/// reported with its cause, and a body at rest sleeps (costs nothing) until something changes.
///
/// The energy account (explicit schemes and XPBD; docs/design/lattice.md, "The energy guard"): the scheme's modified
/// energy H̃ = kinetic + spring + gravity + (h/2) vᵀf may change only by what crossed the body's
/// boundary since the account started: the drags' work (drivers are drags), minus what node and spring
/// damping dissipated, plus what plane contacts changed (each measured per substep, exactly for linear
/// springs). Growth beyond that by more than energyTolerance of the body's kinetic + elastic energy is
/// energy from nowhere. H̃ cannot see a linear instability (a mode past its bound grows with H̃ = 0),
/// so the check also rolls back when the springs' (h/2) vᵀf holds nearly all the elastic and kinetic
/// energy, which only a step at or past the bound allows. Checks run every energyCheckSteps steps and
/// wherever the caller settles (SceneSimulation does before it returns a time that may be shown or written).
/// A failed check restores the last state that passed one (never one that was already bad) together with
/// its time, and doubles the substeps, so the caller steps the span again, finer: the motion stays one
/// continuous trajectory. A guard already at kMaxGuardFactor cannot do better; it stops the body there
/// (every later step is refused, as a step needing more than maxSubsteps is), which a bake reports as a failure.
/// XPBD has no modified energy: its account compares E, from twice the body's elastic energy above what it
/// holds (its Gauss-Seidel pass swings E even where it is stable), and its substeps are xpbdSubsteps times
/// the guard's factor.

#include "core/body/body_model.h"
#include "core/body/current_stiffness.h"
#include "core/body/forces.h"
#include "core/solver/integrator.h"

#include <memory>
#include <string>

namespace softtouch {

/// Per-simulator settings.
struct SimulationSettings {
    IntegratorKind integrator = IntegratorKind::ImplicitEuler; ///< Scheme.
    double dt = 1.0 / 240.0;      ///< Fixed step, seconds. Range (0, 0.1].
    int xpbdSubsteps = 8;         ///< Substeps per step for XPBD. Range [1, 10000].
    double stabilitySafety = 0.8; ///< Fraction of the explicit stability bound used. Range (0, 2]. Above
                                  ///< ~0.85 undamped bodies can grow slowly; above 1 the explicit schemes
                                  ///< are unstable and only the energy guard catches it (tests use that).
    int maxSubsteps = 200000;     ///< Cap on explicit substeps per step; beyond it the step is refused.
    int energyCheckSteps = 8;     ///< Steps between energy checks (explicit schemes and XPBD; sooner once 256 substeps
                                  ///< have run since the last); 0 turns the guard off. [0, 1e6].
    double energyTolerance = 0.05; ///< Growth beyond what the account explains, as a fraction of kinetic +
                                   ///< spring energy, that counts as energy from nowhere. (0, 1]. H̃ is
                                   ///< conserved exactly only for linear springs: under large deformation it
                                   ///< wobbles by a few percent (a 3x4x3 body displaced by 5 cm per node:
                                   ///< 3.1% in 8 steps, test_core_physics releasedFreeBody…), so 2% would
                                   ///< report and substep ordinary cartoon squash; 5% does not.
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
    bool refused = false;      ///< The step was not taken (the body froze): it needed more than maxSubsteps
                               ///< substeps, or the guard had already multiplied them by kMaxGuardFactor.
    int rewoundSteps = 0;      ///< Steps the clock went back with a rollback: the caller steps them again.
    double energyGrowth = 0.0; ///< At a failed energy check: growth beyond the account, fraction of the body's energy.
    int strainCorrections = 0; ///< Springs the stretch and squash limits put back this step (0: none was out).
    double worstStrainExcess = 0.0; ///< Largest excess they found, fraction of a rest length.
    int colliderContacts = 0;  ///< Contact points found inside a collider this step (before correction).
    double deepestContact = 0.0; ///< The deepest of them, metres.
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
    /// The model, to build another Simulator of the same body.
    const std::shared_ptr<const BodyModel>& sharedModel() const { return m_model; }
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

    /// Advances one step of dt under the given forces. After a rollback (report.rewoundSteps > 0) the
    /// time is that of the state restored; step on to take the span again at the finer substep.
    StepReport step(const ExternalForces& external);
    /// Runs the energy check now if steps were taken since the last one (explicit schemes and XPBD with the
    /// guard on), so the current state is one the guard has accepted before it is shown or written. `external`:
    /// the forces of the step just taken. Returns false when it rolled back (the report says how far).
    bool settle(const ExternalForces& external, StepReport& report);
    /// Step count of the last state the guard accepted.
    long long lastAcceptedStep() const { return m_lastGoodStep; }
    /// Puts the body back to an accepted state of the same run and its step count, keeping what the guard
    /// learnt (its substep factor): a scene whose objects step together rolls them all back this way
    /// when one of them fails a check.
    void rewind(const BodyState& state, long long stepCount);

    /// Takes a state that a pass outside the step corrected (the scene's body contacts: same node count),
    /// keeping the time. The energy account books what the correction changed as contact work, so the
    /// guard does not take it for energy from nowhere; void nodes follow; a sleeping body wakes.
    /// `external`: the forces of the step just taken.
    void applyCorrection(const BodyState& corrected, const ExternalForces& external);

    /// Largest stable explicit substep for these forces, seconds: safety × 2/ω_max × (√(1+ζ²) − ζ),
    /// with ω_max² the largest eigenvalue of M⁻¹K (springs plus drags) and ζ its damping ratio. K is
    /// the rest stiffness, or the current state's tangent stiffness where that is stiffer (tracked
    /// at each energy check; see current_stiffness.h).
    double stableStep(const ExternalForces& external) const;
    /// Whether the scheme is explicit: only then does stableStep() bound its substeps.
    bool isExplicit() const;
    /// λ_max(M⁻¹K) of the springs at the last energy check's state, 1/s² (0 before the first, or
    /// with the guard off); stableStep() uses it where it exceeds the rest value.
    double currentStiffnessOverMass() const { return m_currentStiffness; }

    /// The energy account since it last started (explicit schemes and XPBD with the guard on), joules.
    struct EnergyAccount {
        double start = 0.0;       ///< H̃ when the account started.
        double work = 0.0;        ///< Drags' work on the body since.
        double dissipated = 0.0;  ///< Taken out by node and spring damping since.
        double contacts = 0.0;    ///< Changed by plane contacts since (position and velocity corrections).
        double limits = 0.0;      ///< Changed by the stretch and squash limits since (never positive by design).
        double volume = 0.0;      ///< Changed by volume preservation since (its constraint's work).
        double expected() const { return start + work - dissipated + contacts + limits + volume; }
    };
    const EnergyAccount& energyAccount() const { return m_account; }
    /// The account's H̃ of the current state, J (what energyAccount().expected() is compared with).
    double accountedEnergy(const ExternalForces& external);
    /// Substeps a step of dt takes with these forces (the energy guard may have multiplied them).
    int substepsFor(const ExternalForces& external) const;
    /// Factor the energy guard has multiplied the substeps by (1 until it first caught growth).
    int guardSubstepFactor() const { return m_guardFactor; }

private:
    bool forcesChanged(const ExternalForces& external) const;
    /// The current state's energies for the account at substep h.
    struct EnergyParts {
        double modified = 0.0;          ///< H̃ = kinetic + spring + gravity + (h/2) vᵀf_c + stepMassEnergy(h), J.
        double elastic = 0.0;           ///< Kinetic + spring, J.
        double springPower = 0.0;       ///< vᵀ f of the springs' elastic forces, W.
        double conservativePower = 0.0; ///< vᵀ f_c, springs plus gravity, W.
    };
    EnergyParts energyParts(const ExternalForces& external, double h);
    /// (h/2) vᵀK̃_s v: the kinetic energy a viscous solid element's substep of h adds with the viscosity it takes
    /// implicitly (elementStepViscosity()), J; 0 for any other body.
    double stepMassEnergy(double h) const;
    /// H̃ of node i alone: its kinetic, gravity and (h/2) v·mg terms plus each of its springs' energy
    /// and (h/2) vᵀf share. A contact moving node i changes H̃ by exactly the change of this.
    double nodeEnergy(std::size_t i, const Vec3& gravity, double h) const;
    /// resolvePlaneContacts, adding each moved node's energy change to the account.
    void resolveContactsAccounted(const ExternalForces& external, double h);
    /// Compares H̃ with the account and the springs' share; on growth or instability rolls back,
    /// raises the substep factor and fills the report. Returns false when it rolled back. `regular`: the
    /// check every energyCheckSteps steps (it also tracks the stiffness and restarts a drained account);
    /// otherwise a settle, which only moves the accepted state on.
    bool checkEnergy(const ExternalForces& external, StepReport& report, bool regular);
    /// Restores the last accepted state and its time after a failed check (`why`); raises the substep
    /// factor, or stops the body when it is already at kMaxGuardFactor, and fills the report.
    void rollBack(const ExternalForces& external, const std::string& why, StepReport& report);
    /// Moves the account to a new substep h (H̃ depends on it) without restarting it.
    void rebaseAccount(const ExternalForces& external, double h);
    /// The same, from `parts` taken at the account's substep.
    void moveAccountStep(const EnergyParts& parts, double h);
    /// Takes the current state as the known-good checkpoint.
    void checkpoint();
    /// The energy guard runs: an explicit scheme with checks on.
    bool accountsEnergy() const;
    /// Starts the account's expected energy and scale from `parts` (the current state's).
    void startAccountAt(const EnergyParts& parts);
    /// Takes a checkpoint and starts the energy account afresh from the current state (restore,
    /// rollback, gravity change, sleep).
    void resetEnergyAccount(const ExternalForces& external);
    /// Runs `iterations` power steps of the current-state stiffness estimate (guard on only).
    void trackStiffness(int iterations);

    std::shared_ptr<const BodyModel> m_model;
    SimulationSettings m_settings;
    std::unique_ptr<Integrator> m_integrator;
    BodyState m_state;
    BodyState m_lastGood;          ///< The last state that passed every check (finite, energy).
    long long m_lastGoodStep = 0;
    EnergyAccount m_account;
    double m_accountStep = 0.0;     ///< Substep h, s, the account's H̃ is measured with.
    Vec3 m_accountGravity = Vec3::Zero(); ///< Gravity the account's potential was measured with.
    double m_accountScale = 0.0;    ///< Kinetic + spring energy when the account started, J.
    double m_peakScale = 0.0;       ///< Largest kinetic + spring energy since the last restore, J.
    double m_dissipatedAtCheck = 0.0; ///< The account's damping work at the last regular check, J.
    double m_noiseEnergy = 1e-12;   ///< Energy below which growth is round-off, J (see the constructor).
    int m_stepsSinceCheckpoint = 0;
    long long m_substepsSinceCheckpoint = 0;
    int m_guardFactor = 1;
    std::string m_stopped;         ///< Why the guard stopped the body (at kMaxGuardFactor); empty: running.
    StiffnessTracker m_tracker;
    double m_currentStiffness = 0.0; ///< See currentStiffnessOverMass().
    std::vector<Vec3> m_zeroVelocity;      ///< Scratch of the energy account (no allocation once warm).
    mutable Eigen::VectorXd m_pullWork;    ///< Scratch of stableStep()'s drag term on a solid element body.
    std::vector<Vec3> m_conservativeForce;
    SpringScratch m_scratch;
    std::vector<Vec3> m_substepStart;  ///< Positions before the current substep (contact history).
    std::vector<Vec3> m_volumeScratch; ///< Volume gradient per node (volume preservation).
    std::vector<ColliderImpulses> m_colliderImpulses; ///< Last substep's contact impulses (warm start).
    long long m_stepCount = 0;
    bool m_sleeping = false;
    int m_quietSteps = 0;
    ExternalForces m_sleepForces;  ///< Forces when the body fell asleep; any change wakes it.
};

}  // namespace softtouch

#pragma once
// Measures a mode from baked motion: start a body on one mode shape, simulate, project the motion on
// that shape and fit the sampled signal (core's fitOscillation, Prony's method).

#include "core/modes/mode_accuracy.h"

namespace softtouch::test {

/// Bakes `seconds` of free vibration from rest + amplitude · mode.shape and fits it, sampling every
/// `sampleEvery` steps.
inline FittedOscillation measureMode(const std::shared_ptr<const BodyModel>& model, const SimulationSettings& settings,
                                     const VibrationMode& mode, double amplitude, double seconds, int sampleEvery = 1) {
    return fitOscillation(bakeModeProjection(model, settings, mode, amplitude, seconds, sampleEvery),
                          settings.dt * sampleEvery);
}

}  // namespace softtouch::test

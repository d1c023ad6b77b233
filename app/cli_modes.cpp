// `softtouch-cli modes`: the lowest vibration modes of each object of a scene, with what the scene's
// integrator and step do to them (core/modes/modes.h, core/modes/mode_accuracy.h), and pictures of their shapes
// (render/mode_pictures.h). The editor's Properties show the same figures and animate the shapes.
#include "app/bench_commands.h"
#include "app/cli_offscreen_gui.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "core/body/network_elasticity.h"
#include "core/modes/mode_accuracy.h"
#include "core/modes/modes.h"
#include "core/modes/solid_modes.h"
#include "io/documents/project_file.h"
#include "render/mode_pictures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace softtouch::cli {
namespace {

constexpr const char* kModesAbout = R"(Print the lowest vibration modes of each object of SCENE about its rest state: natural frequency,
damping ratio (split into node damping on absolute velocity and spring damping on relative velocity),
and what the scene's integrator at its time step does to each mode: the damping ratio the clip shows (the
material's and the integrator's together: implicit Euler adds its own), the amplitude kept per period
against what the material alone keeps, and the frequency error. Anchors and voids are as in the scene; the
analysis is linear, so it describes small wobbles (docs/design/lattice.md). Last, the solid the springs make:
Young's modulus along each box axis and the shear moduli under a uniform strain, beside the painted
modulus (they differ on flat or long cells: docs/design/lattice.md, "What solid the springs make").
)";

/// The converged solid's modes beside the lattice's, and the lattice's error on each. Goal springs toward a
/// base animation belong to the scene, not to the material, so the lattice is compared without them.
void printReference(const SceneObject& object, const SolidComparison& c) {
    const SolidModes& solid = c.solid;
    if (!solid.converged()) {
        std::printf("  no converged solid: from Bernstein degree %d to %d a mode moves by %.1f%%. A solid held at points "
                    "or along lines is not held in the limit; anchor whole faces for a reference (docs/design/lattice.md)\n",
                    solid.degree - 1, solid.degree, 100.0 * solid.spread);
        return;
    }
    std::printf("  converged solid (Bernstein degree %d, consistent mass, %d unknowns):", solid.degree, solid.unknowns);
    for (double f : solid.frequencyHz)
        std::printf(" %.4f", f);
    std::printf(" Hz (degree %d: within %.2f%%)\n  this lattice's error%s: %s\n", solid.degree - 1, 100.0 * solid.spread,
                object.baseAnimation ? " (without the goal springs)" : "", describeModeErrors(c.error).c_str());
    const bool far = std::any_of(c.error.begin(), c.error.end(), [](double e) { return std::abs(e) > kSpringDepartureTolerance; });
    if (far)
        std::printf("  more than %.0f%% off the material's solid: the frequencies above are this lattice's, not the "
                    "material's\n", 100.0 * kSpringDepartureTolerance);
}

}  // namespace

int runModes(const std::vector<std::string>& args) {
    std::string scenePath, objectName, picturePrefix;
    render::ModePictureOptions pictureOptions;
    std::pair<int, int> size{pictureOptions.width, pictureOptions.height};
    std::optional<double> count, amplitude, referenceDegree;
    bool reference = false;
    CommandLine line("modes", kModesAbout, "Exit status: 0 on success, 1 when SCENE cannot be loaded or analysed, 2 on bad usage.");
    line.positional("SCENE", scenePath, "The project to analyse (*.softtouch).");
    line.number("--count", count, {1, 20, true}, {"N", "Modes per object, 1..20 (default 3)."});
    line.text("--object", objectName, {"NAME", "Only this object."});
    std::string elementName;
    line.text("--element", elementName,
              {"springs|solid", "Analyse every object as if its material said this element (docs/design/lattice.md, "
                                "\"The solid element\"), the file unchanged: the same scene on springs and on the solid element."});
    line.flag("--reference", reference,
              "Also solve the solid the material describes without the lattice's approximations (Galerkin over a "
              "Bernstein basis of degree P with the consistent mass, anchors held fixed: core/modes/solid_modes.h) and "
              "print how far each of the lattice's modes is from it: the lattice's own error, which a finer lattice "
              "shrinks (docs/design/lattice.md).");
    line.number("--reference-degree", referenceDegree, {2, double(kMaxSolidDegree), true},
                {"P", "Degree of that basis per axis, 2..7 (default 5, within 0.4% of 7 on the bundled scenes; 3 on a "
                      "4x4x4 Bezier lattice is the textbook element on the same net). The solid is solved at P-1 too: "
                      "when a mode moves by more than 2% it is not converged (anchors at points or along lines never "
                      "are) and no error is printed."});
    line.text("--pictures", picturePrefix,
              {"PREFIX", "Also draw each mode of the object (the first, or --object) headless on the GPU (EGL, no X "
                         "server): the mesh deformed by +A x shape over a grey ghost of the rest pose, with the lattice "
                         "(springs coloured by strain, anchors black), seen across the motion. Writes PREFIX-1.png ... "
                         "PREFIX-N.png and PREFIX-modes.png, all side by side."});
    line.value("--size", sizeReader(size), {"WxH", "Size of each picture in pixels (default 640x400; 16..8192)."});
    line.number("--amplitude", amplitude, {0, 1},
                {"F", "A as a fraction of the lattice box's largest side (default 0.12, as the editor's mode view; 0 "
                      "draws the rest pose), [0, 1]."});
    if (const auto exit = line.parse(args))
        return *exit;
    pictureOptions.width = size.first;
    pictureOptions.height = size.second;
    pictureOptions.amplitudeFraction = amplitude.value_or(pictureOptions.amplitudeFraction);
    std::optional<BodyElement> asked;
    for (BodyElement e : {BodyElement::Springs, BodyElement::Solid})
        if (elementName == bodyElementName(e))
            asked = e;
    if (!elementName.empty() && !asked)
        return line.usage("--element is springs or solid, not '" + elementName + "'");
    auto project = io::loadProjectToRun(scenePath);
    if (!project)
        return fail(project.message());
    if (asked) {
        for (SceneObject& object : project->scene.objects) {
            object.material.element = *asked;
            if (Status s = checkSolverLimits(object, project->scene.world); !s)
                return fail(scenePath + ": " + s.message());
        }
    }
    const Scene& scene = project->scene;
    const SimulationSettings& settings = scene.world.simulation;
    bool found = false;
    bool pictured = false;
    for (const SceneObject& object : scene.objects) {
        if (!objectName.empty() && object.name != objectName)
            continue;
        found = true;
        auto body = buildLatticeBody(object.lattice, simulatedMaterial(object));
        if (!body)
            return fail(scenePath + ": object '" + object.name + "': " + body.message());
        auto modes = objectModes(object, int(count.value_or(3)));  // with goal springs on a base animation
        if (!modes)
            return fail(scenePath + ": object '" + object.name + "': " + modes.message());
        const double h = integrationStep(Simulator(body.value(), settings));
        const bool element = object.material.element == BodyElement::Solid;
        std::printf("%s: %d unknowns, %d rigid modes; %s; %s, dt %.6g s (step %.6g s)\n", object.name.c_str(),
                    modes->unknowns, modes->rigidModes, element ? "solid element" : "springs",
                    std::string(integratorName(settings.integrator)).c_str(), settings.dt, h);
        std::printf("  mode  frequency_hz  damping_ratio  node_part  spring_part  clip_damping_ratio  kept_per_period  material_alone  "
                    "frequency_error\n");
        std::string summary;  // what the scheme does to the lowest mode, in words
        const std::vector<ModeAccuracy> accuracy = schemeAccuracies(body.value(), settings, modes->modes);
        for (std::size_t m = 0; m < modes->modes.size(); ++m) {
            const VibrationMode& mode = modes->modes[m];
            const ModeAccuracy& a = accuracy[m];
            std::printf("  %4zu  %12.4f  %13.4f  %9.4f  %11.4f  %18.4f  %14.1f%%  %13.1f%%  %+14.2f%%\n", m + 1,
                        mode.frequencyHz, mode.dampingRatio, mode.nodeDampingRatio, mode.springDampingRatio, a.dampingRatio,
                        100.0 * a.amplitudePerPeriod, 100.0 * a.exactAmplitudePerPeriod, 100.0 * a.frequencyError);
            if (m == 0)
                summary = describeModeAccuracy(settings, mode, a);
        }
        if (!summary.empty())
            std::printf("  %s\n", summary.c_str());
        if (modes->rigidModes > 0) {  // a free body: how its spin fares under the scheme
            if (const std::string spin = describeSpinKept(body.value(), settings); !spin.empty())
                std::printf("  %s\n", spin.c_str());
        }
        // The element runs the painted material's solid; springs make their own network's.
        const NetworkElasticity e = element ? materialElasticity(object.lattice, object.material)
                                            : networkElasticity(object.lattice, object.material);
        const char* actor = element ? "solid element acts as" : "springs act as";
        if (e.resistsEveryStrain) {
            std::printf("  %s: E_u %.4g  E_v %.4g  E_w %.4g Pa, G_vw %.4g  G_uw %.4g  G_uv %.4g Pa", actor, e.youngsModulus.x(),
                        e.youngsModulus.y(), e.youngsModulus.z(), e.shearModulus.x(), e.shearModulus.y(), e.shearModulus.z());
            if (object.material.model == MaterialModel::Continuum)
                std::printf(" (painted modulus, mean %.4g Pa)", solidMean(object.material.stiffness, object.material));
            std::printf("\n");
        } else {
            std::printf("  %s: no resistance to some uniform strain (a spring kind scaled to 0)\n", actor);
        }
        if (const auto departure = element ? std::nullopt : springDeparture(object.lattice, object.material);
            departure && departure->largest() > kSpringDepartureTolerance)
            std::printf("  springs on these cells are not the painted material (%s): the modes are the springs'; "
                        "--reference measures them against the material's solid, which the solid element runs\n",
                        departure->describe().c_str());
        if (reference || referenceDegree) {
            const int degree = int(referenceDegree.value_or(kDefaultSolidDegree));
            auto compared = compareWithSolid(object.lattice, object.material, degree, int(count.value_or(3)));
            if (!compared)
                return fail(scenePath + ": object '" + object.name + "': reference solid: " + compared.message());
            printReference(object, compared.value());
        }
        if (!picturePrefix.empty() && !pictured) {
            pictured = true;
            const auto gui = offscreenApplication();
            auto written = render::writeModePictures(object, modes->modes, pictureOptions, picturePrefix);
            if (!written)
                return fail(scenePath + ": object '" + object.name + "': pictures: " + written.message());
            for (const std::string& file : written->files)
                std::printf("  wrote %s\n", file.c_str());
            std::printf("  (%dx%d, largest node displacement %.3g of the box's largest side; %s)\n", pictureOptions.width,
                        pictureOptions.height, pictureOptions.amplitudeFraction, written->context.c_str());
        }
    }
    if (!found)
        return fail(scenePath + ": no object named '" + objectName + "'");
    return 0;
}

}  // namespace softtouch::cli

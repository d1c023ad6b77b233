#include "core/integrator.h"

#include <array>

namespace softtouch {

std::unique_ptr<Integrator> makeSymplecticEuler();
std::unique_ptr<Integrator> makeVerlet();
std::unique_ptr<Integrator> makeImplicitEuler();
std::unique_ptr<Integrator> makeXpbd();

namespace {
constexpr std::array<std::pair<IntegratorKind, std::string_view>, 4> kNames{{
    {IntegratorKind::SymplecticEuler, "symplectic-euler"},
    {IntegratorKind::Verlet, "verlet"},
    {IntegratorKind::ImplicitEuler, "implicit-euler"},
    {IntegratorKind::Xpbd, "xpbd"},
}};
}  // namespace

std::string_view integratorName(IntegratorKind kind) {
    for (const auto& [k, name] : kNames) {
        if (k == kind)
            return name;
    }
    return "unknown";
}

std::optional<IntegratorKind> parseIntegratorKind(std::string_view name) {
    for (const auto& [k, n] : kNames) {
        if (n == name)
            return k;
    }
    return std::nullopt;
}

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::SymplecticEuler: return makeSymplecticEuler();
    case IntegratorKind::Verlet: return makeVerlet();
    case IntegratorKind::ImplicitEuler: return makeImplicitEuler();
    case IntegratorKind::Xpbd: return makeXpbd();
    }
    return makeImplicitEuler();
}

}  // namespace softtouch

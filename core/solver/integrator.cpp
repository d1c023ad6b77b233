#include "core/solver/integrator.h"

#include <array>
#include <vector>

namespace softtouch {

std::unique_ptr<Integrator> makeSymplecticEuler();
std::unique_ptr<Integrator> makeVerlet();
std::unique_ptr<Integrator> makeImplicitEuler();
std::unique_ptr<Integrator> makeXpbd();

namespace {

constexpr std::size_t kNoRow = std::size_t(-1);

/// Each kind's row of kIntegrators. Without a default, a kind added to the enum and not here stops the build
/// (-Wswitch is an error in every CI build); the assertion below then makes the rows follow the enum, one each.
constexpr std::size_t rowOf(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::SymplecticEuler: return 0;
    case IntegratorKind::Verlet: return 1;
    case IntegratorKind::ImplicitEuler: return 2;
    case IntegratorKind::Xpbd: return 3;
    }
    return kNoRow;
}

constexpr bool oneRowPerKind() {
    for (std::size_t r = 0; r < std::size(kIntegrators); ++r)
        if (rowOf(kIntegrators[r].kind) != r)
            return false;
    // The enum's values run from 0 with no gaps: the value after the last row is no kind at all.
    return rowOf(IntegratorKind(std::size(kIntegrators))) == kNoRow;
}
static_assert(oneRowPerKind(), "kIntegrators has one row per IntegratorKind, in rowOf()'s order");

}  // namespace

const IntegratorInfo& integratorInfo(IntegratorKind kind) {
    const std::size_t row = rowOf(kind);
    return kIntegrators[row != kNoRow ? row : rowOf(IntegratorKind::ImplicitEuler)];  // a value no file can hold
}

std::string_view integratorName(IntegratorKind kind) { return integratorInfo(kind).name; }

std::optional<IntegratorKind> parseIntegratorKind(std::string_view name) {
    for (const IntegratorInfo& info : kIntegrators)
        if (info.name == name)
            return info.kind;
    return std::nullopt;
}

std::string integratorNames(bool (*which)(const IntegratorInfo&)) {
    std::vector<std::string_view> names;
    for (const IntegratorInfo& info : kIntegrators)
        if (which(info))
            names.push_back(info.name);
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + ("\"" + std::string(names[i]) + "\"");
    return out;
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

#include "core/base/ranges.h"

#include <cstdio>

namespace softtouch {
namespace {

/// 0.1, 1e-05, 1000000: whole numbers in full, the rest as %g (what a user types back).
std::string rangeBound(double x) {
    char text[32];
    if (std::abs(x) < 1e15 && std::floor(x) == x)
        std::snprintf(text, sizeof text, "%.0f", x);
    else
        std::snprintf(text, sizeof text, "%g", x);
    return text;
}

}  // namespace

std::string FieldRange::describe() const {
    std::string text = whole ? "a whole number" : "a number";
    if (std::isfinite(low) && std::isfinite(high))
        text += std::string(" in ") + (lowIncluded ? "[" : "(") + rangeBound(low) + ", " + rangeBound(high) + "]";
    else if (std::isfinite(low))
        text += (lowIncluded ? " >= " : " > ") + rangeBound(low);
    else if (std::isfinite(high))
        text += " <= " + rangeBound(high);
    if (unit && *unit)
        text += std::string(" (") + unit + ")";
    return text;
}

std::string firstProblem(std::initializer_list<RangedValue> fields) {
    for (const RangedValue& f : fields)
        if (std::string p = f.range.problem(f.value); !p.empty())
            return p;
    return {};
}

std::string FieldRange::problem(double x) const {
    if (contains(x))
        return {};
    char value[32];
    std::snprintf(value, sizeof value, "%g", x);
    return std::string(label) + " must be " + describe() + ", got " + value;
}

}  // namespace softtouch

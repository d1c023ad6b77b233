#pragma once
/// The Table 1 section of `softtouch-cli bench`: every size measured (table1.h), printed as it goes,
/// and its JSON ("table1" rows; keys: docs/measurements/benchmarks.md).

#include "bench/table1.h"

#include <nlohmann/json.hpp>

#include <ostream>

namespace softtouch::bench {

/// One size as its "table1" JSON row.
nlohmann::json table1Json(const Table1Size& size, const Table1Options& options);

/// Measures every size of the paper's Table 1 (208 … 24,928 triangles; 208 … 2,160 when `quick`),
/// prints each as it is done and returns the JSON rows.
nlohmann::json table1Section(bool quick, std::ostream& out);

}  // namespace softtouch::bench

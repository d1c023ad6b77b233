#pragma once
/// Renders the study's error-against-cost plot to a PNG (log-log, one colour per integrator, the
/// Pareto front joined by a line). Headless: Qt's raster painter on a QImage, no display needed.

#include "bench/study.h"

#include <string>

namespace softtouch::cli {

/// Writes the plot; returns an empty string or the reason it failed.
std::string writeStudyPlot(const bench::StudyResult& result, const std::string& path);

}  // namespace softtouch::cli

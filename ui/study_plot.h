#pragma once
/// The study's error-against-cost plot (log-log, one colour per integrator, the Pareto front joined
/// by a line), drawn with Qt's raster painter on a QImage: written to a PNG by `softtouch-cli study`,
/// and shown by the editor with the current settings marked on it.

#include "analysis/study.h"

#include <QImage>

#include <optional>
#include <string>

namespace softtouch::ui {

/// A point to mark on the plot (the editor's current settings).
struct PlotMarker {
    double costPerSecond = 0.0;  ///< Wall seconds per simulated second.
    double rmsError = 0.0;       ///< The study's error (StudyResult::error), relative to the box diagonal.
    std::string label;           ///< Shown beside the mark.
};

/// Draws the plot at the given size (pixels). Needs a QGuiApplication for text. A null image when no
/// row is finite.
QImage renderStudyPlot(const analysis::StudyResult& result, int width, int height, const std::optional<PlotMarker>& marker = {});

/// Writes the 1000x700 plot as a PNG atomically (needs a QGuiApplication; headless:
/// app/cli_offscreen_gui.h); returns an empty string or the reason it failed.
std::string writeStudyPlot(const analysis::StudyResult& result, const std::string& path);

}  // namespace softtouch::ui

#include "ui/material_thumbnail.h"

#include "core/solver/simulator.h"

#include <QPainter>

#include <algorithm>

namespace softtouch::ui {

QImage materialThumbnail(const LatticeShape& shape, const LatticeMaterial& input, int size) {
    QImage image(size, size, QImage::Format_ARGB32);
    image.fill(QColor(245, 245, 245));
    QPainter p(&image);
    p.setRenderHint(QPainter::Antialiasing);
    OrientedBox box;
    box.size = Vec3(1.0, 1.0, 1.0);
    auto lattice = Lattice::create(shape, box);
    LatticeMaterial material = input;
    bool anchored = false;
    for (AnchorMode a : material.anchor)
        anchored = anchored || a != AnchorMode::Free;
    if (lattice && !anchored) {
        // A cantilever: the left face is held, so softness shows as a droop of the free end.
        for (int k = 0; k < lattice->count(2); ++k)
            for (int j = 0; j < lattice->count(1); ++j)
                material.anchor[std::size_t(lattice->index(0, j, k))] = AnchorMode::Pinned;
    }
    auto model = lattice ? buildLatticeBody(lattice.value(), material) : Result<std::shared_ptr<const BodyModel>>(Status::error(""));
    if (!model) {
        p.setPen(QPen(QColor(150, 150, 150), 2));
        p.drawLine(8, 8, size - 8, size - 8);
        p.drawLine(size - 8, 8, 8, size - 8);
        return image;
    }
    // Half a second of sag under a strong pull (6 g, so that the differences between presets show at
    // thumbnail size), implicit Euler (stable for any preset).
    SimulationSettings settings;
    settings.sleep = false;
    Simulator sim(model.value(), settings);
    ExternalForces gravity;
    gravity.gravity = Vec3(0, -6.0 * 9.81, 0);
    for (int s = 0; s < 120; ++s)
        sim.step(gravity);
    // Side view (x right, y up) of the front face's edges, with room below for the sag.
    const double margin = 0.18 * size;
    auto toPixel = [&](const Vec3& x) {
        return QPointF(margin + x.x() * (size - 2 * margin), margin + (1.0 - x.y()) * (size - 2 * margin) * 0.8);
    };
    const std::vector<Vec3> rest = lattice->restNodes();
    const std::vector<Vec3>& now = sim.state().position;
    const int k = 0;
    for (const auto& [pose, colour, width] : {std::tuple{&rest, QColor(200, 200, 205), 1.0},
                                              std::tuple{&now, QColor(40, 60, 120), 1.6}}) {
        p.setPen(QPen(colour, width));
        for (int j = 0; j < lattice->count(1); ++j)
            for (int i = 0; i < lattice->count(0); ++i) {
                const QPointF a = toPixel((*pose)[std::size_t(lattice->index(i, j, k))]);
                if (i + 1 < lattice->count(0))
                    p.drawLine(a, toPixel((*pose)[std::size_t(lattice->index(i + 1, j, k))]));
                if (j + 1 < lattice->count(1))
                    p.drawLine(a, toPixel((*pose)[std::size_t(lattice->index(i, j + 1, k))]));
            }
    }
    return image;
}

}  // namespace softtouch::ui

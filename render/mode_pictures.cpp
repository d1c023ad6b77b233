#include "render/mode_pictures.h"

#include "core/body/lattice_body.h"
#include "render/egl_context.h"
#include "render/mesh_renderer.h"

#include <QFont>
#include <QFontMetrics>
#include <QPainter>
#include <QSaveFile>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace softtouch::render {

namespace {

/// The 3/4 view `softtouch-cli render` uses; the mode views lean towards it so the pictures keep a sense
/// of depth and look at the body from the same side.
const Vec3 kThreeQuarterView = Vec3(-0.6, -0.45, -1.0).normalized();

/// Fraction of a picture's height kept free for the caption at the top.
constexpr double kCaptionRoom = 0.16;

/// Unit direction along which the mode moves the nodes most: the principal axis of Σ φ_i φ_iᵀ.
Vec3 mainDirection(const VibrationMode& mode) {
    Mat3 scatter = Mat3::Zero();
    for (const Vec3& phi : mode.shape)
        scatter += phi * phi.transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> solver(scatter);
    return solver.eigenvectors().col(2);  // eigenvalues ascend
}

/// The lattice's first axis: fitBox() puts it along the largest variance of the mesh, a fish's spine.
Vec3 spineAxis(const OrientedBox& box) { return box.axes.col(0).normalized(); }

QString captionLine(int index, const VibrationMode& mode) {
    return QStringLiteral("Mode %1 · %2 Hz · ζ %3")
        .arg(index)
        .arg(mode.frequencyHz, 0, 'f', 3)
        .arg(mode.dampingRatio, 0, 'f', 3);
}

void drawCaption(QImage& image, int index, const VibrationMode& mode, double fraction) {
    QPainter p(&image);
    p.setRenderHint(QPainter::Antialiasing);
    p.setRenderHint(QPainter::TextAntialiasing);
    QFont big = p.font();
    big.setPixelSize(std::max(11, image.height() / 20));
    big.setBold(true);
    QFont small = big;
    small.setPixelSize(std::max(9, image.height() / 30));
    small.setBold(false);
    const QString title = captionLine(index, mode);
    const QString note = QStringLiteral("+%1% of the box · grey: rest").arg(100.0 * fraction, 0, 'g', 3);
    const int pad = std::max(4, image.height() / 60);
    const int w = std::max(QFontMetrics(big).horizontalAdvance(title), QFontMetrics(small).horizontalAdvance(note));
    const int h = QFontMetrics(big).height() + QFontMetrics(small).height();
    p.fillRect(QRect(pad, pad, w + 2 * pad, h + 2 * pad), QColor(0, 0, 0, 110));
    p.setPen(Qt::white);
    p.setFont(big);
    p.drawText(QPoint(2 * pad, 2 * pad + QFontMetrics(big).ascent()), title);
    p.setFont(small);
    p.setPen(QColor(225, 225, 225));
    p.drawText(QPoint(2 * pad, 2 * pad + QFontMetrics(big).height() + QFontMetrics(small).ascent()), note);
}

}  // namespace

Camera modeCamera(const SceneObject& object, const VibrationMode& mode, double amplitude, int width, int height) {
    const Vec3 along = spineAxis(object.lattice.box());
    const Vec3 moves = mainDirection(mode);
    // Across the motion and the spine: a sideways tail swing seen from above, a vertical one from the side.
    Vec3 view = moves.cross(along);
    if (view.norm() < 0.3)  // the mode stretches the body along its spine: any view across it shows that
        view = kThreeQuarterView - kThreeQuarterView.dot(along) * along;
    view.normalize();
    if (view.dot(kThreeQuarterView) < 0.0)
        view = -view;
    // Lean 45 degrees towards the 3/4 view, about the spine only (it stays horizontal): a flat body
    // swinging across its plane then shows both its outline and its motion at cos 45° = 71% each.
    const Vec3 lean = kThreeQuarterView - kThreeQuarterView.dot(along) * along - kThreeQuarterView.dot(view) * view;
    if (lean.norm() > 1e-6)
        view = (view + 1.0 * lean.normalized()).normalized();
    Vec3 up = view.cross(along).normalized();
    if (std::abs(up.y()) > 0.05 ? up.y() < 0.0 : up.dot(kThreeQuarterView) > 0.0)
        up = -up;
    const Vec3 right = view.cross(up);

    // Frame the lattice at rest and displaced by the motion's room: the mesh stays inside the hull of its
    // nodes, so every pose drawn fits. The room is at least the default amplitude's, so a rest picture
    // (amplitude 0) shares the camera with the displaced one. The distance is the least at which every
    // point fits the view, measured in the camera's own axes.
    const double room = std::max(amplitude, kModeDisplayFraction * object.lattice.box().size.maxCoeff());
    std::vector<Vec3> points = object.lattice.restNodes();
    if (mode.shape.size() == points.size()) {
        const std::vector<Vec3> displaced = modePose(points, mode, room);
        points.insert(points.end(), displaced.begin(), displaced.end());
    }
    const Bounds bounds = boundsOf(points);
    const Vec3 centre = 0.5 * (bounds.min + bounds.max);
    const double aspect = double(width) / double(height);
    // The top kCaptionRoom of the picture is left to the caption: the body is fitted below it.
    const double tanX = std::tan(0.5 * double(kDefaultFovY)) * aspect;
    const double tanY = std::tan(0.5 * double(kDefaultFovY)) * (1.0 - kCaptionRoom);
    double distance = 0.0, depth = 0.0;
    for (const Vec3& p : points)
        depth = std::max(depth, std::abs((p - centre).dot(view)));
    for (const Vec3& p : points) {
        // A point nearer the camera needs more distance: its depth counts against the one in front.
        const Vec3 c = p - centre;
        distance = std::max({distance, std::abs(c.dot(right)) / tanX - c.dot(view), std::abs(c.dot(up)) / tanY - c.dot(view)});
    }
    distance = std::max(distance * 1.08, depth + 1e-3);
    Camera camera;
    camera.view = lookAt((centre - view * distance).cast<float>(), centre.cast<float>(), up.cast<float>());
    camera.projection = perspective(kDefaultFovY, float(aspect), float(std::max(distance - 2.0 * depth, distance * 0.01)),
                                    float(distance + 2.0 * depth));
    // Shift the picture down by half the caption's room (y_ndc -= kCaptionRoom, written on clip space).
    camera.projection.row(1) -= float(kCaptionRoom) * camera.projection.row(3);
    return camera;
}

Result<std::vector<ModePicture>> renderModePictures(const SceneObject& object, const std::vector<VibrationMode>& modes,
                                                    const ModePictureOptions& options, std::string* contextName) {
    if (options.width < 16 || options.height < 16 || options.width > 8192 || options.height > 8192)
        return Status::error("picture size must be 16..8192 pixels a side");
    if (!(options.amplitudeFraction >= 0.0 && options.amplitudeFraction <= 1.0))
        return Status::error("the amplitude must be a fraction of the box in [0, 1]");
    auto body = buildLatticeBody(object.lattice, object.material);
    if (!body)
        return Status::error(body.message());
    const BodyModel& model = *body.value();
    for (const VibrationMode& mode : modes) {
        if (mode.shape.size() != model.nodeCount())
            return Status::error("a mode shape does not match the object's lattice");
    }
    auto context = EglContext::create(options.width, options.height, 4);
    if (!context)
        return Status::error("cannot create a headless OpenGL context: " + context.message());
    if (contextName)
        *contextName = context.value()->description();
    MeshRenderer renderer;
    if (Status s = renderer.initialize(); !s)
        return s;
    // Object 0: the rest pose, translucent; object 1: the body displaced along the mode, with its lattice.
    for (int copy = 0; copy < 2; ++copy) {
        if (auto id = renderer.addObject(object.mesh, object.lattice); !id) {
            renderer.release();
            return Status::error("object '" + object.name + "': " + id.message());
        }
    }
    MeshStyle ghost;
    ghost.mode = ShadeMode::XRay;
    ghost.colour = Eigen::Vector3f(0.78f, 0.84f, 0.95f);
    renderer.setStyle(0, ghost);
    renderer.setStyle(1, MeshStyle{});

    const std::vector<Vec3>& rest = model.restPositions;
    const double amplitude = options.amplitudeFraction * object.lattice.box().size.maxCoeff();
    LatticeOverlay overlay;
    for (std::size_t n = 0; n < rest.size(); ++n) {
        overlay.anchor.push_back(std::uint8_t(object.material.anchor[n]));
        overlay.isVoid.push_back(object.material.isVoid[n]);
    }
    overlay.nodeSizePixels = float(std::clamp(options.height / 50.0, 5.0, 16.0));

    std::vector<ModePicture> pictures;
    std::vector<std::uint8_t> pixels;
    Status drawn = Status::success();
    for (std::size_t m = 0; m < modes.size() && drawn; ++m) {
        const std::vector<Vec3> pose = modePose(rest, modes[m], amplitude);
        renderer.setNodes(0, rest);
        renderer.setNodes(1, pose);
        // Edge springs only, as the editor draws them, coloured by how the mode stretches them.
        overlay.springs.clear();
        overlay.springStrain.clear();
        for (const Spring& s : model.springs) {
            if (s.kind != SpringKind::Edge)
                continue;
            overlay.springs.emplace_back(s.a, s.b);
            overlay.springStrain.push_back(float(((pose[s.b] - pose[s.a]).norm() - s.restLength) / s.restLength));
        }
        renderer.setOverlay(1, overlay);
        renderer.setOverlayVisible(1, true);
        ModePicture picture;
        picture.amplitude = amplitude;
        picture.camera = modeCamera(object, modes[m], amplitude, options.width, options.height);
        context.value()->bindFramebuffer();
        renderer.draw(picture.camera, options.width, options.height);
        drawn = context.value()->readPixels(pixels);
        if (!drawn)
            break;
        picture.image = QImage(pixels.data(), options.width, options.height, options.width * 4, QImage::Format_RGBA8888)
                            .convertToFormat(QImage::Format_RGB32);
        if (options.caption)
            drawCaption(picture.image, int(m) + 1, modes[m], options.amplitudeFraction);
        pictures.push_back(std::move(picture));
    }
    renderer.release();
    if (!drawn)
        return drawn;
    return pictures;
}

Result<ModePicturesWritten> writeModePictures(const SceneObject& object, const std::vector<VibrationMode>& modes,
                                              const ModePictureOptions& options, const std::string& prefix) {
    if (modes.empty())
        return Status::error("no mode to draw");
    ModePicturesWritten written;
    auto pictures = renderModePictures(object, modes, options, &written.context);
    if (!pictures)
        return Status::error(pictures.message());

    std::vector<std::pair<std::string, QImage>> files;
    QImage strip(options.width * int(pictures->size()), options.height, QImage::Format_RGB32);
    strip.fill(QColor(40, 40, 44));
    {
        QPainter p(&strip);
        for (std::size_t m = 0; m < pictures->size(); ++m) {
            const QImage& image = pictures.value()[m].image;
            files.emplace_back(prefix + "-" + std::to_string(m + 1) + ".png", image);
            p.drawImage(int(m) * options.width, 0, image);
            if (m > 0)
                p.fillRect(int(m) * options.width - 1, 0, 2, options.height, QColor(40, 40, 44));
        }
    }
    files.emplace_back(prefix + "-modes.png", strip);
    // Every picture is drawn before any file is touched; each file is replaced atomically.
    for (const auto& [path, image] : files) {
        QSaveFile file(QString::fromStdString(path));
        if (!file.open(QIODevice::WriteOnly) || !image.save(&file, "PNG") || !file.commit())
            return Status::error("cannot write '" + path + "': " + file.errorString().toStdString());
        written.files.push_back(path);
    }
    return written;
}

}  // namespace softtouch::render

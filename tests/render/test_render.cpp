// The renderer's vertex shader against core's Binding, and frames drawn headless through EGL.
#include "core/geometry/binding.h"
#include "core/geometry/lattice.h"
#include "core/geometry/primitives.h"
#include "render/egl_context.h"
#include "render/mesh_renderer.h"

#include <Eigen/Geometry>
#include <QtTest>

#include <set>

#include <random>

using namespace softtouch;

namespace {

/// A box far from the origin and rotated, so precision and the cofactor algebra are both exercised.
OrientedBox rotatedBox() {
    OrientedBox box;
    box.axes = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    box.origin = Vec3(10.0, -4.0, 2.5);
    box.size = Vec3(2.0, 0.5, 1.25);
    return box;
}

/// An ellipsoid filling most of the box (made in parameter space, mapped to world).
Mesh meshInBox(const OrientedBox& box) {
    Mesh mesh = makeUvEllipsoid(24, 48, Vec3::Constant(0.42), Vec3::Constant(0.5));
    for (Vec3f& p : mesh.positions)
        p = box.toWorld(p.cast<double>()).cast<float>();
    mesh.computeNormals();
    return mesh;
}

std::vector<Vec3> displacedNodes(const Lattice& lattice, double amount, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<Vec3> nodes = lattice.restNodes();
    for (Vec3& n : nodes)
        n += amount * Vec3(uniform(random), uniform(random), uniform(random));
    return nodes;
}

int maxChannelDifference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int width, int x, int y) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
        const std::size_t i = (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4 + std::size_t(c);
        worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    }
    return worst;
}

}  // namespace

class TestRender : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void cleanupTestCase();
    void deformationMatchesBinding_data();
    void deformationMatchesBinding();
    void cpuDeformedMeshIsDrawnAsGiven();
    void sphereCoversMiddleNotCorners();
    void collidersAreDrawnWhereTheyAre();
    void shadedAndWireframeDiffer();
    void overlayAndPlanesDraw();

private:
    /// Draws one sphere object (or none) and returns the frame.
    std::vector<std::uint8_t> frame(bool withSphere, render::ShadeMode mode, bool overlay = false, bool planes = false);

    std::unique_ptr<render::EglContext> m_context;
    render::MeshRenderer m_renderer;
    static constexpr int kSize = 160;
};

void TestRender::initTestCase() {
    // Skip only when there is no EGL driver at all; with one (Mesa's llvmpipe here) everything must work.
    if (Status driver = render::EglContext::probeDriver(); !driver)
        QSKIP(("no EGL driver: " + driver.message()).c_str());
    auto context = render::EglContext::create(kSize, kSize, 4);
    QVERIFY2(context.ok(), context.message().c_str());
    m_context = std::move(context.value());
    qInfo("%s", m_context->description().c_str());
    Status initialized = m_renderer.initialize();
    QVERIFY2(initialized.ok(), initialized.message().c_str());
}

void TestRender::cleanupTestCase() {
    if (m_context && m_context->makeCurrent().ok()) {
        m_renderer.release();
        m_renderer.release();  // documented as safe twice
    }
    m_context.reset();
}

void TestRender::deformationMatchesBinding_data() {
    QTest::addColumn<int>("kind");
    QTest::addColumn<int>("nx");
    QTest::addColumn<int>("ny");
    QTest::addColumn<int>("nz");
    QTest::newRow("bezier 4x4x4") << int(LatticeKind::Bezier) << 4 << 4 << 4;
    QTest::newRow("bezier 8x8x8 (degree 7)") << int(LatticeKind::Bezier) << 8 << 8 << 8;
    QTest::newRow("bspline 8x4x4") << int(LatticeKind::BSpline) << 8 << 4 << 4;
    QTest::newRow("bspline 12x12x12") << int(LatticeKind::BSpline) << 12 << 12 << 12;
}

void TestRender::deformationMatchesBinding() {
    QFETCH(int, kind);
    QFETCH(int, nx);
    QFETCH(int, ny);
    QFETCH(int, nz);
    const OrientedBox box = rotatedBox();
    auto lattice = Lattice::create({LatticeKind(kind), {nx, ny, nz}}, box);
    QVERIFY2(lattice.ok(), lattice.message().c_str());
    const Mesh mesh = meshInBox(box);
    const double diagonal = box.diagonal();
    const std::vector<Vec3> nodes = displacedNodes(lattice.value(), 0.08 * diagonal, unsigned(nx * 100 + ny * 10 + nz));

    const Binding binding = Binding::create(lattice.value(), mesh.positions, mesh.normals);
    std::vector<Vec3f> cpuPositions(mesh.positions.size()), cpuNormals(mesh.positions.size());
    binding.evaluate(nodes, cpuPositions, cpuNormals, 1);

    m_renderer.clearObjects();
    auto id = m_renderer.addObject(mesh, lattice.value());
    QVERIFY2(id.ok(), id.message().c_str());
    m_renderer.setNodes(id.value(), nodes);
    std::vector<Vec3f> gpuPositions, gpuNormals;
    Status read = m_renderer.readDeformed(id.value(), gpuPositions, gpuNormals);
    QVERIFY2(read.ok(), read.message().c_str());
    QCOMPARE(gpuPositions.size(), mesh.positions.size());
    QCOMPARE(gpuNormals.size(), mesh.positions.size());

    double positionError = 0.0, normalError = 0.0, moved = 0.0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        positionError = std::max(positionError, double((gpuPositions[v] - cpuPositions[v]).norm()));
        normalError = std::max(normalError, double((gpuNormals[v] - cpuNormals[v]).norm()));
        moved = std::max(moved, double((cpuPositions[v] - mesh.positions[v]).norm()));
    }
    qInfo("%zu vertices: max position difference %.3g of the diagonal, max normal difference %.3g, deformation %.3g",
          mesh.positions.size(), positionError / diagonal, normalError, moved / diagonal);
    QVERIFY2(moved > 0.01 * diagonal, "the random node displacement must visibly deform the mesh");
    QVERIFY2(positionError <= 1e-5 * diagonal, qPrintable(QString("position error %1").arg(positionError)));
    QVERIFY2(normalError <= 1e-3, qPrintable(QString("normal error %1").arg(normalError)));

    // Back at rest the map is the identity: the GPU returns the rest mesh.
    m_renderer.setNodes(id.value(), lattice->restNodes());
    read = m_renderer.readDeformed(id.value(), gpuPositions, gpuNormals);
    QVERIFY2(read.ok(), read.message().c_str());
    double restError = 0.0;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        restError = std::max(restError, double((gpuPositions[v] - mesh.positions[v]).norm()));
    QVERIFY2(restError <= 1e-5 * diagonal, qPrintable(QString("rest error %1").arg(restError)));
    m_renderer.clearObjects();
}

// A body on a base animation is deformed on the CPU (the rig moves it) and drawn as given: the shader passes
// the positions and normals through, bit for bit.
void TestRender::cpuDeformedMeshIsDrawnAsGiven() {
    const OrientedBox box = rotatedBox();
    const Lattice lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, box).value();
    const Mesh mesh = meshInBox(box);
    std::vector<Vec3f> positions(mesh.positions.size()), normals(mesh.positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const Vec3f p = mesh.positions[v];
        positions[v] = p + Vec3f(0.1f * std::sin(7.0f * p.y()), 0.0f, 0.05f * p.x());  // no lattice makes this
        normals[v] = Vec3f(p.x(), 1.0f, 0.5f).normalized();
    }
    m_renderer.clearObjects();
    auto id = m_renderer.addObject(mesh, lattice);
    QVERIFY2(id.ok(), id.message().c_str());
    m_renderer.setDeformed(id.value(), positions, normals, lattice.restNodes());
    std::vector<Vec3f> gpuPositions, gpuNormals;
    const Status read = m_renderer.readDeformed(id.value(), gpuPositions, gpuNormals);
    QVERIFY2(read.ok(), read.message().c_str());
    QCOMPARE(gpuPositions, positions);
    QCOMPARE(gpuNormals, normals);
    m_renderer.clearObjects();
}

std::vector<std::uint8_t> TestRender::frame(bool withSphere, render::ShadeMode mode, bool overlay, bool planes) {
    m_renderer.clearObjects();
    m_renderer.setPlanes({}, 1.0f);
    Mesh sphere = makeUvEllipsoid(32, 64, Vec3::Constant(1.0), Vec3(3.0, 1.0, -2.0));
    const Bounds bounds = sphere.bounds();
    if (withSphere) {
        auto box = fitBox(sphere.positions);
        auto lattice = Lattice::create({LatticeKind::Bezier, {3, 3, 3}}, box.value());
        auto id = m_renderer.addObject(sphere, lattice.value());
        if (!id.ok())
            qFatal("%s", id.message().c_str());
        m_renderer.setStyle(id.value(), {mode, {0.95f, 0.55f, 0.2f}});
        if (overlay) {
            render::LatticeOverlay o;
            o.nodeValue.assign(27, 0.0f);
            o.nodeValue[13] = 1.0f;
            o.anchor.assign(27, 0);
            o.anchor[0] = 1;
            o.springs = {{0, 1}, {1, 2}, {0, 26}};
            o.springStrain = {-0.2f, 0.0f, 0.3f};
            m_renderer.setOverlay(id.value(), o);
            m_renderer.setOverlayVisible(id.value(), true);
        }
    }
    if (planes) {
        const CollisionPlane floor{Vec3(3.0, 0.0, -2.0), Vec3::UnitY(), 0.0, 0.5};
        m_renderer.setPlanes(std::span(&floor, 1), 2.5f);
    }
    const render::Camera camera = render::frameBounds(bounds, Eigen::Vector3f(-1.0f, -0.6f, -1.0f), 1.0f);
    m_context->bindFramebuffer();
    m_renderer.draw(camera, kSize, kSize);
    std::vector<std::uint8_t> pixels;
    Status read = m_context->readPixels(pixels);
    if (!read)
        qFatal("%s", read.message().c_str());
    m_renderer.clearObjects();
    return pixels;
}

void TestRender::sphereCoversMiddleNotCorners() {
    const auto background = frame(false, render::ShadeMode::Shaded);
    const auto sphere = frame(true, render::ShadeMode::Shaded);
    QCOMPARE(sphere.size(), std::size_t(kSize * kSize * 4));
    // The background is a vertical gradient, lighter at the top.
    QVERIFY(background[4 * 2 + 0] > background[(std::size_t(kSize - 3) * kSize + 2) * 4 + 0]);
    const int c = kSize / 2;
    for (auto [x, y] : {std::pair{c, c}, {c - 10, c + 5}, {c + 8, c - 8}})
        QVERIFY2(maxChannelDifference(background, sphere, kSize, x, y) > 40, "the sphere covers the middle");
    for (auto [x, y] : {std::pair{1, 1}, {kSize - 2, 1}, {1, kSize - 2}, {kSize - 2, kSize - 2}})
        QVERIFY2(maxChannelDifference(background, sphere, kSize, x, y) <= 1, "the corners show the background");
}

// A box collider on the left and a capsule on the right, nothing else: each covers its own side of the
// picture and shades its faces differently; without them the background shows.
void TestRender::collidersAreDrawnWhereTheyAre() {
    const Bounds bounds{Vec3(-1.0, -1.0, -1.0), Vec3(1.0, 1.0, 1.0)};
    const render::Camera camera = render::frameBounds(bounds, Eigen::Vector3f(0.0f, 0.0f, -1.0f), 1.0f);
    auto draw = [&](std::span<const Collider> colliders) {
        m_renderer.setColliders(colliders);
        m_context->bindFramebuffer();
        m_renderer.draw(camera, kSize, kSize);
        std::vector<std::uint8_t> pixels;
        if (Status read = m_context->readPixels(pixels); !read)
            qFatal("%s", read.message().c_str());
        return pixels;
    };
    Collider box, capsule;
    box.shape = ColliderShape::Box;
    box.centre = Vec3(-0.55, 0.0, 0.0);
    box.halfExtents = Vec3(0.3, 0.3, 0.3);
    box.axes = Eigen::AngleAxisd(0.6, Vec3(1, 1, 0).normalized()).toRotationMatrix();  // three faces in view
    capsule.shape = ColliderShape::Capsule;
    capsule.centre = Vec3(0.55, 0.0, 0.0);
    capsule.radius = 0.2;
    capsule.halfLength = 0.4;
    capsule.axis = Vec3::UnitY();
    const std::vector<Collider> both{box, capsule};
    const auto empty = draw({});
    const auto drawn = draw(both);
    m_renderer.setColliders({});
    for (const Vec3& centre : {box.centre, capsule.centre, Vec3(capsule.centre + Vec3(0, 0.45, 0))}) {
        const Eigen::Vector3d p = render::toPixels(camera, centre, kSize, kSize);
        QVERIFY2(maxChannelDifference(empty, drawn, kSize, int(p.x()), int(p.y())) > 30,
                 qPrintable(QString("nothing drawn at (%1, %2)").arg(p.x()).arg(p.y())));
    }
    const Eigen::Vector3d gap = render::toPixels(camera, Vec3(0.0, 0.8, 0.0), kSize, kSize);  // between and above
    QVERIFY(maxChannelDifference(empty, drawn, kSize, int(gap.x()), int(gap.y())) <= 1);
    // Faceted shading: the box shows faces of different brightness.
    std::set<int> shades;
    for (int dy = -12; dy <= 12; dy += 4)
        for (int dx = -12; dx <= 12; dx += 4) {
            const Eigen::Vector3d p = render::toPixels(camera, box.centre, kSize, kSize);
            shades.insert(drawn[(std::size_t(int(p.y()) + dy) * kSize + std::size_t(int(p.x()) + dx)) * 4] / 8);
        }
    QVERIFY2(shades.size() >= 2, "the box's faces are shaded alike");
}

void TestRender::shadedAndWireframeDiffer() {
    const auto shaded = frame(true, render::ShadeMode::Shaded);
    const auto wire = frame(true, render::ShadeMode::Wireframe);
    const auto xray = frame(true, render::ShadeMode::XRay);
    int wireDiffers = 0, xrayDiffers = 0;
    for (int y = kSize / 4; y < 3 * kSize / 4; ++y)
        for (int x = kSize / 4; x < 3 * kSize / 4; ++x) {
            wireDiffers += maxChannelDifference(shaded, wire, kSize, x, y) > 20;
            xrayDiffers += maxChannelDifference(shaded, xray, kSize, x, y) > 20;
        }
    const int area = (kSize / 2) * (kSize / 2);
    qInfo("middle pixels differing from shaded: wireframe %d, x-ray %d of %d", wireDiffers, xrayDiffers, area);
    QVERIFY(wireDiffers > area / 10);
    QVERIFY(xrayDiffers > area / 10);
}

void TestRender::overlayAndPlanesDraw() {
    const auto plain = frame(true, render::ShadeMode::Shaded);
    const auto withOverlay = frame(true, render::ShadeMode::Shaded, true);
    const auto withPlane = frame(true, render::ShadeMode::Shaded, false, true);
    int overlayDiffers = 0, planeDiffers = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            overlayDiffers += maxChannelDifference(plain, withOverlay, kSize, x, y) > 20;
            planeDiffers += maxChannelDifference(plain, withPlane, kSize, x, y) > 10;
        }
    qInfo("pixels changed: overlay %d, plane %d", overlayDiffers, planeDiffers);
    QVERIFY2(overlayDiffers > 27 * 10, "27 node discs and 3 springs are drawn");
    QVERIFY2(planeDiffers > kSize * kSize / 20, "the floor plane is drawn");
}

QTEST_GUILESS_MAIN(TestRender)
#include "test_render.moc"

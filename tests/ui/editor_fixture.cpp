// The window every editor test opens, its helpers, and the program's main().
#include "editor_fixture.h"

namespace softtouch::test::editor {

void dragWith(QWidget* widget, QPoint from, QPoint to, Qt::KeyboardModifiers modifiers) {
    QTest::mousePress(widget, Qt::LeftButton, modifiers, from);
    QTest::mouseMove(widget, (from + to) / 2);
    QTest::mouseMove(widget, to);
    QTest::mouseRelease(widget, Qt::LeftButton, modifiers, to);
}

QStringList chooseFromMenu(QWidget* widget, QPoint at, const QString& menuName, const QString& text) {
    QStringList offered;
    // The menu is modal: it is answered from a timer while it runs.
    QTimer::singleShot(100, widget, [&] {
        auto* menu = qobject_cast<QMenu*>(QApplication::activePopupWidget());
        if (!menu || menu->objectName() != menuName)
            return;
        for (QAction* action : menu->actions()) {
            offered << action->text();
            if (action->text() == text)
                action->trigger();
        }
        menu->close();
    });
    QContextMenuEvent rightClick(QContextMenuEvent::Mouse, at, widget->mapToGlobal(at));
    QApplication::sendEvent(widget, &rightClick);
    return offered;
}

/// Largest distance between two vertex sets.
double maxDistance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, double((a[i] - b[i]).norm()));
    return d;
}

bool sameMaterial(const LatticeMaterial& a, const LatticeMaterial& b) {
    return a.mass == b.mass && a.stiffness == b.stiffness && a.damping == b.damping && a.nodeDamping == b.nodeDamping &&
           a.anchor == b.anchor && a.isVoid == b.isVoid && a.anisotropy == b.anisotropy && a.kindScale == b.kindScale &&
           a.volumePreservation == b.volumePreservation;
}

/// Fraction of pixels inside `region` that differ from the background of their row (the background
/// is a vertical gradient, sampled at the left edge).
double coverage(const QImage& image, const QRect& region) {
    int differ = 0, total = 0;
    for (int y = std::max(region.top(), 0); y <= std::min(region.bottom(), image.height() - 1); ++y) {
        const QColor background = image.pixelColor(1, y);
        for (int x = std::max(region.left(), 0); x <= std::min(region.right(), image.width() - 1); ++x) {
            const QColor c = image.pixelColor(x, y);
            const int d = std::abs(c.red() - background.red()) + std::abs(c.green() - background.green()) +
                          std::abs(c.blue() - background.blue());
            differ += d > 24 ? 1 : 0;
            ++total;
        }
    }
    return total > 0 ? double(differ) / total : 0.0;
}

/// One brush stroke across the middle of the viewport: press, six moves of 20 px, release, with the
/// brush at strength 0.8 and an 80 px radius (the field and value are the caller's).
void paintStroke(Viewport* view) {
    view->brush().strength = 0.8;
    view->brush().radiusPixels = 80.0;
    const QPoint start = view->rect().center() - QPoint(60, 0);
    QTest::mousePress(view, Qt::LeftButton, {}, start);
    for (int i = 1; i <= 6; ++i)
        QTest::mouseMove(view, start + QPoint(20 * i, 0));
    QTest::mouseRelease(view, Qt::LeftButton, {}, start + QPoint(120, 0));
}

/// The properties panel analyses the modes off the UI thread: waits until the latest edit's are shown.
void waitForModes(MainWindow& w) {
    auto* modes = w.findChild<QLabel*>("modes");
    QVERIFY(modes);
    QTRY_VERIFY_WITH_TIMEOUT(!modes->property("analysing").toBool(), 30000);
}

/// The study dock keeps its references in the test's own folder: none from another run is found there.
void keepReferencesIn(const QTemporaryDir& dir) {
    QVERIFY(QDir().mkpath(dir.filePath("cache")));
    qputenv("XDG_CACHE_HOME", dir.filePath("cache").toUtf8());
}

void answerSaveDialog(QFileDialog& dialog, const QString& nameFilter, const QString& path) {
    dialog.selectNameFilter(nameFilter);
    dialog.setDirectory(QFileInfo(path).absolutePath());
    if (auto* name = dialog.findChild<QLineEdit*>("fileNameEdit"))
        name->setText(QFileInfo(path).fileName());
    else
        dialog.selectFile(path);
    static_cast<QDialog&>(dialog).accept();  // QFileDialog::accept, through its public base
}

}  // namespace softtouch::test::editor

void TestEditor::initTestCase() {
    m_cacheHome = qgetenv("XDG_CACHE_HOME");
    QDesktopServices::setUrlHandler("file", this, "desktopOpened");
    QStandardPaths::setTestModeEnabled(true);
    QApplication::setOrganizationName("SoftTouchTests");
    QApplication::setApplicationName("test_editor");
    m_unansweredDialogs.setInterval(15000);  // tests answer theirs within a second or two, even under ASan
    connect(&m_unansweredDialogs, &QTimer::timeout, this, [this] {
        QWidget* modal = QApplication::activeModalWidget();
        if (modal && modal == m_openSinceLastTick) {
            const auto* box = qobject_cast<QMessageBox*>(modal);
            qWarning("closing a dialog no test answered: '%s' %s", qPrintable(modal->windowTitle()),
                     box ? qPrintable(box->text()) : "");
            if (auto* dialog = qobject_cast<QDialog*>(modal))
                dialog->reject();
            else
                modal->close();
            modal = nullptr;
        }
        m_openSinceLastTick = modal;
    });
    m_unansweredDialogs.start();
}

void TestEditor::init() {
    m_dir = std::make_unique<QTemporaryDir>();
    QVERIFY(m_dir->isValid());
    QSettings().clear();
    m_window = makeWindow();
    QVERIFY(m_window->openFile(kDefaultScene));
    m_window->simulation()->pause();  // tests advance time themselves
}

void TestEditor::cleanup() {
    m_desktopOpened.clear();
    if (m_window)
        m_window->document()->undoStack()->setClean();  // no unsaved-changes prompt on close
    m_window.reset();
    m_dir.reset();
    // Every function runs in one process: what one test points at is gone with its folder.
    if (m_cacheHome.isNull())
        qunsetenv("XDG_CACHE_HOME");
    else
        qputenv("XDG_CACHE_HOME", m_cacheHome);
}

std::unique_ptr<MainWindow> TestEditor::makeWindow() {
    MainWindowOptions options;
    options.autosaveFolder = m_dir->filePath("autosave");
    options.autosaveMilliseconds = 100;
    options.presetFolder = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/materials");
    options.webFolder = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/web");
    options.shaderFolder = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/io/shaders");
    auto w = std::make_unique<MainWindow>(options);
    w->resize(1280, 800);
    w->show();
    if (!QTest::qWaitForWindowExposed(w.get()))
        qWarning("window not exposed");
    return w;
}

Viewport* TestEditor::startPosing(MainWindow& w) const {
    w.activateWindow();
    if (!QTest::qWaitForWindowActive(&w))
        qWarning("window not active");
    w.simulation()->setDriversEnabled(false);
    w.simulation()->reset();
    w.findChild<QAction*>("toolPose")->trigger();
    w.viewport()->setFocus();
    return w.viewport();
}

QPoint TestEditor::screenOfNode(MainWindow& w, int node) const {
    const auto& x = w.simulation()->simulation()->simulator(0).state().position;
    return w.viewport()->toWidget(x[std::size_t(node)]).toPoint();
}

int TestEditor::isolatedNode(MainWindow& w, int object) const {
    // A node whose screen position is far from every other node's, so a click picks it unambiguously.
    const auto& x = w.simulation()->simulation()->simulator(std::size_t(object)).state().position;
    int best = -1;
    double bestGap = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) {
        const QPointF p = w.viewport()->toWidget(x[n]);
        if (!w.viewport()->rect().adjusted(20, 20, -20, -20).contains(p.toPoint()))
            continue;
        double gap = 1e9;
        for (std::size_t m = 0; m < x.size(); ++m)
            if (m != n)
                gap = std::min(gap, QLineF(p, w.viewport()->toWidget(x[m])).length());
        if (gap > bestGap && w.document()->scene().objects[0].material.anchor[n] == AnchorMode::Free) {
            bestGap = gap;
            best = int(n);
        }
    }
    return bestGap > 4.0 ? best : -1;
}

int main(int argc, char** argv) {
    QSurfaceFormat format;
    format.setVersion(3, 3);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setDepthBufferSize(24);
    QSurfaceFormat::setDefaultFormat(format);
    QApplication app(argc, argv);
    TestEditor test;
    return QTest::qExec(&test, argc, argv);
}


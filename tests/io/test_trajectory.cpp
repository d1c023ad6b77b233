// Trajectory files (docs/formats.md): round trip bit for bit, velocities from positions, and bad
// files rejected with the file, the JSON pointer and what was expected.
#include "io/documents/trajectory_file.h"

#include <QtTest/QtTest>
#include <QTemporaryDir>

#include <cstring>
#include <fstream>

using namespace softtouch;

namespace {
std::filesystem::path writeText(const QTemporaryDir& dir, const char* name, const std::string& text) {
    const std::filesystem::path path = std::filesystem::path(dir.path().toStdString()) / name;
    std::ofstream(path) << text;
    return path;
}
}  // namespace

class TestTrajectory : public QObject {
    Q_OBJECT
private slots:
    void roundTripIsBitExact();
    void velocitiesFromPositions();
    void badFiles_data();
    void badFiles();
    void failedSaveKeepsTheOldFile();
};

void TestTrajectory::roundTripIsBitExact() {
    QTemporaryDir dir;
    io::Trajectory t;
    t.device.name = "Recorded pen";
    t.device.buttons = 3;
    for (int i = 0; i < 50; ++i) {
        DeviceSample s;
        s.time = i / 1000.0 + 1e-7 * std::sin(i);  // not round numbers: digits must survive
        s.position = Vec3(std::sin(0.1 * i) / 3.0, std::cos(0.2 * i) / 7.0, 1.0 / (i + 3.0));
        s.velocity = Vec3(0.1 / 3.0 * std::cos(0.1 * i), -0.2 / 7.0 * std::sin(0.2 * i), -1.0 / ((i + 3.0) * (i + 3.0)));
        s.buttons = std::uint32_t(i % 4);
        s.pressure = (i % 10) / 9.0;
        s.tiltX = 0.3 / (i + 1);
        s.tiltY = -0.2 / (i + 1);
        t.samples.push_back(s);
    }
    const auto path = std::filesystem::path(dir.path().toStdString()) / "session.sttraj";
    QVERIFY(io::saveTrajectory(path, t).ok());
    const auto back = io::loadTrajectory(path);
    QVERIFY2(back.ok(), back.message().c_str());
    QCOMPARE(back->device.name, std::string("Recorded pen"));
    QCOMPARE(back->device.buttons, 3);
    QCOMPARE(back->samples.size(), t.samples.size());
    for (std::size_t i = 0; i < t.samples.size(); ++i) {
        const DeviceSample &a = t.samples[i], &b = back->samples[i];
        QVERIFY(a.time == b.time && a.position == b.position && a.velocity == b.velocity && a.buttons == b.buttons &&
                a.pressure == b.pressure && a.tiltX == b.tiltX && a.tiltY == b.tiltY);
    }
}

void TestTrajectory::velocitiesFromPositions() {
    QTemporaryDir dir;
    const auto path = writeText(dir, "line.sttraj",
                                R"({"format": "softtouch-trajectory", "version": 1,
                                    "samples": [[0, 0, 0, 0], [0.5, 0.1, 0, 0], [1.0, 0.2, 0.05, 0]]})");
    const auto t = io::loadTrajectory(path);
    QVERIFY2(t.ok(), t.message().c_str());
    QCOMPARE(t->device.name, scriptedDeviceInfo().name);  // no "device": the scripted defaults
    QVERIFY(t->samples[0].velocity.isApprox(Vec3(0.2, 0, 0)));
    QVERIFY(t->samples[1].velocity.isApprox(Vec3(0.2, 0.05, 0)));
    QVERIFY(t->samples[2].velocity.isApprox(Vec3(0.2, 0.1, 0)));
}

void TestTrajectory::badFiles_data() {
    QTest::addColumn<QString>("text");
    QTest::addColumn<QString>("expected");
    QTest::newRow("wrong format") << R"({"format": "softtouch-project", "version": 1, "samples": [[0,0,0,0]]})"
                                  << "/format: expected \"softtouch-trajectory\"";
    QTest::newRow("newer version") << R"({"format": "softtouch-trajectory", "version": 9, "samples": [[0,0,0,0]]})"
                                   << "/version: version 9 was written by a newer SoftTouch";
    QTest::newRow("no samples") << R"({"format": "softtouch-trajectory", "version": 1, "samples": []})"
                                << "/samples: expected a non-empty array";
    QTest::newRow("time goes back") << R"({"format": "softtouch-trajectory", "version": 1,
                                          "samples": [[0,0,0,0], [0.25,0,0,0], [0.2,0,0,0]]})"
                                    << "/samples/2/0: expected a time after 0.25 s, got 0.2";
    QTest::newRow("five numbers") << R"({"format": "softtouch-trajectory", "version": 1, "samples": [[0,0,0,0,1]]})"
                                  << "/samples/0: expected [t, x, y, z]";
    QTest::newRow("text in a sample") << R"({"format": "softtouch-trajectory", "version": 1, "samples": [[0,"a",0,0]]})"
                                      << "/samples/0/1: expected a number (position, m)";
    QTest::newRow("typo") << R"({"format": "softtouch-trajectory", "version": 1, "smaples": []})"
                          << "/smaples";
    QTest::newRow("workspace inverted")
        << R"({"format": "softtouch-trajectory", "version": 1, "device": {"workspace": {"min": [0,0,0], "max": [1,-1,1]}},
              "samples": [[0,0,0,0]]})"
        << "/device/workspace/max: expected every component";
    QTest::newRow("syntax") << "{\"format\": \n  \"softtouch-trajectory\",, }" << "line 2";
}

void TestTrajectory::badFiles() {
    QFETCH(QString, text);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    const auto path = writeText(dir, "bad.sttraj", text.toStdString());
    const auto t = io::loadTrajectory(path);
    QVERIFY(!t.ok());
    const QString message = QString::fromStdString(t.message());
    QVERIFY2(message.contains("bad.sttraj") && message.contains(expected), qPrintable(message));
}

void TestTrajectory::failedSaveKeepsTheOldFile() {
    QTemporaryDir dir;
    io::Trajectory good;
    good.samples.push_back(DeviceSample{});
    const auto path = std::filesystem::path(dir.path().toStdString()) / "keep.sttraj";
    QVERIFY(io::saveTrajectory(path, good).ok());
    io::Trajectory bad = good;
    bad.samples.push_back(DeviceSample{});
    bad.samples.back().time = 1.0;
    bad.samples.back().position.x() = std::nan("");
    const Status s = io::saveTrajectory(path, bad);
    QVERIFY(!s.ok());
    QVERIFY2(QString::fromStdString(s.message()).contains("/samples/1"), s.message().c_str());
    const auto back = io::loadTrajectory(path);
    QVERIFY(back.ok());
    QCOMPARE(back->samples.size(), std::size_t(1));
}

QTEST_GUILESS_MAIN(TestTrajectory)
#include "test_trajectory.moc"

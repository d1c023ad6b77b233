// The headers most suites read, parsed once per build into a precompiled header that every suite built
// without Qt Gui reuses (tests/CMakeLists.txt, softtouch_add_qtest). A suite still includes what it uses:
// this list only makes parsing cheaper, and a header here must not change what a suite means when the
// suite does not include it (no implementation macros, no configuration macros).
#pragma once

#include <QDir>
#include <QFile>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "core/body/lattice_body.h"
#include "core/geometry/primitives.h"
#include "core/modes/modes.h"
#include "io/documents/project_file.h"

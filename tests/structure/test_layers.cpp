// The layer check of docs/design/architecture.md ("Layers"): core/ and io/ are split into subsystem folders, declared
// bottom first in each module's CMakeLists (softtouch_add_library's LAYERS). A file includes headers of its own
// layer and of the layers before it only, every file sits in a declared layer, and core includes nothing from
// another module, Qt, OpenGL or a file-format library. The rules run on the real tree and, so that the check
// itself cannot pass vacuously, on made-up files that break each rule once.

#include <QtTest>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// Module -> its layers, bottom first.
using Layers = std::map<std::string, std::vector<std::string>>;

/// "core:base,geometry|io:files,import" (SOFTTOUCH_MODULE_LAYERS, set by the build) as a table.
Layers parseLayers(const std::string& text) {
    Layers layers;
    std::stringstream modules(text);
    std::string module;
    while (std::getline(modules, module, '|')) {
        const auto colon = module.find(':');
        if (colon == std::string::npos)
            continue;
        std::stringstream names(module.substr(colon + 1));
        std::string name;
        while (std::getline(names, name, ','))
            layers[module.substr(0, colon)].push_back(name);
    }
    return layers;
}

int layerIndex(const Layers& layers, const std::string& module, const std::string& layer) {
    const auto& list = layers.at(module);
    const auto it = std::find(list.begin(), list.end(), layer);
    return it == list.end() ? -1 : int(it - list.begin());
}

/// What is wrong with the file at `path` (relative to the source tree, "core/body/forces.h") holding `text`.
std::vector<std::string> layerProblems(const Layers& layers, const std::string& path, const std::string& text) {
    std::vector<std::string> problems;
    const auto slash = path.find('/');
    const std::string module = path.substr(0, slash);
    if (!layers.count(module))
        return problems;
    const auto second = path.find('/', slash + 1);
    const std::string layer = second == std::string::npos ? "" : path.substr(slash + 1, second - slash - 1);
    const int own = layerIndex(layers, module, layer);
    if (own < 0) {
        problems.push_back(path + ": not in a layer of " + module + "/ (its CMakeLists declares them)");
        return problems;
    }
    static const std::regex quoted(R"(#include\s*"([a-z_]+)/([^"]*)\")");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), quoted); it != std::sregex_iterator(); ++it) {
        const std::string target = (*it)[1].str(), rest = (*it)[2].str();
        const std::string include = target + "/" + rest;
        if (target == module) {
            const std::string targetLayer = rest.substr(0, rest.find('/'));
            const int index = rest.find('/') == std::string::npos ? -1 : layerIndex(layers, module, targetLayer);
            if (index < 0)
                problems.push_back(path + ": includes " + include + ", which is in no layer of " + module + "/");
            else if (index > own)
                problems.push_back(path + ": includes " + include + ", an upward include (" + layer + " is below " +
                                   targetLayer + ")");
        } else if (module == "core") {
            problems.push_back(path + ": includes " + include + "; core includes only core");
        }
    }
    if (module == "core") {
        static const std::regex system(R"(#include\s*<(Q[A-Za-z]*|GL/|EGL/|assimp/|nlohmann/|tiny_gltf|libav|OpenEXR/|Imath|SDL|meshoptimizer)[^>]*>)");
        for (auto it = std::sregex_iterator(text.begin(), text.end(), system); it != std::sregex_iterator(); ++it)
            problems.push_back(path + ": includes " + it->str().substr(it->str().find('<')) +
                               "; core stays free of Qt, OpenGL and file formats");
    }
    return problems;
}

std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

}  // namespace

class TestLayers : public QObject {
    Q_OBJECT

    const Layers m_layers = parseLayers(SOFTTOUCH_MODULE_LAYERS);

private slots:
    // The table the build declares is the one checked: core and io, several layers each.
    void bothModulesDeclareTheirLayers() {
        QVERIFY(m_layers.count("core") && m_layers.count("io"));
        QVERIFY2(m_layers.at("core").size() >= 5, SOFTTOUCH_MODULE_LAYERS);
        QVERIFY2(m_layers.at("io").size() >= 3, SOFTTOUCH_MODULE_LAYERS);
    }

    // The must-show: every source of core/ and io/ is in a declared layer and includes only down.
    void everyIncludePointsDown() {
        const std::filesystem::path root(SOFTTOUCH_SOURCE_DIR);
        std::vector<std::string> problems;
        int files = 0;
        for (const auto& [module, list] : m_layers) {
            for (const auto& entry : std::filesystem::recursive_directory_iterator(root / module)) {
                const std::string ext = entry.path().extension().string();
                if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp"))
                    continue;
                ++files;
                const std::string path = entry.path().lexically_relative(root).generic_string();
                for (std::string& p : layerProblems(m_layers, path, readFile(entry.path())))
                    problems.push_back(std::move(p));
            }
        }
        qInfo("%d files of %zu modules checked", files, m_layers.size());
        QVERIFY(files > 100);
        std::string all;
        for (const std::string& p : problems)
            all += "\n  " + p;
        QVERIFY2(problems.empty(), all.c_str());
    }

    // The check catches each kind of wrong include and misplaced file, and passes a right one.
    void aWrongIncludeIsCaught_data() {
        QTest::addColumn<QString>("path");
        QTest::addColumn<QString>("text");
        QTest::addColumn<QString>("problem");  // a part of the one problem expected; empty: none
        QTest::newRow("down") << "core/solver/simulator.h" << "#include \"core/body/forces.h\"\n" << "";
        QTest::newRow("same layer") << "io/export/pc2.cpp" << "#include \"io/export/vertex_cache.h\"\n" << "";
        QTest::newRow("io reads core") << "io/files/atomic_file.cpp" << "#include \"core/scene/scene.h\"\n" << "";
        QTest::newRow("upward") << "core/body/element_body.cpp" << "#include \"core/modes/solid_modes.h\"\n"
                                << "upward include (body is below modes)";
        QTest::newRow("upward in io") << "io/files/atomic_file.cpp" << "#include \"io/export/vertex_cache_internal.h\"\n"
                                      << "upward include (files is below export)";
        QTest::newRow("core reads io") << "core/base/types.h" << "#include \"io/files/input_file.h\"\n"
                                       << "core includes only core";
        QTest::newRow("core reads Qt") << "core/scene/scene.cpp" << "#include <QString>\n" << "free of Qt";
        QTest::newRow("flat path") << "core/scene/scene.cpp" << "#include \"core/lattice.h\"\n" << "in no layer";
        QTest::newRow("undeclared folder") << "core/extras/thing.h" << "" << "not in a layer";
        QTest::newRow("top of module") << "io/thing.cpp" << "" << "not in a layer";
    }

    void aWrongIncludeIsCaught() {
        QFETCH(QString, path);
        QFETCH(QString, text);
        QFETCH(QString, problem);
        const Layers layers = parseLayers("core:base,geometry,body,solver,modes,scene|io:files,export");
        const std::vector<std::string> found = layerProblems(layers, path.toStdString(), text.toStdString());
        if (problem.isEmpty()) {
            QVERIFY2(found.empty(), found.empty() ? "" : found.front().c_str());
            return;
        }
        QCOMPARE(int(found.size()), 1);
        QVERIFY2(QString::fromStdString(found.front()).contains(problem), found.front().c_str());
    }
};

QTEST_GUILESS_MAIN(TestLayers)
#include "test_layers.moc"

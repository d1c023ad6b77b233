#include "plugins/device_registry.h"

#include <QCoreApplication>
#include <QDir>
#include <QFileInfo>
#include <QLibrary>

namespace softtouch {

QString DeviceRegistry::defaultFolder() {
    const QByteArray env = qgetenv("SOFTTOUCH_PLUGIN_PATH");
    if (!env.isEmpty()) return QString::fromLocal8Bit(env);
    // Without a QCoreApplication (the CLI) the executable's folder comes from /proc (Linux).
    const QString bin = QCoreApplication::instance() ? QCoreApplication::applicationDirPath()
                                                     : QFileInfo(QStringLiteral("/proc/self/exe")).canonicalFilePath().section('/', 0, -2);
    return QDir(bin).filePath("../lib/softtouch/devices");
}

DeviceRegistry::DeviceRegistry(const QString& folder) {
    const QDir dir(folder);
    for (const QString& file : dir.entryList(QDir::Files, QDir::Name)) {
        const QString path = dir.filePath(file);
        if (!QLibrary::isLibrary(path)) continue;
        auto* loader = new QPluginLoader(path);
        QObject* instance = loader->instance();
        auto* plugin = instance ? qobject_cast<InputDevicePlugin*>(instance) : nullptr;
        if (!plugin) {
            m_problems << QString("%1: %2").arg(path, instance ? QString("does not implement %1").arg(SoftTouchInputDevicePlugin_iid)
                                                               : loader->errorString());
            loader->unload();
            delete loader;
            continue;
        }
        m_loaders << loader;
        m_plugins << plugin;
    }
}

DeviceRegistry::~DeviceRegistry() {
    // Plugin instances are owned by their loaders; devices they created must be gone by now.
    qDeleteAll(m_loaders);
}

InputDevicePlugin* DeviceRegistry::plugin(const QString& name) const {
    for (InputDevicePlugin* p : m_plugins)
        if (p->name() == name) return p;
    return nullptr;
}

std::unique_ptr<InputDevice> DeviceRegistry::open(const QString& name, int index, const QString& argument,
                                                  QString* chosen, QString* error) const {
    if (!name.isEmpty()) {
        InputDevicePlugin* p = plugin(name);
        if (!p) {
            if (error) *error = QString("no input-device plugin named '%1' (found: %2)").arg(name, [&] {
                QStringList names;
                for (InputDevicePlugin* q : m_plugins) names << q->name();
                return names.join(", ");
            }());
            return nullptr;
        }
        auto device = p->createDevice(index, argument);
        if (!device && error) *error = p->errorString();
        if (device && chosen) *chosen = p->name();
        return device;
    }
    for (InputDevicePlugin* p : m_plugins) {
        if (p->capabilities() & unsigned(DeviceCapability::Virtual)) continue;
        if (p->deviceCount() <= 0) continue;
        if (auto device = p->createDevice(0, {})) {
            if (chosen) *chosen = p->name();
            return device;
        }
    }
    if (InputDevicePlugin* null = plugin("null")) {
        if (auto device = null->createDevice(0, {})) {
            if (chosen) *chosen = null->name();
            return device;
        }
    }
    if (chosen) *chosen = "null";
    return std::make_unique<NullDevice>();
}

}  // namespace softtouch

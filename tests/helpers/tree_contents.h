#pragma once
// Every file under a folder, by path relative to it, with a hash of its bytes: two trees compared file by
// file (a library baked twice, locally and on the farm).

#include <QByteArray>
#include <QCryptographicHash>
#include <QDir>
#include <QDirIterator>
#include <QFile>
#include <QMap>
#include <QString>

namespace softtouch::test {

/// Every file under `root` (hidden ones and stamps included) by relative path, with the SHA-256 of its bytes.
inline QMap<QString, QByteArray> treeContents(const QString& root) {
    QMap<QString, QByteArray> files;
    QDirIterator it(root, QDir::Files | QDir::Hidden, QDirIterator::Subdirectories);
    while (it.hasNext()) {
        const QString path = it.next();
        QFile f(path);
        if (f.open(QIODevice::ReadOnly))
            files[QDir(root).relativeFilePath(path)] = QCryptographicHash::hash(f.readAll(), QCryptographicHash::Sha256);
    }
    return files;
}

}  // namespace softtouch::test

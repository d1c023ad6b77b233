#include "ui/autosave.h"

#include "io/files/atomic_file.h"

#include <QDir>
#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>
#include <QStandardPaths>

namespace softtouch::ui {

Autosave::Autosave(Document* document, QString folder, QObject* parent)
    : QObject(parent), m_document(document), m_folder(std::move(folder)) {
    if (m_folder.isEmpty())
        m_folder = QStandardPaths::writableLocation(QStandardPaths::AppDataLocation) + "/autosave";
    m_timer.setInterval(60 * 1000);
    connect(&m_timer, &QTimer::timeout, this, &Autosave::saveNow);
    m_timer.start();
    // Saving, opening or undoing back to the saved state makes the autosave stale.
    connect(document->undoStack(), &QUndoStack::cleanChanged, this, [this](bool clean) {
        if (clean)
            discard();
    });
}

QString Autosave::projectPath() const { return m_folder + "/autosave.softtouch"; }
QString Autosave::notePath() const { return m_folder + "/autosave.json"; }

bool Autosave::saveNow() {
    if (!m_document->isModified())
        return true;
    if (!QDir().mkpath(m_folder)) {
        emit failed(tr("Autosave: cannot create %1").arg(m_folder));
        return false;
    }
    if (Status s = m_document->saveCopy(projectPath()); !s) {
        emit failed(tr("Autosave failed: %1").arg(QString::fromStdString(s.message())));
        return false;
    }
    const QJsonObject note{{"original", m_document->filePath()},
                           {"savedAt", QDateTime::currentDateTimeUtc().toString(Qt::ISODate)}};
    const QByteArray bytes = QJsonDocument(note).toJson();
    if (Status s = io::writeFileAtomically(notePath().toStdString(), bytes.toStdString()); !s) {
        emit failed(tr("Autosave failed: %1").arg(QString::fromStdString(s.message())));
        return false;
    }
    return true;
}

void Autosave::discard() {
    QFile::remove(notePath());
    QFile::remove(projectPath());
}

std::optional<RecoveryCandidate> Autosave::pending() const {
    QFile note(notePath());
    if (!QFile::exists(projectPath()) || !note.open(QIODevice::ReadOnly))
        return std::nullopt;
    const QJsonObject o = QJsonDocument::fromJson(note.readAll()).object();
    RecoveryCandidate c;
    c.autosavePath = projectPath();
    c.originalPath = o.value("original").toString();
    c.savedAt = QDateTime::fromString(o.value("savedAt").toString(), Qt::ISODate);
    return c;
}

Status Autosave::recover(const RecoveryCandidate& candidate) {
    if (Status s = m_document->open(candidate.autosavePath); !s)
        return s;
    m_document->adoptPath(candidate.originalPath);
    return Status::success();
}

}  // namespace softtouch::ui

#pragma once
/// Autosave and crash recovery. While a document has unsaved changes it is written every interval
/// (default one minute) to the user's data folder, beside a small note of which file it belongs to.
/// A clean exit, a save, or opening another file removes it; after a crash or a kill it is still
/// there, and the next start offers it back.

#include "ui/document.h"

#include <QDateTime>
#include <QObject>
#include <QTimer>

#include <optional>

namespace softtouch::ui {

/// What a previous run left behind.
struct RecoveryCandidate {
    QString autosavePath;   ///< The autosaved project.
    QString originalPath;   ///< The file it was edited from (empty: never saved).
    QDateTime savedAt;      ///< When it was written.
};

/// Autosaves one document.
class Autosave : public QObject {
    Q_OBJECT
public:
    /// `folder` empty: <AppDataLocation>/autosave.
    explicit Autosave(Document* document, QString folder = {}, QObject* parent = nullptr);

    /// Milliseconds between autosaves.
    void setInterval(int milliseconds) { m_timer.setInterval(milliseconds); }
    int interval() const { return m_timer.interval(); }
    /// Where autosaves go.
    const QString& folder() const { return m_folder; }

    /// Writes the autosave now if the document has unsaved changes; returns false when writing failed.
    bool saveNow();
    /// Removes the autosave (after a save or on a clean exit).
    void discard();

    /// The autosave a previous run left, if any.
    std::optional<RecoveryCandidate> pending() const;
    /// Opens a candidate into the document: the scene as autosaved, the original path kept, and the
    /// document marked modified (it differs from the file on disk).
    Status recover(const RecoveryCandidate& candidate);

signals:
    /// An autosave failed (disk full, no permission): the message says where and why.
    void failed(const QString& message);

private:
    QString projectPath() const;
    QString notePath() const;

    Document* m_document;
    QString m_folder;
    QTimer m_timer;
};

}  // namespace softtouch::ui

#pragma once
/// The keys dock: keyframes of the lattice pose (all nodes, or the selected ones) in one of the project's
/// keyframe sets ("keys" unless another is chosen in its Key set box, or a new one made there): set from the
/// current pose, move, copy and delete keys, preview one, and make a clip of them, played as keyed or as goals
/// (goal springs pull the simulated body toward the keyed pose, so physics adds follow-through). Every change to
/// the keys is one undo step; which set is shown is a view, not an edit.

#include "ui/viewport.h"

#include <QList>
#include <QWidget>

#include <functional>

class QCheckBox;
class QDoubleSpinBox;
class QSpinBox;
class QLabel;
class QComboBox;
class QListWidget;

namespace softtouch::ui {

/// Lattice-pose keyframes of the open document.
class KeyframePanel : public QWidget {
    Q_OBJECT
public:
    /// Name of the keyframe set the panel edits in a project that has no other.
    static constexpr const char* kDefaultSet = "keys";

    KeyframePanel(Document* document, SimulationController* simulation, Viewport* viewport, QWidget* parent = nullptr);

    /// The keyframe set the panel shows and edits (it may not be in the library yet: the first key makes it).
    const std::string& keySet() const { return m_set; }
    /// Shows and edits the set `name` from now on.
    void setKeySet(const std::string& name);
    /// Adds an empty set, "keys 2" or the next free name, and shows it (one undo step).
    bool newKeySet();

    /// Keys of the current object in the shown set, in time order.
    std::vector<LatticeKey> keys() const;
    /// The time the panel's buttons and I key at, seconds: its Key frame field, in frames at the scene's rate
    /// as the ruler counts them, which follows the playhead.
    double keyTime() const;
    /// Sets the Key frame field to the frame nearest `seconds`.
    void setKeyTime(double seconds);
    /// Keys the current pose at `seconds` (the selected nodes, or all). Returns false with the reason shown.
    bool keyPose(double seconds);
    /// Moves (copy = false) or copies key `index` to `seconds`.
    bool moveKey(int index, double seconds, bool copy);
    bool deleteKey(int index);
    /// Sets how key `index` moves on to the next (one undo step).
    bool setInterpolation(int index, KeyInterpolation interpolation);
    /// The dope sheet's edits of several keys at once, each one undo step: move (or copy) them by `seconds` (a
    /// key landing where another is merges into it, as a copy does), delete them, set how each moves on.
    bool moveKeys(const QList<int>& indices, double seconds, bool copy);
    bool deleteKeys(const QList<int>& indices);
    bool setInterpolation(const QList<int>& indices, KeyInterpolation interpolation);
    /// Shows key `index`'s pose.
    void showKey(int index);
    /// Adds a clip of the keys from the first to the last key at the scene's fps; goals simulate them.
    bool makeClip(bool goals);

signals:
    /// Another keyframe set is shown.
    void keySetChanged();

private:
    /// Applies `change` to a copy of the library's keyframe set (made when missing) as one undo step.
    bool edit(const QString& text, const std::function<Status(KeyframeAnimation&)>& change);
    void refresh();
    /// The Key set box: the library's sets, and the shown one where it has no keys yet.
    void refreshSets();
    /// A new document: its "keys", else its first set, else "keys" (refresh() keeps to that rule).
    void pickSetOf();
    /// The Key frame field's time in seconds, beside it.
    void showSeconds();
    /// Shows the selected key's interpolation in the Interpolation box (not an edit).
    void showInterpolation(KeyInterpolation interpolation);

    Document* m_document;
    SimulationController* m_simulation;
    Viewport* m_viewport;
    std::string m_set = kDefaultSet;
    QComboBox* m_sets = nullptr;  ///< The Key set box.
    QListWidget* m_list = nullptr;
    QSpinBox* m_frame = nullptr;  ///< Key frame, at the scene's rate.
    QLabel* m_seconds = nullptr;  ///< That frame in seconds.
    QCheckBox* m_goals = nullptr;
    QDoubleSpinBox* m_goalStrength = nullptr;  ///< The goal springs' weight for the next clip.
    QComboBox* m_interpolation = nullptr;  ///< The selected key's interpolation.
    QLabel* m_message = nullptr;
};

}  // namespace softtouch::ui

#pragma once
/// The tool options bar: the active tool's settings, where the tool is (under the tool buttons), as
/// Blender's and Maya's tool settings bars show them. Paint: field, value, radius, strength, falloff and
/// the overlay's colour range; Drag: the mouse spring; Anchor: pinned or heavy; the other tools say what a
/// click does. Settings live in the Viewport (brush(), dragSettings(), anchor mode); this bar edits them.

#include "ui/viewport.h"

#include <QToolBar>

#include <map>
#include <optional>
#include <utility>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QStackedWidget;

namespace softtouch::ui {

class ToolOptionsBar : public QToolBar {
    Q_OBJECT
public:
    ToolOptionsBar(Document* document, Viewport* viewport, QWidget* parent = nullptr);
    /// The tool whose options are on show.
    Tool shownTool() const { return m_shown; }

private:
    QWidget* buildDragPage();
    QWidget* buildPaintPage();
    QWidget* buildAnchorPage();
    QWidget* buildPosePage();
    QWidget* hintPage(const QString& text);
    void showTool(Tool tool);
    /// The brush value's range and unit for the field and material shown, and a value offered in that
    /// unit when either changed; the colour range fields.
    void refresh();
    void showColourRange();

    Document* m_document;
    Viewport* m_viewport;
    QStackedWidget* m_pages = nullptr;
    std::map<Tool, int> m_pageOf;
    Tool m_shown = Tool::Drag;
    QComboBox* m_brushField = nullptr;
    QDoubleSpinBox* m_brushValue = nullptr;
    QDoubleSpinBox* m_brushRadius = nullptr;
    QDoubleSpinBox* m_brushStrength = nullptr;
    QComboBox* m_brushFalloff = nullptr;
    QComboBox* m_colourRange = nullptr;     ///< Painted min – max, or fixed.
    QDoubleSpinBox* m_colourLow = nullptr;  ///< The fixed range's blue end.
    QDoubleSpinBox* m_colourHigh = nullptr; ///< Its red end.
    QLabel* m_colourLowLabel = nullptr;     ///< Their labels, shown with them.
    QLabel* m_colourHighLabel = nullptr;
    QComboBox* m_anchorMode = nullptr;
    QDoubleSpinBox* m_dragStiffness = nullptr;
    QDoubleSpinBox* m_dragDamping = nullptr;
    std::optional<std::pair<PaintField, MaterialModel>> m_brushFieldShown; ///< Field and model the brush value is for.
    /// The brush value is the one offered (twice the field's mean), not one the user typed: it follows the
    /// material when an edit other than a paint stroke (Properties, undo, a preset) changes it.
    bool m_brushValueOffered = false;
    double m_offeredFromMean = 0.0;  ///< The field's mean the offered value was made from.
    bool m_offering = false;         ///< The value is being set by refresh(), not by the user.
};

}  // namespace softtouch::ui

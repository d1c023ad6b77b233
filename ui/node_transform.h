#pragma once
/// Direct posing of lattice nodes, as in Blender's lattice edit mode: G moves, R rotates and S scales the
/// selected nodes about their centre; X, Y or Z constrains the transform to that world axis (the same key
/// again frees it); a typed number gives the exact amount (metres, degrees or a factor) in place of the
/// mouse's. This is the transform's arithmetic only (no Qt): the viewport feeds it the mouse, mapped
/// through its camera, and shows positions().

#include "core/base/types.h"

#include <optional>
#include <string>
#include <vector>

namespace softtouch::ui {

/// What a transform does.
enum class TransformKind { Move, Rotate, Scale };

/// The world axis a transform is held to (Free: the view plane for a move, the view axis for a rotation,
/// every direction for a scale).
enum class TransformAxis { Free, X, Y, Z };

/// One transform of some nodes of a lattice, from where they were when it began.
class NodeTransform {
public:
    /// `start`: every node of the lattice; `nodes`: the indices transformed (out-of-range ones are dropped).
    NodeTransform(TransformKind kind, std::vector<Vec3> start, const std::vector<int>& nodes);

    TransformKind kind() const { return m_kind; }
    TransformAxis axis() const { return m_axis; }
    /// The centre the nodes turn and scale about: the mean of their start positions.
    const Vec3& pivot() const { return m_pivot; }
    const std::vector<Vec3>& start() const { return m_start; }
    const std::vector<int>& nodes() const { return m_nodes; }

    /// Holds the transform to `axis`; asking for the axis it already has frees it again.
    void toggleAxis(TransformAxis axis);
    /// Numeric entry: a digit or '.' extends the number, '-' flips its sign. Returns false for anything else.
    bool type(char c);
    /// Removes the last typed character (the sign last of all).
    void backspace();
    /// The typed amount, when a number has been typed: metres (move), degrees (rotate) or a factor (scale).
    std::optional<double> typedValue() const;
    /// What was typed, as shown ("-0.25").
    std::string typedText() const;

    /// The mouse's move: the cursor's travel on the view plane through the pivot, metres (a held axis
    /// keeps its component along that axis).
    void setMouseMove(const Vec3& delta) { m_mouseMove = delta; }
    /// The mouse's turn: the angle the cursor swept about the pivot on screen, radians, counter-clockwise
    /// as the viewer sees it; `towardViewer` is the unit direction from the scene to the camera.
    void setMouseRotate(double radians, const Vec3& towardViewer);
    /// The mouse's scale: the cursor's distance from the pivot on screen over its distance when it began.
    void setMouseScale(double factor) { m_mouseScale = factor; }

    /// Every node's position with the transform applied (the others where they started).
    std::vector<Vec3> positions() const;
    /// What the transform does now, for the status bar: "Move X 0.1 m", "Rotate Z 90°", "Scale 2".
    std::string describe() const;

private:
    /// The unit vector of the held axis (the view axis for a free rotation).
    Vec3 axisVector() const;

    TransformKind m_kind;
    TransformAxis m_axis = TransformAxis::Free;
    std::vector<Vec3> m_start;
    std::vector<int> m_nodes;
    Vec3 m_pivot = Vec3::Zero();
    std::string m_digits;   ///< Typed digits and point.
    bool m_negative = false;///< '-' typed an odd number of times.
    Vec3 m_mouseMove = Vec3::Zero();
    double m_mouseAngle = 0.0;
    Vec3 m_towardViewer = Vec3::UnitZ();
    double m_mouseScale = 1.0;
};

/// The unit vector of a world axis (Free: zero).
Vec3 axisDirection(TransformAxis axis);

}  // namespace softtouch::ui

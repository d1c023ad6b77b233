#include "ui/node_transform.h"

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace softtouch::ui {

Vec3 axisDirection(TransformAxis axis) {
    switch (axis) {
    case TransformAxis::X: return Vec3::UnitX();
    case TransformAxis::Y: return Vec3::UnitY();
    case TransformAxis::Z: return Vec3::UnitZ();
    case TransformAxis::Free: break;
    }
    return Vec3::Zero();
}

NodeTransform::NodeTransform(TransformKind kind, std::vector<Vec3> start, const std::vector<int>& nodes)
    : m_kind(kind), m_start(std::move(start)) {
    for (int n : nodes)
        if (n >= 0 && std::size_t(n) < m_start.size())
            m_nodes.push_back(n);
    for (int n : m_nodes)
        m_pivot += m_start[std::size_t(n)];
    if (!m_nodes.empty())
        m_pivot /= double(m_nodes.size());
}

void NodeTransform::toggleAxis(TransformAxis axis) { m_axis = m_axis == axis ? TransformAxis::Free : axis; }

bool NodeTransform::type(char c) {
    if (c == '-') {
        m_negative = !m_negative;
        return true;
    }
    if (c == '.' && m_digits.find('.') == std::string::npos) {
        m_digits += m_digits.empty() ? "0." : ".";
        return true;
    }
    if (c >= '0' && c <= '9' && m_digits.size() < 16) {
        m_digits += c;
        return true;
    }
    return false;
}

void NodeTransform::backspace() {
    if (!m_digits.empty())
        m_digits.pop_back();
    else
        m_negative = false;
}

std::optional<double> NodeTransform::typedValue() const {
    if (m_digits.empty())
        return std::nullopt;
    const double v = std::strtod(m_digits.c_str(), nullptr);
    return m_negative ? -v : v;
}

std::string NodeTransform::typedText() const { return (m_negative ? "-" : "") + m_digits; }

void NodeTransform::setMouseRotate(double radians, const Vec3& towardViewer) {
    m_mouseAngle = radians;
    if (towardViewer.norm() > 0.0)
        m_towardViewer = towardViewer.normalized();
}

Vec3 NodeTransform::axisVector() const {
    return m_axis == TransformAxis::Free ? m_towardViewer : axisDirection(m_axis);
}

std::vector<Vec3> NodeTransform::positions() const {
    std::vector<Vec3> out = m_start;
    const std::optional<double> typed = typedValue();
    if (m_kind == TransformKind::Move) {
        // A typed distance with no axis held goes along X, as Blender's does.
        Vec3 delta = m_mouseMove;
        if (typed)
            delta = *typed * (m_axis == TransformAxis::Free ? Vec3::UnitX() : axisDirection(m_axis));
        else if (m_axis != TransformAxis::Free)
            delta = m_mouseMove.dot(axisDirection(m_axis)) * axisDirection(m_axis);
        for (int n : m_nodes)
            out[std::size_t(n)] += delta;
    } else if (m_kind == TransformKind::Rotate) {
        // The mouse turns the nodes the way the cursor went round the pivot as the viewer sees it: about a
        // held axis that points away from the viewer, that is the opposite turn.
        const Vec3 axis = axisVector();
        double angle = typed ? *typed * std::numbers::pi / 180.0 : m_mouseAngle;
        if (!typed && axis.dot(m_towardViewer) < 0.0)
            angle = -angle;
        const Mat3 turn = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
        for (int n : m_nodes)
            out[std::size_t(n)] = m_pivot + turn * (m_start[std::size_t(n)] - m_pivot);
    } else {
        const double factor = typed ? *typed : m_mouseScale;
        for (int n : m_nodes) {
            const Vec3 offset = m_start[std::size_t(n)] - m_pivot;
            out[std::size_t(n)] = m_axis == TransformAxis::Free
                                      ? Vec3(m_pivot + factor * offset)
                                      : Vec3(m_start[std::size_t(n)] + (factor - 1.0) * offset.dot(axisVector()) * axisVector());
        }
    }
    return out;
}

std::string NodeTransform::describe() const {
    static const char* const axisNames[] = {"", " X", " Y", " Z"};
    const char* axis = axisNames[int(m_axis)];
    const std::optional<double> typed = typedValue();
    char text[160];
    if (m_kind == TransformKind::Move) {
        const Vec3 d = m_nodes.empty() ? Vec3::Zero()
                                       : Vec3(positions()[std::size_t(m_nodes.front())] - m_start[std::size_t(m_nodes.front())]);
        std::snprintf(text, sizeof text, "Move%s %.4g m (%.4g, %.4g, %.4g)", axis, d.norm(), d.x(), d.y(), d.z());
    } else if (m_kind == TransformKind::Rotate) {
        const double degrees = typed ? *typed : m_mouseAngle * 180.0 / std::numbers::pi;
        std::snprintf(text, sizeof text, "Rotate%s %.4g°", m_axis == TransformAxis::Free ? " (view)" : axis, degrees);
    } else {
        std::snprintf(text, sizeof text, "Scale%s %.4g", axis, typed ? *typed : m_mouseScale);
    }
    return std::string(text) + " · " + std::to_string(m_nodes.size()) + (m_nodes.size() == 1 ? " node" : " nodes");
}

}  // namespace softtouch::ui

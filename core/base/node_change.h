#pragma once
/// Whether a body's lattice nodes moved since the last frame. The mesh is a function of the nodes
/// alone, so an unchanged frame (a sleeping body, a clip holding its last frame) can skip its
/// deformation and keep the previous output: it costs one comparison of a few hundred nodes.

#include "core/base/types.h"

#include <algorithm>
#include <span>
#include <vector>

namespace softtouch {

/// One per object and output buffer: the buffer must hold what the last changed frame wrote.
class NodeChangeTracker {
public:
    /// True on the first call and whenever `nodes` differ, bit for bit, from the previous call's.
    bool changed(std::span<const Vec3> nodes) {
        if (m_valid && nodes.size() == m_last.size() && std::equal(nodes.begin(), nodes.end(), m_last.begin()))
            return false;
        m_last.assign(nodes.begin(), nodes.end());
        m_valid = true;
        return true;
    }
    /// Forgets the last nodes (the output buffer was overwritten by something else).
    void reset() { m_valid = false; }

private:
    std::vector<Vec3> m_last;
    bool m_valid = false;
};

}  // namespace softtouch

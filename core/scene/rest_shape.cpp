#include "core/scene/rest_shape.h"

#include "core/base/ranges.h"
#include "core/geometry/binding.h"

#include <algorithm>
#include <string>

namespace softtouch {

Status RestShapeEdit::validate() const {
    if (Status s = shape.validate(); !s)
        return s;
    if (Status s = box.validate(); !s)
        return s;
    const std::size_t count = std::size_t(shape.nodes[0]) * std::size_t(shape.nodes[1]) * std::size_t(shape.nodes[2]);
    if (nodes.size() != count)
        return Status::error("the rest shape has " + std::to_string(nodes.size()) + " nodes; its lattice has " +
                             std::to_string(count));
    for (std::size_t n = 0; n < nodes.size(); ++n)
        if (!isFinite(nodes[n]) || nodes[n].norm() > ranges::kMaxMeshSize)
            return Status::error("rest shape node " + std::to_string(n) + " is not a finite position within 1e5 m");
    return Status::success();
}

Status applyRestShapeEdit(Mesh& mesh, const RestShapeEdit& edit) {
    if (Status s = edit.validate(); !s)
        return s;
    auto lattice = Lattice::create(edit.shape, edit.box);
    if (!lattice)
        return Status::error(lattice.message());
    if (mesh.normals.size() != mesh.positions.size())
        mesh.computeNormals();
    const Binding binding = Binding::create(lattice.value(), mesh.positions, mesh.normals);
    std::vector<Vec3f> positions(mesh.positions.size()), normals(mesh.positions.size());
    binding.evaluate(edit.nodes, positions, normals, 1);
    for (const Vec3f& p : positions)
        if (!isFinite(p))
            return Status::error("the rest shape edit moves a vertex to a non-finite position");
    mesh.positions = std::move(positions);
    mesh.normals = std::move(normals);
    return Status::success();
}

OrientedBox boxHolding(const OrientedBox& box, std::span<const Vec3f> points, double padding) {
    Vec3 lo = Vec3::Zero(), hi = box.size;  // in the box's frame, from its origin corner
    for (const Vec3f& p : points) {
        const Vec3 local = box.axes.transpose() * (p.cast<double>() - box.origin);
        lo = lo.cwiseMin(local);
        hi = hi.cwiseMax(local);
    }
    const double room = padding * (hi - lo).maxCoeff();
    for (int a = 0; a < 3; ++a) {
        if (lo[a] < 0.0)
            lo[a] -= room;
        if (hi[a] > box.size[a])
            hi[a] += room;
    }
    OrientedBox grown = box;
    grown.origin = box.origin + box.axes * lo;
    grown.size = hi - lo;
    return grown;
}

Result<RestShapeChange> withRestShape(const SceneObject& object, std::span<const Vec3> pose) {
    if (object.baseAnimation)
        return Status::error("'" + object.name + "' follows its own animation: its rest shape is the animation's");
    RestShapeChange change;
    change.edit.shape = object.lattice.shape();
    change.edit.box = object.lattice.box();
    change.edit.nodes.assign(pose.begin(), pose.end());
    change.object = object;
    Mesh mesh = *object.mesh;  // a new rest mesh: the scene's copies (undo) keep the old one
    if (Status s = applyRestShapeEdit(mesh, change.edit); !s)
        return Status::error("'" + object.name + "': " + s.message());
    change.object.mesh = std::move(mesh);
    const OrientedBox box = boxHolding(object.lattice.box(), change.object.mesh->positions);
    if (!(box.origin == object.lattice.box().origin && box.size == object.lattice.box().size)) {
        auto lattice = Lattice::create(object.lattice.shape(), box);
        if (!lattice)
            return Status::error("'" + object.name + "': " + lattice.message());
        change.object.lattice = lattice.value();
    }
    return change;
}

}  // namespace softtouch

#include "render/shaders.h"

namespace softtouch::render::shaders {

const std::string& deformFunction() {
    // Q(u,v,w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w), P relative to the node centroid (uOrigin) so float
    // keeps its precision far from the world origin, exactly as core/geometry/binding.cpp does.
    //
    // Normals (core/geometry/binding.h): with J = dQ/dx_rest = [Qu Qv Qw] A, A = d(u,v,w)/dx constant for the box,
    //   n' ~ cof(J) n = cof([Qu Qv Qw]) cof(A) n,   cof([Qu Qv Qw]) m = (Qv x Qw) m_u + (Qw x Qu) m_v + (Qu x Qv) m_w,
    // so each vertex carries m = cof(A) n_rest (normalised, computed once on the CPU in double) and the
    // shader needs only the three partial derivatives Qu, Qv, Qw.
    //
    // The basis: one clamped uniform B-spline routine for both kinds (a Bezier axis of n nodes is degree
    // n-1 with no interior knots), de Boor / Cox in the triangular form of The NURBS Book A2.2/A2.3, the
    // same algorithm as core/geometry/axis_basis.cpp. GLSL 3.30 has no arrays of arrays: ndu is flattened 8x8.
    static const std::string source = R"GLSL(
uniform sampler2D uNodes;
uniform int uNodeTextureWidth;
uniform ivec3 uCount;
uniform ivec3 uDegree;
uniform vec3 uOrigin;

float clampedKnot(int i, int degree, int spans) {
    // degree zeros, uniform interior knots s/spans, degree ones
    return float(clamp(i - degree, 0, spans)) / float(spans);
}

void axisBasis(float t, int count, int p, out int first, out float N[8], out float dN[8]) {
    int spans = count - p;
    int s = clamp(int(clamp(t, -1.0, 2.0) * float(spans)), 0, spans - 1);
    int span = s + p;
    float ndu[64];
    float left[8];
    float right[8];
    for (int i = 0; i < 8; ++i) { N[i] = 0.0; dN[i] = 0.0; left[i] = 0.0; right[i] = 0.0; }
    ndu[0] = 1.0;
    for (int j = 1; j <= p; ++j) {
        left[j] = t - clampedKnot(span + 1 - j, p, spans);
        right[j] = clampedKnot(span + j, p, spans) - t;
        float saved = 0.0;
        for (int r = 0; r < j; ++r) {
            ndu[j * 8 + r] = right[r + 1] + left[j - r];
            float temp = ndu[r * 8 + j - 1] / ndu[j * 8 + r];
            ndu[r * 8 + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * 8 + j] = saved;
    }
    first = s;
    for (int r = 0; r <= p; ++r) {
        N[r] = ndu[r * 8 + p];
        float d = 0.0;
        if (r >= 1)
            d += ndu[(r - 1) * 8 + p - 1] / ndu[p * 8 + r - 1];
        if (r <= p - 1)
            d -= ndu[r * 8 + p - 1] / ndu[p * 8 + r];
        dN[r] = float(p) * d;
    }
}

void deformVertex(vec3 uvw, vec3 cofNormal, out vec3 position, out vec3 normal) {
    int fu; int fv; int fw;
    float Nu[8]; float dNu[8]; float Nv[8]; float dNv[8]; float Nw[8]; float dNw[8];
    axisBasis(uvw.x, uCount.x, uDegree.x, fu, Nu, dNu);
    axisBasis(uvw.y, uCount.y, uDegree.y, fv, Nv, dNv);
    axisBasis(uvw.z, uCount.z, uDegree.z, fw, Nw, dNw);
    vec3 X = vec3(0.0);
    vec3 Qu = vec3(0.0);
    vec3 Qv = vec3(0.0);
    vec3 Qw = vec3(0.0);
    for (int c = 0; c <= uDegree.z; ++c) {
        for (int b = 0; b <= uDegree.y; ++b) {
            float vw = Nv[b] * Nw[c];
            float dvw = dNv[b] * Nw[c];
            float vdw = Nv[b] * dNw[c];
            int row = uCount.x * ((fv + b) + uCount.y * (fw + c));
            for (int a = 0; a <= uDegree.x; ++a) {
                int node = fu + a + row;
                vec3 P = texelFetch(uNodes, ivec2(node % uNodeTextureWidth, node / uNodeTextureWidth), 0).xyz;
                X += (Nu[a] * vw) * P;
                Qu += (dNu[a] * vw) * P;
                Qv += (Nu[a] * dvw) * P;
                Qw += (Nu[a] * vdw) * P;
            }
        }
    }
    position = uOrigin + X;
    vec3 n = cross(Qv, Qw) * cofNormal.x + cross(Qw, Qu) * cofNormal.y + cross(Qu, Qv) * cofNormal.z;
    float len = length(n);
    normal = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
}
)GLSL";
    return source;
}

std::string meshVertex() {
    return "#version 330 core\n" + deformFunction() + R"GLSL(
uniform mat4 uView;
uniform mat4 uProjection;
uniform int uDirect;                        // 1: the attributes are the deformed position and normal
layout(location = 0) in vec3 aParameters;   // (u,v,w) in the lattice box
layout(location = 1) in vec3 aCofNormal;    // cof(A) n_rest, unit
out vec3 vWorldPosition;
out vec3 vWorldNormal;
out vec3 vViewPosition;
out vec3 vViewNormal;
void main() {
    if (uDirect != 0) {  // deformed on the CPU (a body on its base animation: MeshRenderer::setDeformed)
        vWorldPosition = aParameters;
        vWorldNormal = aCofNormal;
    } else {
        deformVertex(aParameters, aCofNormal, vWorldPosition, vWorldNormal);
    }
    vec4 viewPosition = uView * vec4(vWorldPosition, 1.0);
    vViewPosition = viewPosition.xyz;
    vViewNormal = mat3(uView) * vWorldNormal;  // the view is rigid
    gl_Position = uProjection * viewPosition;
}
)GLSL";
}

const std::string& meshFragment() {
    static const std::string source = R"GLSL(#version 330 core
uniform vec3 uColour;
uniform float uAlpha;
uniform int uFlat;
in vec3 vWorldPosition;
in vec3 vWorldNormal;
in vec3 vViewPosition;
in vec3 vViewNormal;
out vec4 fragColour;
void main() {
    if (uFlat != 0) {
        fragColour = vec4(uColour, uAlpha);
        return;
    }
    vec3 n = normalize(vViewNormal);
    if (!gl_FrontFacing)
        n = -n;
    vec3 toEye = normalize(-vViewPosition);
    // Two lights fixed to the camera: a warm key from the upper left, a cool fill from the right.
    vec3 key = normalize(vec3(-0.5, 0.7, 0.6));
    vec3 fill = normalize(vec3(0.8, -0.1, 0.4));
    float lambert = 0.85 * max(dot(n, key), 0.0) + 0.35 * max(dot(n, fill), 0.0);
    float rim = pow(1.0 - max(dot(n, toEye), 0.0), 3.0);
    vec3 colour = uColour * (0.18 + lambert) * vec3(1.0, 0.98, 0.95) + 0.35 * rim * vec3(0.85, 0.9, 1.0);
    fragColour = vec4(min(colour, vec3(1.0)), uAlpha);
}
)GLSL";
    return source;
}

const std::string& flatVertex() {
    static const std::string source = R"GLSL(#version 330 core
uniform mat4 uView;
uniform mat4 uProjection;
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
layout(location = 2) in vec2 aPoint;   // x: size in pixels, y: 1 hollow
out vec4 vColour;
flat out float vHollow;
void main() {
    vColour = aColour;
    vHollow = aPoint.y;
    gl_PointSize = aPoint.x;
    gl_Position = uProjection * (uView * vec4(aPosition, 1.0));
}
)GLSL";
    return source;
}

const std::string& flatFragment() {
    static const std::string source = R"GLSL(#version 330 core
uniform int uPoints;
in vec4 vColour;
flat in float vHollow;
out vec4 fragColour;
void main() {
    if (uPoints != 0) {
        float r = length(gl_PointCoord - vec2(0.5)) * 2.0;
        if (r > 1.0 || (vHollow > 0.5 && r < 0.55))
            discard;
        // a dark outline keeps nodes readable on any background
        fragColour = r > 0.78 ? vec4(0.08, 0.08, 0.1, vColour.a) : vColour;
        return;
    }
    fragColour = vColour;
}
)GLSL";
    return source;
}

const std::string& backgroundVertex() {
    static const std::string source = R"GLSL(#version 330 core
out float vHeight;
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    vHeight = corner.y;  // 0 at the bottom edge, 1 at the top
    gl_Position = vec4(corner * 2.0 - 1.0, 0.999, 1.0);
}
)GLSL";
    return source;
}

const std::string& backgroundFragment() {
    static const std::string source = R"GLSL(#version 330 core
in float vHeight;
out vec4 fragColour;
void main() {
    // mid-grey gradient, lighter at the top
    fragColour = vec4(mix(vec3(0.30, 0.31, 0.33), vec3(0.56, 0.57, 0.60), clamp(vHeight, 0.0, 1.0)), 1.0);
}
)GLSL";
    return source;
}

}  // namespace softtouch::render::shaders

#version 430 core
// SoftTouch lattice cache: reference vertex shader (GLSL 4.30). Reproduces the baked deformation
// from <base>.lattice.glb and <base>.lattice.bin alone (docs/formats.md, "Lattice cache"):
//
//   x(u,v,w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w)
//
// with N the clamped uniform B-spline basis of the header's "degrees" over "nodes" (a Bezier
// lattice is the case degree = nodes - 1: the Bernstein polynomials, up to degree 7). The knot
// vector is computed here rather than uploaded; it equals the header's "knots".
//
// Inputs, per object (= one primitive of the GLB):
//   attribute  inLatticeUvw  _LATTICE_UVW (or TEXCOORD_0.xy and TEXCOORD_1.x)
//   attribute  inNormal      NORMAL (rest normals), for the deformed normal
//   SSBO       LatticeNodes  the .bin file from byte 12 + headerBytes on, as is: every frame's nodes,
//                            3 floats each (x, y, z), frame after frame. With LATTICE_NODE_TEXTURE
//                            defined (WebGL 2, which has no storage buffers; drop the #version line for
//                            "#version 300 es"): the same nodes as texels of uLatticeNodeTexture instead.
//   uniforms   uNodeCount = objects[i].nodes, uDegree = objects[i].degrees,
//              uNodesPerFrame = nodesPerFrame, uFirstNode = objects[i].firstNode,
//              uFrameA / uFrameB / uBlend: the two frames around the playback time and the blend
//              between them (the mesh is linear in the nodes, so blending nodes blends positions),
//              uBoxAxes / uBoxSize = objects[i].box.axes (as columns) / .size, for normals.
//
// The C++ mirror of latticeBasis/latticeDeform is tests/io/test_exports.cpp (evaluateLattice),
// which checks that the files reproduce the PC2 of the same bake within 1e-6 of the diagonal; on
// the GPU the sums run in float32 (about 1e-7 of the coordinates' magnitude).

const int LATTICE_MAX_ORDER = 8;  // degree 7 + 1

#ifdef LATTICE_NODE_TEXTURE
// WebGL 2 / GLSL ES 3.00 has no storage buffers: the same floats as RGB texels of a float texture, one
// node a texel in the .bin's order, rows of the texture's width (the preview page, web/preview.js).
uniform highp sampler2D uLatticeNodeTexture;
vec3 latticeNodeAt(int i) {
    int width = textureSize(uLatticeNodeTexture, 0).x;
    return texelFetch(uLatticeNodeTexture, ivec2(i % width, i / width), 0).xyz;
}
#else
layout(std430, binding = 0) readonly buffer LatticeNodes { float latticeNodes[]; };
vec3 latticeNodeAt(int i) { return vec3(latticeNodes[3 * i], latticeNodes[3 * i + 1], latticeNodes[3 * i + 2]); }
#endif

uniform ivec3 uNodeCount;
uniform ivec3 uDegree;
uniform int uNodesPerFrame;
uniform int uFirstNode;
uniform int uFrameA;
uniform int uFrameB;
uniform float uBlend;
uniform mat3 uBoxAxes;
uniform vec3 uBoxSize;
uniform mat4 uModelViewProjection;
uniform mat3 uNormalMatrix;

layout(location = 0) in vec3 inLatticeUvw;
layout(location = 1) in vec3 inNormal;

out vec3 vNormal;

// Knot i of the clamped uniform knot vector: degree+1 zeros, (s / spans), degree+1 ones.
float latticeKnot(int i, int count, int degree) {
    return clamp(float(i - degree) / float(count - degree), 0.0, 1.0);
}

// Non-zero basis values N[0..degree] and slopes D[0..degree] at t (The NURBS Book A2.2/A2.3);
// returns the index of the first node they weigh. Parameters outside [0,1] use the end spans.
int latticeBasis(int count, int degree, float t, out float N[LATTICE_MAX_ORDER], out float D[LATTICE_MAX_ORDER]) {
    int spans = count - degree;
    int span = clamp(int(floor(t * float(spans))), 0, spans - 1) + degree;
    // The book's ndu[r][c] as ndu[r * LATTICE_MAX_ORDER + c] (GLSL ES 3.00 has no arrays of arrays):
    // upper triangle values by degree, lower knot differences.
    float ndu[LATTICE_MAX_ORDER * LATTICE_MAX_ORDER];
    float left[LATTICE_MAX_ORDER];
    float right[LATTICE_MAX_ORDER];
    ndu[0] = 1.0;
    for (int j = 1; j <= degree; ++j) {
        left[j] = t - latticeKnot(span + 1 - j, count, degree);
        right[j] = latticeKnot(span + j, count, degree) - t;
        float saved = 0.0;
        for (int r = 0; r < j; ++r) {
            ndu[j * LATTICE_MAX_ORDER + r] = right[r + 1] + left[j - r];
            float temp = ndu[r * LATTICE_MAX_ORDER + j - 1] / ndu[j * LATTICE_MAX_ORDER + r];
            ndu[r * LATTICE_MAX_ORDER + j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j * LATTICE_MAX_ORDER + j] = saved;
    }
    for (int r = 0; r < LATTICE_MAX_ORDER; ++r) {
        N[r] = 0.0;
        D[r] = 0.0;
    }
    for (int r = 0; r <= degree; ++r) {
        N[r] = ndu[r * LATTICE_MAX_ORDER + degree];
        // N'_{i,p} = p (N_{i,p-1} / (u_{i+p} - u_i) - N_{i+1,p-1} / (u_{i+p+1} - u_{i+1}))
        float d = 0.0;
        if (r >= 1)
            d += ndu[(r - 1) * LATTICE_MAX_ORDER + degree - 1] / ndu[degree * LATTICE_MAX_ORDER + r - 1];
        if (r <= degree - 1)
            d -= ndu[r * LATTICE_MAX_ORDER + degree - 1] / ndu[degree * LATTICE_MAX_ORDER + r];
        D[r] = float(degree) * d;
    }
    return span - degree;
}

vec3 latticeNode(int frame, int index) { return latticeNodeAt(frame * uNodesPerFrame + uFirstNode + index); }

// Deformed position at uvw; xu, xv, xw receive the partial derivatives dx/du, dx/dv, dx/dw.
vec3 latticeDeform(vec3 uvw, out vec3 xu, out vec3 xv, out vec3 xw) {
    float Nu[LATTICE_MAX_ORDER], Nv[LATTICE_MAX_ORDER], Nw[LATTICE_MAX_ORDER];
    float Du[LATTICE_MAX_ORDER], Dv[LATTICE_MAX_ORDER], Dw[LATTICE_MAX_ORDER];
    int fu = latticeBasis(uNodeCount.x, uDegree.x, uvw.x, Nu, Du);
    int fv = latticeBasis(uNodeCount.y, uDegree.y, uvw.y, Nv, Dv);
    int fw = latticeBasis(uNodeCount.z, uDegree.z, uvw.z, Nw, Dw);
    vec3 x = vec3(0.0);
    xu = vec3(0.0);
    xv = vec3(0.0);
    xw = vec3(0.0);
    for (int k = 0; k <= uDegree.z; ++k) {
        for (int j = 0; j <= uDegree.y; ++j) {
            for (int i = 0; i <= uDegree.x; ++i) {
                int index = (fu + i) + uNodeCount.x * ((fv + j) + uNodeCount.y * (fw + k));
                vec3 p = mix(latticeNode(uFrameA, index), latticeNode(uFrameB, index), uBlend);
                x += (Nu[i] * Nv[j] * Nw[k]) * p;
                xu += (Du[i] * Nv[j] * Nw[k]) * p;
                xv += (Nu[i] * Dv[j] * Nw[k]) * p;
                xw += (Nu[i] * Nv[j] * Dw[k]) * p;
            }
        }
    }
    return x;
}

// Normals follow the cofactor of the map's Jacobian (core/geometry/binding.h): with m = cof(A) n_rest,
// A = d(u,v,w)/dx = diag(1/size) axes^T, cof(J) n = (xv x xw) m_u + (xw x xu) m_v + (xu x xv) m_w.
// cof(A) = det(A) A^-T = diag(size) axes^T / (size.x size.y size.z); the common factor drops out
// on normalising.
vec3 latticeNormal(vec3 restNormal, vec3 xu, vec3 xv, vec3 xw) {
    vec3 m = (transpose(uBoxAxes) * restNormal) * uBoxSize;
    return normalize(cross(xv, xw) * m.x + cross(xw, xu) * m.y + cross(xu, xv) * m.z);
}

void main() {
    vec3 xu, xv, xw;
    vec3 position = latticeDeform(inLatticeUvw, xu, xv, xw);
    vNormal = uNormalMatrix * latticeNormal(inNormal, xu, xv, xw);
    gl_Position = uModelViewProjection * vec4(position, 1.0);
}

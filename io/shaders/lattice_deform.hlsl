// SoftTouch lattice cache: reference vertex shader (HLSL, shader model 5; Unity and Unreal). The
// same evaluation as lattice_deform.glsl, line for line; read that file's header for the inputs.
// Reproduces the baked deformation from <base>.lattice.glb and <base>.lattice.bin alone
// (docs/formats.md, "Lattice cache"):
//
//   x(u,v,w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w)
//
// N: clamped uniform B-spline basis of the header's "degrees" over "nodes" (Bezier = degree
// nodes - 1, up to 7). LatticeNodes is the .bin file from byte 12 + headerBytes on, as is.
// Unity: bind the nodes with ComputeBuffer (stride 4) and MaterialPropertyBlock; the glTF
// importer puts _LATTICE_UVW nowhere, so read (u, v) from UV0 and w from UV1.x (TEXCOORD_0/1).
// Unreal: the same through a Custom node or a global shader; UV channels 0 and 1.

#define LATTICE_MAX_ORDER 8  // degree 7 + 1

StructuredBuffer<float> LatticeNodes : register(t0);

cbuffer LatticeParameters : register(b0) {
    int3 uNodeCount;        // objects[i].nodes
    int uNodesPerFrame;     // nodesPerFrame
    int3 uDegree;           // objects[i].degrees
    int uFirstNode;         // objects[i].firstNode
    int uFrameA;            // frame before the playback time
    int uFrameB;            // frame after it
    float uBlend;           // (time * fps - frameA) in [0, 1]
    float uPadding;
    float3x3 uBoxAxes;      // objects[i].box.axes as columns
    float3 uBoxSize;        // objects[i].box.size
    float4x4 uModelViewProjection;
    float3x3 uNormalMatrix;
};

struct LatticeVertexIn {
    float2 uv : TEXCOORD0;      // (u, v)
    float2 wAndObject : TEXCOORD1;  // (w, object index)
    float3 normal : NORMAL;     // rest normal
};

struct LatticeVertexOut {
    float4 position : SV_Position;
    float3 normal : NORMAL;
};

// Knot i of the clamped uniform knot vector: degree+1 zeros, (s / spans), degree+1 ones.
float latticeKnot(int i, int count, int degree) {
    return clamp(float(i - degree) / float(count - degree), 0.0, 1.0);
}

// Non-zero basis values N[0..degree] and slopes D[0..degree] at t (The NURBS Book A2.2/A2.3);
// returns the index of the first node they weigh. Parameters outside [0,1] use the end spans.
int latticeBasis(int count, int degree, float t, out float N[LATTICE_MAX_ORDER], out float D[LATTICE_MAX_ORDER]) {
    int spans = count - degree;
    int span = clamp(int(floor(t * float(spans))), 0, spans - 1) + degree;
    float ndu[LATTICE_MAX_ORDER][LATTICE_MAX_ORDER];
    float left[LATTICE_MAX_ORDER];
    float right[LATTICE_MAX_ORDER];
    [unroll] for (int a = 0; a < LATTICE_MAX_ORDER; ++a) {
        left[a] = 0.0;
        right[a] = 0.0;
        [unroll] for (int b = 0; b < LATTICE_MAX_ORDER; ++b)
            ndu[a][b] = 0.0;
    }
    ndu[0][0] = 1.0;
    for (int j = 1; j <= degree; ++j) {
        left[j] = t - latticeKnot(span + 1 - j, count, degree);
        right[j] = latticeKnot(span + j, count, degree) - t;
        float saved = 0.0;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];
            float temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    [unroll] for (int z = 0; z < LATTICE_MAX_ORDER; ++z) {
        N[z] = 0.0;
        D[z] = 0.0;
    }
    for (int r = 0; r <= degree; ++r) {
        N[r] = ndu[r][degree];
        // N'_{i,p} = p (N_{i,p-1} / (u_{i+p} - u_i) - N_{i+1,p-1} / (u_{i+p+1} - u_{i+1}))
        float d = 0.0;
        if (r >= 1)
            d += ndu[r - 1][degree - 1] / ndu[degree][r - 1];
        if (r <= degree - 1)
            d -= ndu[r][degree - 1] / ndu[degree][r];
        D[r] = float(degree) * d;
    }
    return span - degree;
}

float3 latticeNode(int frame, int index) {
    int base = 3 * (frame * uNodesPerFrame + uFirstNode + index);
    return float3(LatticeNodes[base], LatticeNodes[base + 1], LatticeNodes[base + 2]);
}

// Deformed position at uvw; xu, xv, xw receive the partial derivatives dx/du, dx/dv, dx/dw.
float3 latticeDeform(float3 uvw, out float3 xu, out float3 xv, out float3 xw) {
    float Nu[LATTICE_MAX_ORDER], Nv[LATTICE_MAX_ORDER], Nw[LATTICE_MAX_ORDER];
    float Du[LATTICE_MAX_ORDER], Dv[LATTICE_MAX_ORDER], Dw[LATTICE_MAX_ORDER];
    int fu = latticeBasis(uNodeCount.x, uDegree.x, uvw.x, Nu, Du);
    int fv = latticeBasis(uNodeCount.y, uDegree.y, uvw.y, Nv, Dv);
    int fw = latticeBasis(uNodeCount.z, uDegree.z, uvw.z, Nw, Dw);
    float3 x = 0.0;
    xu = 0.0;
    xv = 0.0;
    xw = 0.0;
    for (int k = 0; k <= uDegree.z; ++k) {
        for (int j = 0; j <= uDegree.y; ++j) {
            for (int i = 0; i <= uDegree.x; ++i) {
                int index = (fu + i) + uNodeCount.x * ((fv + j) + uNodeCount.y * (fw + k));
                float3 p = lerp(latticeNode(uFrameA, index), latticeNode(uFrameB, index), uBlend);
                x += (Nu[i] * Nv[j] * Nw[k]) * p;
                xu += (Du[i] * Nv[j] * Nw[k]) * p;
                xv += (Nu[i] * Dv[j] * Nw[k]) * p;
                xw += (Nu[i] * Nv[j] * Dw[k]) * p;
            }
        }
    }
    return x;
}

// cof(J) n = (xv x xw) m_u + (xw x xu) m_v + (xu x xv) m_w with m = cof(A) n_rest, which is
// (axes^T n_rest) * size up to a factor (see lattice_deform.glsl and core/geometry/binding.h).
float3 latticeNormal(float3 restNormal, float3 xu, float3 xv, float3 xw) {
    float3 m = mul(transpose(uBoxAxes), restNormal) * uBoxSize;
    return normalize(cross(xv, xw) * m.x + cross(xw, xu) * m.y + cross(xu, xv) * m.z);
}

LatticeVertexOut main(LatticeVertexIn input) {
    float3 uvw = float3(input.uv, input.wAndObject.x);
    float3 xu, xv, xw;
    float3 position = latticeDeform(uvw, xu, xv, xw);
    LatticeVertexOut output;
    output.normal = mul(uNormalMatrix, latticeNormal(input.normal, xu, xv, xw));
    output.position = mul(uModelViewProjection, float4(position, 1.0));
    return output;
}

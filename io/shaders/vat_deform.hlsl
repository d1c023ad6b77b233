// SoftTouch vertex animation textures: reference vertex shader (HLSL, shader model 5; Unity and Unreal).
// The same evaluation as vat_deform.glsl, line for line; read that file's header for the inputs.
// Unity's and Unreal's glTF importers flip v (bottom-left origin): sample with 1 - v and frame steps of
// -frameRowStep, or import the EXR flipped; check one vertex at a late frame (docs/formats.md).

Texture2D<float4> uOffsets : register(t0);
Texture2D<float4> uNormals : register(t1);
SamplerState uNearest : register(s0);  // point filtering, clamp, no mipmaps

cbuffer VatParameters : register(b0) {
    float uFrameRowStep;    // the JSON's frameRowStep
    int uFrameA;            // frame before the playback time
    int uFrameB;            // frame after it
    float uBlend;           // (time * fps - frameA) in [0, 1]
    float4x4 uModelViewProjection;
    float3x3 uNormalMatrix;
};

struct VatVertexIn {
    float3 position : POSITION;  // rest POSITION
    float2 lookup : TEXCOORD1;   // frame 0's texel centre
};

struct VatVertexOut {
    float4 position : SV_Position;
    float3 normal : NORMAL;
};

float2 vatLookup(float2 frame0, int frame) {
    return frame0 + float2(0.0, float(frame) * uFrameRowStep);
}

VatVertexOut main(VatVertexIn input) {
    float2 a = vatLookup(input.lookup, uFrameA);
    float2 b = vatLookup(input.lookup, uFrameB);
    float3 offset = lerp(uOffsets.SampleLevel(uNearest, a, 0).rgb, uOffsets.SampleLevel(uNearest, b, 0).rgb, uBlend);
    float3 normal = normalize(lerp(uNormals.SampleLevel(uNearest, a, 0).rgb, uNormals.SampleLevel(uNearest, b, 0).rgb, uBlend));
    VatVertexOut output;
    output.normal = mul(uNormalMatrix, normal);
    output.position = mul(uModelViewProjection, float4(input.position + offset, 1.0));
    return output;
}

#version 430 core
// SoftTouch vertex animation textures: reference vertex shader (GLSL 4.30). Plays a VAT export
// (docs/formats.md, "Vertex animation textures") from its files alone:
//
//   position = rest POSITION + offset texel,  normal = normal texel
//
// Inputs:
//   attribute  inPosition  POSITION of <base>.vat-mesh.glb (the rest pose)
//   attribute  inLookup    TEXCOORD_1: frame 0's texel centre, v measured from the top (glTF)
//   sampler    uOffsets    <base>.vat-position.exr, RGB half float; upload scanline 0 as the texture's
//                          first row (t = 0), so the glTF v is the GL t as is; NEAREST, no mipmaps
//   sampler    uNormals    <base>.vat-normal.exr, the same way
//   uniforms   uFrameRowStep = the JSON's frameRowStep; uFrameA / uFrameB / uBlend: the two frames
//              around the playback time and the blend between them (frame = time x fps)
//
// tests/render/test_shipped_shaders.cpp runs this shader on an export and checks it against the PC2 of
// the same bake (within half-float precision).

uniform sampler2D uOffsets;
uniform sampler2D uNormals;
uniform float uFrameRowStep;
uniform int uFrameA;
uniform int uFrameB;
uniform float uBlend;
uniform mat4 uModelViewProjection;
uniform mat3 uNormalMatrix;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec2 inLookup;

out vec3 vNormal;

// The texel centre of this vertex at `frame`: frames are stacked rowsPerFrame rows apart.
vec2 vatLookup(vec2 frame0, int frame) {
    return frame0 + vec2(0.0, float(frame) * uFrameRowStep);
}

void main() {
    vec2 a = vatLookup(inLookup, uFrameA);
    vec2 b = vatLookup(inLookup, uFrameB);
    vec3 offset = mix(texture(uOffsets, a).rgb, texture(uOffsets, b).rgb, uBlend);
    vec3 normal = normalize(mix(texture(uNormals, a).rgb, texture(uNormals, b).rgb, uBlend));
    vNormal = uNormalMatrix * normal;
    gl_Position = uModelViewProjection * vec4(inPosition + offset, 1.0);
}

#pragma once
/// GLSL 3.30 sources of the renderer.

#include <string>

namespace softtouch::render::shaders {

/// The deformation as a GLSL function, self-contained: `void deformVertex(vec3 uvw, vec3 cofNormal,
/// out vec3 position, out vec3 normal)` with uniforms uNodes (RGBA32F 2D texture, node i at texel
/// (i % uNodeTextureWidth, i / uNodeTextureWidth), xyz relative to uOrigin), uNodeTextureWidth, uCount
/// (nodes per axis), uDegree (per axis) and uOrigin (node centroid). Also the reference shader for the
/// lattice cache export.
const std::string& deformFunction();
/// Mesh vertex shader: deformFunction() + view/projection; outputs vWorldPosition and vWorldNormal
/// (captured by transform feedback in readDeformed()).
std::string meshVertex();
/// Mesh fragment shader: two-light Lambert + rim; uAlpha for X-ray; uFlat for wire colour.
const std::string& meshFragment();
/// Flat-coloured points (round nodes, hollow when asked), lines and quads.
const std::string& flatVertex();
/// Fragment shader of flatVertex().
const std::string& flatFragment();
/// Full-screen vertical gradient (no attributes: gl_VertexID makes one triangle).
const std::string& backgroundVertex();
/// Fragment shader of backgroundVertex().
const std::string& backgroundFragment();

}  // namespace softtouch::render::shaders

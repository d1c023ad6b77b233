#pragma once
// A COLLADA file written by hand for the animated import's test (assimp's own COLLADA export of an
// animation is not read back by its importer): a box in centimetres whose node's translation is keyed.

#include <fstream>
#include <string>

namespace softtouch::test {

/// Writes the box: `positions` its 8 corners (24 numbers, centimetres), `keys` 5 times (seconds) and
/// `values` 5 translations (15 numbers, centimetres), as space-separated text.
inline void writeKeyedColladaBox(const std::string& path, const std::string& positions, const std::string& keys,
                                 const std::string& values) {
    std::ofstream(path) << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="box-mesh" name="box"><mesh>
    <source id="box-positions"><float_array id="box-positions-array" count="24">)" + positions + R"(</float_array>
      <technique_common><accessor source="#box-positions-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="box-vertices"><input semantic="POSITION" source="#box-positions"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#box-vertices" offset="0"/>
      <p>0 2 1 1 2 3 4 5 6 5 7 6 0 1 4 1 5 4 2 6 3 3 6 7 0 4 2 2 4 6 1 3 5 3 7 5</p></triangles>
  </mesh></geometry></library_geometries>
  <library_animations><animation id="move">
    <source id="move-input"><float_array id="move-input-array" count="5">)" + keys + R"(</float_array>
      <technique_common><accessor source="#move-input-array" count="5" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
    <source id="move-output"><float_array id="move-output-array" count="15">)" + values + R"(</float_array>
      <technique_common><accessor source="#move-output-array" count="5" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source>
    <source id="move-interpolation"><Name_array id="move-interpolation-array" count="5">LINEAR LINEAR LINEAR LINEAR LINEAR</Name_array>
      <technique_common><accessor source="#move-interpolation-array" count="5" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
    <sampler id="move-sampler"><input semantic="INPUT" source="#move-input"/><input semantic="OUTPUT" source="#move-output"/>
      <input semantic="INTERPOLATION" source="#move-interpolation"/></sampler>
    <channel source="#move-sampler" target="box/location"/>
  </animation></library_animations>
  <library_visual_scenes><visual_scene id="scene" name="scene">
    <node id="box" name="box" type="NODE"><translate sid="location">0 0 0</translate>
      <instance_geometry url="#box-mesh" name="box"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

}  // namespace softtouch::test

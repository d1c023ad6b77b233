# Imports a GLB with Blender's own glTF importer and plays its first animation as Blender does (the evaluated
# mesh: armature, shape keys, object motion), frame by frame at k / FPS, against the PC2 of the same bake.
# Prints one JSON object: frames, vertices, and the RMS and worst vertex distance over every frame, as
# fractions of the rest mesh's bounding-box diagonal (from the OBJ the bake wrote beside the PC2). A file
# Blender cannot import prints {"imported": false, "error": "..."} and exits 0.
# Usage: blender -b --factory-startup --python play_in_blender.py -- FILE.glb CACHE.pc2 REST.obj FPS
#
# Shading 'SMOOTH': Blender 3.4's importer, with its default ('NORMALS'), calls numpy's np.bool, which numpy
# 1.24 (Debian 12's) no longer has, and fails on every file (docs/formats.md says what users choose instead).
# Vertex order is compared as is: a player that reorders vertices could not take the PC2 either.
import json
import math
import struct
import sys

import bpy

glb, pc2, rest_obj, fps = sys.argv[sys.argv.index('--') + 1:][:4]
fps = float(fps)


def read_pc2(path):
    with open(path, 'rb') as f:
        data = f.read()
    if data[:12] != b'POINTCACHE2\0':
        raise SystemExit(f'{path}: not a PC2 file')
    _, points, _, _, samples = struct.unpack_from('<iiffi', data, 12)
    values = struct.unpack_from(f'<{3 * points * samples}f', data, 32)
    return [values[3 * points * s:3 * points * (s + 1)] for s in range(samples)], points


def diagonal(path):
    low, high = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith('v '):
                p = [float(x) for x in line.split()[1:4]]
                low = [min(a, b) for a, b in zip(low, p)]
                high = [max(a, b) for a, b in zip(high, p)]
    return math.dist(low, high)


frames, points = read_pc2(pc2)
scale = diagonal(rest_obj)
bpy.ops.wm.read_factory_settings(use_empty=True)
try:
    bpy.ops.import_scene.gltf(filepath=glb, import_shading='SMOOTH')
except RuntimeError as e:
    print(json.dumps({'imported': False, 'error': str(e).strip().splitlines()[-1]}))
    sys.exit(0)
meshes = [o for o in bpy.context.scene.objects if o.type == 'MESH']
scene = bpy.context.scene
sum_squares, worst, count = 0.0, 0.0, 0
for k, expected in enumerate(frames):
    at = k * scene.render.fps / scene.render.fps_base / fps
    scene.frame_set(int(math.floor(at)), subframe=at - math.floor(at))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    played = []
    for o in meshes:
        evaluated = o.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        world = evaluated.matrix_world
        for v in mesh.vertices:
            p = world @ v.co
            played.append((p.x, p.z, -p.y))  # Blender's Z-up back to glTF's Y-up
        evaluated.to_mesh_clear()
    if len(played) != points:
        print(json.dumps({'imported': True, 'error': f'{len(played)} vertices played, {points} in the cache'}))
        sys.exit(0)
    for i, p in enumerate(played):
        d = math.dist(p, expected[3 * i:3 * i + 3])
        sum_squares += d * d
        worst = max(worst, d)
        count += 1
print(json.dumps({'imported': True, 'frames': len(frames), 'vertices': points,
                  'rms': math.sqrt(sum_squares / count) / scale, 'worst': worst / scale}))

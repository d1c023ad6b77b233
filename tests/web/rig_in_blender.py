# Imports a source GLB and a skin exported onto its rig with Blender's own glTF importer, and compares the source
# joints as Blender shows them: every joint of the source must be in the export under the same name and parent,
# with the same rest (bind) matrix, and its world matrix at clip frame k (time k / FPS of the export) must equal
# the source's at take time TAKE_START + ((CLIP_START + k / FPS) mod TAKE_LENGTH), the time the bake played.
# Translations are compared as fractions of the diagonal of the rest mesh (the OBJ the bake wrote).
# Prints one JSON object: joints, helpers (the export's extra bones, with their parents), frames, and the largest
# difference of any matrix entry (translations over the diagonal) in the rest and in the animation.
# Usage: blender -b --factory-startup --python rig_in_blender.py -- SOURCE.glb EXPORT.glb REST.obj FPS FRAMES
#        CLIP_START TAKE_START TAKE_LENGTH
#
# Both files are imported with the 'BLENDER' bone heuristic: the default guesses each bone's direction from its
# children, and the export's helper bones are children the source does not have.
import json
import math
import sys

import bpy

source, export, rest_obj, fps, frames, clip_start, take_start, take_length = sys.argv[sys.argv.index('--') + 1:][:8]
fps, frames = float(fps), int(frames)
clip_start, take_start, take_length = float(clip_start), float(take_start), float(take_length)


def diagonal(path):
    low, high = [math.inf] * 3, [-math.inf] * 3
    with open(path) as f:
        for line in f:
            if line.startswith('v '):
                p = [float(x) for x in line.split()[1:4]]
                low = [min(a, b) for a, b in zip(low, p)]
                high = [max(a, b) for a, b in zip(high, p)]
    return math.dist(low, high)


def armature_at(path, times):
    """Every bone's parent, rest matrix and world matrix at each time (seconds into the file's animation)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path, import_shading='SMOOTH', bone_heuristic='BLENDER')
    scene = bpy.context.scene
    armature = [o for o in scene.objects if o.type == 'ARMATURE'][0]
    bones = {b.name: {'parent': b.parent.name if b.parent else None,
                      'rest': armature.matrix_world @ b.matrix_local, 'world': []} for b in armature.data.bones}
    for t in times:
        at = t * scene.render.fps / scene.render.fps_base
        scene.frame_set(int(math.floor(at)), subframe=at - math.floor(at))
        for b in armature.pose.bones:
            bones[b.name]['world'].append((armature.matrix_world @ b.matrix).copy())
    for b in bones.values():
        b['rest'] = b['rest'].copy()
    return bones


def difference(a, b, scale):
    return max(abs(a[r][c] - b[r][c]) / (scale if c == 3 else 1.0) for r in range(3) for c in range(4))


scale = diagonal(rest_obj)
clip_times = [k / fps for k in range(frames)]
take_times = [take_start + math.fmod(clip_start + t, take_length) for t in clip_times]
theirs = armature_at(source, take_times)
ours = armature_at(export, clip_times)
missing = [name for name in theirs if name not in ours]
moved = [name for name in theirs if name in ours and ours[name]['parent'] != theirs[name]['parent']]
rest = max((difference(ours[n]['rest'], theirs[n]['rest'], scale) for n in theirs if n in ours), default=math.inf)
animation = max((difference(ours[n]['world'][k], theirs[n]['world'][k], scale)
                 for n in theirs if n in ours for k in range(frames)), default=math.inf)
helpers = {n: b['parent'] for n, b in ours.items() if n not in theirs}
print(json.dumps({'joints': len(theirs), 'missing': missing, 'reparented': moved, 'helpers': helpers,
                  'frames': frames, 'rest': rest, 'animation': animation}))

# The Blender add-on (blender/addons/softtouch_wobble) as a user runs it, headless: one check per run, its findings
# printed as one JSON line for tests/blender/test_blender_addon.cpp to judge.
# Usage: BLENDER_USER_SCRIPTS=blender (the checkout's, with addons/softtouch_wobble) SOFTTOUCH_CLI=softtouch-cli
#        blender -b --factory-startup --python addon_checks.py -- CHECK WORKDIR
# CHECK: register, bake, pinned, reload, cycle, shapekeys, open, bad-preset, cancel.
import addon_utils
import hashlib
import json
import os
import subprocess
import sys
import time

import bpy
import numpy as np

check, work = sys.argv[sys.argv.index('--') + 1:][:2]
GUPPY = os.path.join(os.path.dirname(os.path.abspath(__file__)), '../../presets/meshes/guppy-rigged.glb')
FRAMES = (0, 5, 11, 17, 23)  # five frames of the one-second swim at 24 fps


def report(**found):
    print(json.dumps(found))
    sys.exit(0)


def enable():
    return addon_utils.enable('softtouch_wobble', default_set=True, handle_error=lambda e: report(error=str(e)))


def guppy_scene():
    """The rigged guppy as Blender imports it, its swim (frames 0-24, 24 = 0) as the scene's range 0-23."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable()
    # 'SMOOTH': Blender 3.4's importer with its default shading calls numpy's removed np.bool.
    bpy.ops.import_scene.gltf(filepath=GUPPY, import_shading='SMOOTH')
    obj = next(o for o in bpy.context.scene.objects if o.type == 'MESH')
    bpy.context.view_layer.objects.active = obj
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 0, 23
    obj.softtouch.folder = os.path.join(work, 'softtouch') + '/'
    obj.softtouch.loop = True
    return obj, scene


def keys():
    """Every key of every action: where it is and how it bends."""
    return [[a.name, fc.data_path, fc.array_index,
             [[*k.co, *k.handle_left, *k.handle_right, k.interpolation] for k in fc.keyframe_points]]
            for a in bpy.data.actions for fc in a.fcurves]


def evaluated(obj, scene, frame, wobble=True):
    """World positions of the evaluated mesh at `frame`, with or without the add-on's modifier."""
    modifier = obj.modifiers.get('SoftTouch wobble')
    if modifier is not None:
        modifier.show_viewport = wobble
    scene.frame_set(frame)
    e = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = e.to_mesh()
    co = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get('co', co)
    e.to_mesh_clear()
    m = np.array(e.matrix_world)
    if modifier is not None:
        modifier.show_viewport = True
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def ramp_group(obj, name, weight):
    group = obj.vertex_groups.new(name=name)
    for v in obj.data.vertices:
        group.add([v.index], weight(v.co), 'REPLACE')
    obj.softtouch.goal_group = name


def files(folder):
    return sorted(os.path.relpath(os.path.join(d, f), folder) for d, _, fs in os.walk(folder) for f in fs + _)


def bake():
    try:
        bpy.ops.softtouch.bake_wobble()
        return []
    except RuntimeError as e:
        return [line for line in str(e).splitlines() if line.startswith('Error:')]


def read_pc2(path):
    with open(path, 'rb') as f:
        data = f.read()
    points, samples = np.frombuffer(data, '<i4', 1, 16)[0], np.frombuffer(data, '<i4', 1, 28)[0]
    return np.frombuffer(data, '<f4', samples * points * 3, 32).reshape(samples, points, 3).astype(np.float64)


def read_obj(path):
    with open(path) as f:
        return np.array([[float(x) for x in line.split()[1:4]] for line in f if line.startswith('v ')])


if check == 'register':
    module = enable()
    found = {'module': module.__name__, 'version': list(module.bl_info['version']),
             'blender': list(module.bl_info['blender']), 'panel': hasattr(bpy.types, 'VIEW3D_PT_softtouch'),
             'operators': [op for op in ('bake_wobble', 'reload', 'open_in_softtouch') if hasattr(bpy.ops.softtouch, op)]}
    # Settings live on the object: a saved .blend reopens with them.
    obj, scene = guppy_scene()
    s = obj.softtouch
    s.preset, s.nodes, s.integrator, s.steps_per_second, s.goal_group, s.loop = 'jelly', (6, 4, 3), 'implicit-euler', 480, 'tail', True
    path = os.path.join(work, 'saved.blend')
    bpy.ops.wm.save_as_mainfile(filepath=path)
    s.preset, s.nodes = 'rubber', (4, 4, 4)  # changed after the save: the reopened file has the saved values
    bpy.ops.wm.open_mainfile(filepath=path)
    s = next(o for o in bpy.context.scene.objects if o.type == 'MESH').softtouch
    found['reopened'] = [s.preset, list(s.nodes), s.integrator, s.steps_per_second, s.goal_group, s.loop]
    report(**found)

def against_cli(obj, scene, project, armature_only, wobbled, d):
    """softtouch-cli's own bake of `project`, matched to Blender's vertices by place at the first frame (nearest,
    brute force), in glTF's axes (x, z, -y): how far the modifier's mesh is from it, and how well the match held."""
    reference = os.path.join(work, 'reference.pc2')
    subprocess.run([os.environ['SOFTTOUCH_CLI'], 'bake', project, '--clip', 'wobble', '--out', reference, '--quiet'],
                   check=True)
    frames, st_rest = read_pc2(reference), read_obj(os.path.splitext(reference)[0] + '.obj')
    to_gltf = lambda p: np.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1)
    first = to_gltf(armature_only[0])
    order = np.array([int(np.argmin(((st_rest - p) ** 2).sum(axis=1))) for p in first])
    return {'matchedBy': float(np.linalg.norm(st_rest[order] - first, axis=1).max()) / d,
            'worst': max(float(np.linalg.norm(to_gltf(w) - frames[f][order], axis=1).max())
                         for f, w in zip(FRAMES, wobbled)) / d,
            'cacheFrames': int(frames.shape[0])}


if check in ('bake', 'pinned', 'reload'):
    obj, scene = guppy_scene()
    if check == 'bake':
        # Placed in the scene, turned, scaled and moving: the cache is in the object's own space, frame by frame,
        # the bake in the world's. The rig's move is keyed on its own action, beside the bones' keys.
        rig = obj.parent
        rig.rotation_mode = 'XYZ'
        rig.rotation_euler, rig.scale = (0.2, 0.0, 0.7), (1.5, 1.5, 1.5)
        for frame, place in ((0, (0.4, -0.3, 0.2)), (24, (0.7, -0.1, 0.3))):
            rig.location = place
            rig.keyframe_insert('location', frame=frame)
        obj.softtouch.loop = False  # a move across the scene is no cycle: baked once, from rest
    rest = np.array([v.co for v in obj.data.vertices])
    low, high = rest[:, 0].min(), rest[:, 0].max()  # the guppy lies along x, its head at +x
    if check == 'pinned':
        ramp_group(obj, 'goal', lambda co: 1.0)
    else:
        ramp_group(obj, 'goal', lambda co: float(np.clip((co.x - low) / (high - low), 0.0, 1.0)))
    before = keys()
    errors = bake()
    if errors:
        report(errors=errors)
    project = os.path.join(work, 'softtouch', obj.name + '.softtouch')
    if check == 'reload':
        # What the editor's Save would leave: node weights instead of the points, and the user's edits (a finer
        # lattice, another material). Reload bakes that, without writing the project again.
        with open(project) as f:
            edited = json.load(f)
        o = edited['objects'][0]
        del o['goalWeightPoints']
        o['material'] = {'preset': o['material']['preset'].replace('fish-body', 'jelly'), 'goalWeight': 0.4}
        o['lattice']['nodes'] = [5, 4, 4]
        with open(project, 'w') as f:
            json.dump(edited, f)
        try:
            bpy.ops.softtouch.reload()
        except RuntimeError as e:
            report(errors=str(e).splitlines())
        with open(project) as f:
            kept = json.load(f) == edited
    modifiers = [[m.name, m.type] for m in obj.modifiers]
    found = {'modifiers': modifiers, 'keysUnchanged': keys() == before, 'frames': list(FRAMES)}
    if check == 'reload':
        found['projectKept'] = kept
    armature_only = [evaluated(obj, scene, f, wobble=False) for f in FRAMES]
    wobbled = [evaluated(obj, scene, f) for f in FRAMES]
    d = diagonal(armature_only[0])
    found['diagonal'] = d
    found['wobble'] = max(float(np.linalg.norm(w - a, axis=1).max()) for w, a in zip(wobbled, armature_only)) / d
    if check == 'pinned':
        found['worst'] = found['wobble']
    else:
        found.update(against_cli(obj, scene, project, armature_only, wobbled, d))
    report(**found)

if check == 'cycle':
    # A loop plays as a cycle on every frame, before and after the range it was baked over, as the rig's cyclic
    # action does; it needs no trusted scripts. A one-shot bake after it plays the range once again.
    obj, scene = guppy_scene()
    action = obj.parent.animation_data.action
    for fc in action.fcurves:  # the swim repeats, as an animator sets up a cycle
        fc.modifiers.new('CYCLES')
    action.update_tag()
    rest = np.array([v.co for v in obj.data.vertices])
    low, high = rest[:, 0].min(), rest[:, 0].max()
    ramp_group(obj, 'goal', lambda co: float(np.clip((co.x - low) / (high - low), 0.0, 1.0)))
    errors = bake()
    if errors:
        report(errors=errors)
    inside = {k: evaluated(obj, scene, k) for k in (0, 5, 17, 23)}
    d = diagonal(inside[0])
    found = {'autoExec': bpy.context.preferences.filepaths.use_scripts_auto_execute,
             'drivers': [[fc.data_path, fc.driver.is_simple_expression, fc.driver.is_valid]
                         for fc in (obj.animation_data.drivers if obj.animation_data else [])],
             'worst': max(float(np.linalg.norm(evaluated(obj, scene, k + shift) - points, axis=1).max())
                          for k, points in inside.items() for shift in (-24, 24, 48)) / d,
             'wobbleAfter': max(float(np.linalg.norm(evaluated(obj, scene, k + 24) -
                                                     evaluated(obj, scene, k + 24, wobble=False), axis=1).max())
                                for k in inside) / d}
    obj.softtouch.loop = False
    errors = bake()
    if errors:
        report(errors=errors)
    found['driversAfterOneShot'] = len(obj.animation_data.drivers) if obj.animation_data else 0
    found['playModeAfterOneShot'] = obj.modifiers['SoftTouch wobble'].play_mode
    report(**found)

if check == 'shapekeys':
    # Shape keys alone, no armature: a long body bent by one key, keyed 0, 1, 0 over the second (frame 24 = 0).
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)
    obj = bpy.context.object
    obj.scale = (0.6, 0.2, 0.25)
    bpy.ops.object.transform_apply(scale=True)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 0, 23
    obj.shape_key_add(name='Basis')
    bend = obj.shape_key_add(name='Bend', from_mix=False)
    for point, v in zip(bend.data, obj.data.vertices):
        point.co = (v.co.x, v.co.y + 0.5 * v.co.x * v.co.x, v.co.z)
    for frame, value in ((0, 0.0), (12, 1.0), (24, 0.0)):
        bend.value = value
        bend.keyframe_insert('value', frame=frame)
    obj.softtouch.folder = os.path.join(work, 'softtouch') + '/'
    obj.softtouch.loop = True
    ramp_group(obj, 'goal', lambda co: float(np.clip((co.x + 0.6) / 1.2, 0.0, 1.0)))
    before = keys()
    errors = bake()
    if errors:
        report(errors=errors)
    project = os.path.join(work, 'softtouch', obj.name + '.softtouch')
    shaped = [evaluated(obj, scene, f, wobble=False) for f in FRAMES]
    wobbled = [evaluated(obj, scene, f) for f in FRAMES]
    d = diagonal(shaped[0])
    found = {'modifiers': [[m.name, m.type] for m in obj.modifiers], 'keysUnchanged': keys() == before,
             'bend': max(float(np.linalg.norm(s - shaped[0], axis=1).max()) for s in shaped) / d,
             'wobble': max(float(np.linalg.norm(w - a, axis=1).max()) for w, a in zip(wobbled, shaped)) / d}
    found.update(against_cli(obj, scene, project, shaped, wobbled, d))
    report(**found)

if check == 'bad-preset':
    # A good bake first: the failed one must leave its cache and modifier as they were.
    obj, scene = guppy_scene()
    errors = bake()
    folder = os.path.join(work, 'softtouch')
    cache = os.path.join(folder, obj.name + '.pc2')
    digest = lambda: hashlib.sha256(open(cache, 'rb').read()).hexdigest()
    modifier = lambda: [[m.name, m.type, getattr(m, 'filepath', ''), getattr(m, 'frame_start', 0)] for m in obj.modifiers]
    good = {'files': files(folder), 'cache': digest(), 'modifiers': modifier(), 'keys': keys()}
    presets = os.path.join(os.environ['XDG_DATA_HOME'], 'SoftTouch', 'SoftTouch', 'presets')
    os.makedirs(presets, exist_ok=True)
    with open(os.path.join(presets, 'broken.stpreset'), 'w') as f:
        f.write('{"format": "softtouch-preset", "version": 2, "name": "Broken", "material": {"stiffness": -5}}')
    obj.softtouch.preset = 'broken'
    found = {'firstErrors': errors, 'errors': bake()}
    after = {'files': files(folder), 'cache': digest(), 'modifiers': modifier(), 'keys': keys()}
    found['unchanged'] = after == good
    found['files'] = after['files']
    report(**found)

if check == 'open':
    # The editor here is a stand-in that writes down what it was started with (SOFTTOUCH_CLI's folder holds it).
    obj, scene = guppy_scene()
    ramp_group(obj, 'goal', lambda co: 0.5)
    bpy.ops.softtouch.open_in_softtouch()
    started = os.path.join(work, 'editor-started-with')
    waited = time.time()
    while not os.path.exists(started) and time.time() - waited < 30:
        time.sleep(0.05)
    folder = os.path.join(work, 'softtouch')
    project = os.path.join(folder, obj.name + '.softtouch')
    validated = subprocess.run([os.environ['SOFTTOUCH_CLI'], 'validate', project], capture_output=True, text=True)
    report(startedWith=open(started).read().strip() if os.path.exists(started) else None, project=project,
           files=files(folder), validated=validated.returncode == 0, validation=validated.stdout + validated.stderr,
           modifiers=[m.name for m in obj.modifiers])

if check == 'cancel':
    from softtouch_wobble import bake as addon_bake
    obj, scene = guppy_scene()
    obj.softtouch.steps_per_second = 100000  # some twenty seconds: cancelled a second in, while it runs
    job = addon_bake.BakeJob(bpy.context, obj)
    job.start()
    staged = sorted(os.listdir(job.staging))
    time.sleep(1.0)
    progress, state = job.progress, job.poll()
    job.cancel()
    folder = os.path.join(work, 'softtouch')
    report(progress=progress, state=state, staged=staged, errors=job.errors, exited=job.process.poll() is not None,
           modifiers=[m.name for m in obj.modifiers], folderLeft=os.path.exists(folder))

report(error='unknown check ' + check)

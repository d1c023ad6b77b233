"""One bake of one object: export it with its evaluated animation through Blender's own glTF exporter, write the
project, run `softtouch-cli bake` as a subprocess, and put the result on the object as a Mesh Cache modifier.

Everything is made in a staging folder inside the object's SoftTouch folder; only a finished bake moves its files
into place and touches the modifier, so a failed or cancelled bake leaves the previous cache, project and
modifier as they were, and no files behind.

Frames: Blender's glTF exporter times frame f at f / fps s (render.fps; fps_base is not used), so cache frame k is
Blender frame frame_start + k. Coordinates: the exporter turns Blender's z-up into glTF's y-up, (x, y, z) ->
(x, z, -y); SoftTouch bakes in that frame, in world space; the cache holds the object's local coordinates, as the
modifier (after the armature) overwrites them.
"""
import os
import re
import shutil
import subprocess
import tempfile
import threading
from contextlib import contextmanager

import bpy
import numpy as np
from mathutils.kdtree import KDTree

from . import pc2, programs, project

MODIFIER = 'SoftTouch wobble'
_PROGRESS = re.compile(r'baking frame (\d+)/(\d+)')
_SIMULATING = re.compile(r'simulating clip (\d+)%')
_SIMULATED_SHARE = 0.9  # of the bar: the clip is simulated whole, then written


class BakeError(Exception):
    """A problem to show the user, one line each."""

    def __init__(self, *lines):
        super().__init__('\n'.join(lines))
        self.lines = list(lines)


def _file_name(name):
    return re.sub(r'[^A-Za-z0-9._-]+', '_', name).strip('._') or 'object'


def folder_of(obj):
    """The object's SoftTouch folder, absolute."""
    folder = obj.softtouch.folder
    if folder.startswith('//') and not bpy.data.filepath:
        raise BakeError('Save the .blend file first, or give the SoftTouch folder as an absolute path: '
                        f'"{folder}" is relative to the .blend file')
    return os.path.normpath(bpy.path.abspath(folder))


def paths_of(obj):
    """The object's project, its GLB and its cache, in its folder, named after the object."""
    base = os.path.join(folder_of(obj), _file_name(obj.name))
    return {'project': base + '.softtouch', 'glb': base + '.glb', 'cache': base + '.pc2'}


def frame_range(obj, scene):
    s = obj.softtouch
    return (scene.frame_start, scene.frame_end) if s.use_scene_range else (s.frame_start, s.frame_end)


def snapshot(obj, scene, cli):
    """The object's settings as the project takes them; errors name the setting."""
    s = obj.softtouch
    presets = programs.material_presets(cli)
    if s.preset not in presets:
        raise BakeError(f'Material preset "{s.preset}" is not among the bundled or your presets '
                        f'({", ".join(sorted(presets)) or "none found"})')
    start, end = frame_range(obj, scene)
    if end <= start:
        raise BakeError(f'The frame range {start}-{end} is empty: the end must come after the start')
    first, last = animation_range()
    if not first <= start < last:
        raise BakeError(f'The frame range starts at {start}, outside the animation (frames {first}-{last})')
    if s.loop and end + 1 > last:
        raise BakeError(f'A loop of frames {start}-{end} needs the animation up to frame {end + 1}, where it is back at '
                        f'frame {start}; the animation ends at frame {last}')
    return {'name': obj.name, 'preset': presets[s.preset], 'lattice_kind': s.lattice_kind, 'nodes': tuple(s.nodes),
            'integrator': s.integrator, 'steps_per_second': s.steps_per_second, 'frame_start': start,
            'frame_end': end, 'fps': scene.render.fps, 'loop': s.loop, 'goal_frequency': s.goal_frequency,
            'goal_damping_ratio': s.goal_damping_ratio, 'gravity': s.gravity, 'animation_end': last}


def animation_range():
    """The frames Blender's glTF exporter samples: from the first action's start to the last's end."""
    if not bpy.data.actions:
        raise BakeError('The scene has no animation to follow (no actions): SoftTouch layers the wobble on an '
                        'animated mesh')
    ranges = [a.frame_range for a in bpy.data.actions]
    return int(round(min(r[0] for r in ranges))), int(round(max(r[1] for r in ranges)))


@contextmanager
def only_armatures(obj):
    """The object evaluated as its GLB holds it (shape keys and armatures): every other modifier off meanwhile,
    this add-on's Mesh Cache included."""
    saved = [(m, m.show_viewport, m.show_render) for m in obj.modifiers if m.type != 'ARMATURE']
    try:
        for m, _, _ in saved:
            m.show_viewport = m.show_render = False
        yield
    finally:
        for m, viewport, render in saved:
            m.show_viewport, m.show_render = viewport, render


@contextmanager
def kept_frame(scene):
    frame, subframe = scene.frame_current, scene.frame_subframe
    try:
        yield
    finally:
        scene.frame_set(frame, subframe=subframe)


def to_gltf(points):
    return np.stack([points[:, 0], points[:, 2], -points[:, 1]], axis=1)


def from_gltf(points):
    return np.stack([points[..., 0], -points[..., 2], points[..., 1]], axis=-1)


def world_positions(obj, scene, frame):
    """Evaluated vertex positions at `frame`, world space, Blender's axes."""
    scene.frame_set(frame)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        co = np.empty(len(mesh.vertices) * 3, dtype=np.float64)
        mesh.vertices.foreach_get('co', co)
    finally:
        evaluated.to_mesh_clear()
    matrix = np.array(evaluated.matrix_world)
    return co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def goal_weights(obj, s):
    """Per vertex: the vertex group's weight (0 where a vertex is not in it), or the default weight everywhere."""
    count = len(obj.data.vertices)
    if not s.goal_group:
        return np.full(count, s.goal_default)
    group = obj.vertex_groups.get(s.goal_group)
    if group is None:
        raise BakeError(f'The goal vertex group "{s.goal_group}" is not on {obj.name}')
    weights = np.zeros(count)
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group == group.index:
                weights[v.index] = g.weight
    return weights


def export_glb(obj, path):
    """The object and the armatures that deform it, with their animation, through Blender's glTF exporter; the
    selection and active object are restored afterwards."""
    view_layer = bpy.context.view_layer
    selected, active = list(bpy.context.selected_objects), view_layer.objects.active
    rigs = {m.object for m in obj.modifiers if m.type == 'ARMATURE' and m.object}
    if obj.parent and obj.parent.type == 'ARMATURE':
        rigs.add(obj.parent)
    try:
        for o in selected:
            o.select_set(False)
        for o in [obj, *rigs]:
            o.select_set(True)
        view_layer.objects.active = obj
        bpy.ops.export_scene.gltf(filepath=path, check_existing=False, export_format='GLB', use_selection=True,
                                  export_normals=False, export_texcoords=False, export_colors=False,
                                  export_materials='NONE', export_cameras=False, export_lights=False,
                                  export_extras=False, export_apply=False, export_animations=True,
                                  export_force_sampling=True, export_nla_strips=False, export_skins=True,
                                  export_morph=True, export_morph_normal=False)
    finally:
        for o in bpy.context.selected_objects:
            o.select_set(False)
        for o in selected:
            o.select_set(True)
        view_layer.objects.active = active


def read_obj_vertices(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith('v '):
                rows.append([float(x) for x in line.split()[1:4]])
    return np.array(rows, dtype=np.float64)


def match_vertices(ours, theirs):
    """For each of `ours` (the Blender mesh's vertices at the first frame, glTF frame), the index of the same
    vertex in `theirs` (SoftTouch's rest mesh). In order where the orders agree (they do when no two vertices
    were merged); otherwise by place."""
    diagonal = float(np.linalg.norm(theirs.max(axis=0) - theirs.min(axis=0))) or 1.0
    tolerance = 1e-5 * diagonal
    if len(ours) == len(theirs) and float(np.abs(ours - theirs).max()) <= tolerance:
        return np.arange(len(ours))
    tree = KDTree(len(theirs))
    for i, p in enumerate(theirs):
        tree.insert(p, i)
    tree.balance()
    out = np.empty(len(ours), dtype=np.int64)
    for i, p in enumerate(ours):
        _, index, distance = tree.find(p)
        if distance > tolerance:
            raise BakeError(f'Vertex {i} of the mesh is not in what SoftTouch baked ({distance:.3g} m from the nearest); '
                            'is it on no face? SoftTouch bakes the faces\' vertices only')
        out[i] = index
    return out


class BakeJob:
    """A bake in progress. start() exports and launches; poll() while it runs; then finish() or cancel().

    rebake: bake the project already in the object's folder (saved by the editor) instead of writing one."""

    def __init__(self, context, obj, rebake=False):
        self.scene = context.scene
        self.obj = obj
        self.rebake = rebake
        self.paths = paths_of(obj)
        self.cli = programs.find_cli(_preference('cli_path'))
        if not self.cli:
            raise BakeError('softtouch-cli was not found: install SoftTouch, or give its path in the add-on\'s '
                            'preferences')
        self.settings = snapshot(obj, self.scene, self.cli) if not rebake else None
        if rebake and not os.path.isfile(self.paths['project']):
            raise BakeError(f'No project to reload at {self.paths["project"]}: use Open in SoftTouch first')
        self.frame_start = frame_range(obj, self.scene)[0]
        self.staging = None
        self.process = None
        self.progress = 0.0
        self.errors, self.notes = [], []

    def start(self):
        """Exports, writes the project and starts softtouch-cli. Raises BakeError, leaving nothing behind."""
        try:
            self._stage()
            source = self._staged('project') if not self.rebake else self.paths['project']
            command = [self.cli, 'bake', source, '--clip', project.CLIP, '--out', self._result()]
            self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            self._readers = [threading.Thread(target=self._read, args=(self.process.stdout, False), daemon=True),
                             threading.Thread(target=self._read, args=(self.process.stderr, True), daemon=True)]
            for r in self._readers:
                r.start()
        except BaseException:
            self._clean()
            raise

    def write_project(self):
        """Writes the project and its GLB into the object's folder without baking (for the editor)."""
        try:
            self._stage()
            for key in ('glb', 'project'):
                os.replace(self._staged(key), self.paths[key])
        except OSError as e:
            raise BakeError(str(e)) from e
        finally:
            self._clean()

    def _stage(self):
        """The staging folder, the mesh's first frame, and (unless rebaking) the GLB and project in it."""
        folder = os.path.dirname(self.paths['project'])
        self._made_folder = not os.path.isdir(folder)
        os.makedirs(folder, exist_ok=True)
        self.staging = tempfile.mkdtemp(prefix='.softtouch-bake-', dir=folder)
        with kept_frame(self.scene), only_armatures(self.obj):
            self.first = to_gltf(world_positions(self.obj, self.scene, self.frame_start))
            if self.rebake:
                return
            export_glb(self.obj, self._staged('glb'))
            weights = goal_weights(self.obj, self.obj.softtouch)
            if len(weights) != len(self.first):
                raise BakeError('A modifier before the armature changes the vertex count; SoftTouch needs the mesh '
                                'the armature deforms')
            points = np.column_stack([self.first, weights]).tolist()
            project.write(self._staged('project'), project.build(self.settings, os.path.basename(self.paths['glb']), points))

    def poll(self):
        """'running', 'done' or 'failed' (errors in self.errors)."""
        if self.process is None or self.process.poll() is None:
            return 'running'
        for r in self._readers:
            r.join()
        if self.process.returncode != 0:
            self.errors = self.errors or [f'softtouch-cli stopped with exit status {self.process.returncode}']
            return 'failed'
        return 'done'

    def wait(self):
        self.process.wait()
        return self.poll()

    def cancel(self):
        """Stops the bake and removes everything it made; the object is as it was."""
        if self.process and self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self._clean()

    def finish(self):
        """Puts a finished bake in place: the cache in the object's order and local space, the project and GLB
        beside it, and the Mesh Cache modifier after the armature. Raises BakeError, changing nothing."""
        try:
            frames = pc2.read(self._result())
            order = match_vertices(self.first, read_obj_vertices(os.path.splitext(self._result())[0] + '.obj'))
            world = from_gltf(frames[:, order, :].astype(np.float64))
            local = np.empty_like(world)
            with kept_frame(self.scene):
                for k in range(len(world)):
                    self.scene.frame_set(self.frame_start + k)
                    matrix = np.linalg.inv(np.array(self.obj.matrix_world))
                    local[k] = world[k] @ matrix[:3, :3].T + matrix[:3, 3]
            pc2.write(self._staged('cache'), local, self.frame_start)
            loops = project.clip_loops(self.paths['project'] if self.rebake else self._staged('project'))
            moved = ['cache'] if self.rebake else ['glb', 'project', 'cache']
            for key in moved:
                os.replace(self._staged(key), self.paths[key])
            set_modifier(self.obj, self.paths['cache'], self.frame_start, len(local) if loops else 0)
        except (OSError, ValueError) as e:
            raise BakeError(str(e)) from e
        finally:
            self._clean()

    def _staged(self, key):
        return os.path.join(self.staging, os.path.basename(self.paths[key]))

    def _result(self):
        return os.path.join(self.staging, 'softtouch.pc2')

    def _read(self, stream, errors):
        # Progress arrives as "\rbaking frame k/N" with no line end: read what is there, not whole lines.
        pending = ''
        while True:
            chunk = os.read(stream.fileno(), 4096)
            if not chunk:
                break
            pending += chunk.decode('utf-8', 'replace').replace('\r', '\n')
            *parts, pending = pending.split('\n')
            for part in parts:
                self._take(part.strip(), errors)
        self._take(pending.strip(), errors)

    def _take(self, part, errors):
        if not part:
            return
        simulated, written = _SIMULATING.search(part), _PROGRESS.search(part)
        if simulated:
            self.progress = _SIMULATED_SHARE * int(simulated.group(1)) / 100
        elif written:
            self.progress = _SIMULATED_SHARE + (1 - _SIMULATED_SHARE) * int(written.group(1)) / max(1, int(written.group(2)))
        elif errors:
            # The staged project is gone once the bake ends: the message starts at the field.
            part = part.removeprefix('softtouch-cli: error: ')
            if self.staging:
                part = part.removeprefix(self._staged('project') + ': ')
            self.errors.append(part)
        else:
            self.notes.append(part)

    def _clean(self):
        if self.staging:
            shutil.rmtree(self.staging, ignore_errors=True)
            self.staging = None
        # A folder this bake made and left empty (it failed or was cancelled) goes too.
        folder = os.path.dirname(self.paths['project'])
        if getattr(self, '_made_folder', False) and os.path.isdir(folder) and not os.listdir(folder):
            os.rmdir(folder)


def set_modifier(obj, cache, frame_start, cycle=0):
    """Adds or updates the Mesh Cache modifier that plays `cache` from `frame_start`, right after the last
    armature (before anything that changes the vertex count). With `cycle` (a loop's frames), it plays the cache as
    that cycle on every frame, before and after the range, as a cyclic action repeats: a driver maps the scene's
    frame to the cache's, a simple expression Blender evaluates without running Python (so it plays in a file
    whose scripts are not trusted)."""
    modifier = obj.modifiers.get(MODIFIER) or obj.modifiers.new(MODIFIER, 'MESH_CACHE')
    modifier.cache_format = 'PC2'
    modifier.filepath = bpy.path.relpath(cache) if bpy.data.filepath else cache
    modifier.frame_start = frame_start
    modifier.frame_scale = 1.0
    modifier.time_mode = 'FRAME'
    modifier.driver_remove('eval_frame')
    if cycle:
        modifier.play_mode = 'CUSTOM'
        driver = modifier.driver_add('eval_frame').driver
        driver.type = 'SCRIPTED'
        driver.expression = f'fmod(fmod(frame - {frame_start}, {cycle}) + {cycle}, {cycle})'
    else:
        modifier.play_mode = 'SCENE'
    modifier.deform_mode = 'OVERWRITE'
    modifier.interpolation = 'LINEAR'
    modifier.forward_axis, modifier.up_axis = 'POS_Y', 'POS_Z'
    modifier.factor = 1.0
    others = [m for m in obj.modifiers if m != modifier]
    armatures = [i for i, m in enumerate(others) if m.type == 'ARMATURE']
    index = armatures[-1] + 1 if armatures else 0  # its place among the others, which is its final index
    if list(obj.modifiers).index(modifier) != index:
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.modifier_move_to_index(modifier=modifier.name, index=index)
    obj.update_tag()


def _preference(name):
    addon = bpy.context.preferences.addons.get(__package__)
    return getattr(addon.preferences, name, '') if addon else ''

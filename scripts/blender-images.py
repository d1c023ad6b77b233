# The pictures of docs/blender.md (scripts/make-blender-images.sh runs this twice).
#   scene FILE.blend: headless, the rigged guppy imported (presets/meshes/guppy-rigged.glb), its swim as the scene's
#     frames 0-23, a "spine" vertex group (free tail, following head) as the goal at 1 Hz, damping 0.3; saved.
#   pictures FOLDER: in Blender's window (under Xvfb, --enable-event-simulate): the add-on in the preferences, the
#     SoftTouch tab (opened by a click on it), Bake wobble run as a user runs it (modal, with its progress), and the
#     guppy from above at the frame where the wobble shows most, with the wobble switched off (the rig alone) and on.
import os
import sys

import addon_utils
import bpy

mode, target = sys.argv[sys.argv.index('--') + 1:][:2]
ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), '..'))

if mode == 'scene':
    bpy.ops.wm.read_factory_settings(use_empty=False)
    addon_utils.enable('softtouch_wobble', default_set=True)
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    # 'SMOOTH': Blender 3.4's importer with its default shading calls numpy's removed np.bool.
    bpy.ops.import_scene.gltf(filepath=os.path.join(ROOT, 'presets/meshes/guppy-rigged.glb'), import_shading='SMOOTH')
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.context.scene.frame_start, bpy.context.scene.frame_end = 0, 23
    spine = obj.vertex_groups.new(name='spine')
    xs = [v.co.x for v in obj.data.vertices]  # the guppy lies along x, its head at +x
    low, high = min(xs), max(xs)
    for v in obj.data.vertices:
        spine.add([v.index], min(1.0, max(0.0, 1.6 * (v.co.x - low) / (high - low) - 0.3)), 'REPLACE')
    obj.softtouch.goal_group = 'spine'
    obj.softtouch.goal_frequency, obj.softtouch.goal_damping_ratio = 1.0, 0.3  # a loose tail, for the picture
    obj.softtouch.loop = True
    bpy.ops.wm.save_as_mainfile(filepath=target)
    sys.exit(0)

steps = []


def step(f):
    steps.append(f)
    return f


def area(kind):
    return next(a for a in bpy.context.window.screen.areas if a.type == kind)


def region(a, kind):
    return next(r for r in a.regions if r.type == kind)


def shot_area(a, name):
    with bpy.context.temp_override(area=a):
        bpy.ops.screen.screenshot_area(filepath=os.path.join(target, name))


@step
def open_tab():
    addon_utils.enable('softtouch_wobble', default_set=True)
    view = area('VIEW_3D')
    view.spaces.active.show_region_ui = True
    with bpy.context.temp_override(area=view, region=region(view, 'WINDOW')):
        bpy.ops.view3d.view_selected()
    # The sidebar's tabs run down its right edge: Item, Tool, View, SoftTouch.
    ui, window = region(view, 'UI'), bpy.context.window
    x, y = ui.x + ui.width - 8, view.y + view.height - 230
    window.event_simulate('MOUSEMOVE', 'NOTHING', x=x, y=y)
    window.event_simulate('LEFTMOUSE', 'PRESS', x=x, y=y)
    window.event_simulate('LEFTMOUSE', 'RELEASE', x=x, y=y)


@step
def panel():
    shot_area(area('VIEW_3D'), 'blender-panel.png')
    bpy.ops.softtouch.bake_wobble('INVOKE_DEFAULT')


@step
def baked():
    from softtouch_wobble import operators
    if operators.running:
        return 'again'
    obj = bpy.context.active_object
    if obj.modifiers.get('SoftTouch wobble') is None:
        raise SystemExit('the bake did not finish')
    modifier = obj.modifiers['SoftTouch wobble']
    scene = bpy.context.scene
    best, frame = -1.0, scene.frame_start
    for f in range(scene.frame_start, scene.frame_end + 1):
        scene.frame_set(f)
        shapes = []
        for shown in (False, True):
            modifier.show_viewport = shown
            evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
            shapes.append([v.co.copy() for v in evaluated.to_mesh().vertices])
            evaluated.to_mesh_clear()
        gap = max((p - q).length for p, q in zip(*shapes))
        if gap > best:
            best, frame = gap, f
    scene.frame_set(frame)
    obj.select_set(False)
    view = area('VIEW_3D')
    space = view.spaces.active
    space.show_region_ui = False
    space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
    space.overlay.show_cursor = space.overlay.show_object_origins = space.overlay.show_bones = False
    with bpy.context.temp_override(area=view, region=region(view, 'WINDOW')):
        bpy.ops.view3d.view_axis(type='TOP')
        obj.select_set(True)
        bpy.ops.view3d.view_selected()
        obj.select_set(False)
    modifier.show_viewport = False
    print(f'frame {frame}: the wobble moves a vertex {best:.3f} m from the rig')


@step
def before():
    shot_area(area('VIEW_3D'), 'blender-before.png')
    bpy.context.active_object.modifiers['SoftTouch wobble'].show_viewport = True


@step
def after():
    shot_area(area('VIEW_3D'), 'blender-after.png')
    bpy.ops.screen.userpref_show()
    bpy.context.preferences.active_section = 'ADDONS'
    bpy.context.window_manager.addon_search = 'SoftTouch'
    for module in addon_utils.modules():
        if module.__name__ == 'softtouch_wobble':
            addon_utils.module_bl_info(module)['show_expanded'] = True
    for window in bpy.context.window_manager.windows:
        for a in window.screen.areas:
            a.tag_redraw()


@step
def preferences():
    window = bpy.context.window_manager.windows[-1]
    with bpy.context.temp_override(window=window, area=window.screen.areas[0]):
        bpy.ops.screen.screenshot(filepath=os.path.join(target, 'blender-addon.png'))
    print('pictures done')


@step
def close():
    bpy.ops.wm.quit_blender()


def run():
    if not steps:
        return None
    if steps[0]() != 'again':
        steps.pop(0)
    return 1.0


bpy.app.timers.register(run, first_interval=2.0)

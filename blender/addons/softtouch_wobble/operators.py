"""Bake wobble, Reload, Open in SoftTouch and the preset menu."""
import atexit
import os
import subprocess

import bpy

from . import bake, programs

# The bake running per object name: one at a time each; the panel shows its progress.
running = {}


@atexit.register
def _cancel_running():
    """Blender closing mid-bake stops the bakes and takes their staged files away."""
    for job in list(running.values()):
        job.cancel()
    running.clear()


def _mesh(context):
    obj = context.active_object
    return obj if obj is not None and obj.type == 'MESH' else None


def _report_lines(operator, kind, lines):
    for line in lines:
        operator.report({kind}, line)


class _BakeOperator:
    """Shared by Bake wobble and Reload: modal in the editor (progress in the status bar, Esc cancels), to the end
    at once from a script or in the background."""
    rebake = False
    bl_options = {'REGISTER'}

    @classmethod
    def poll(cls, context):
        obj = _mesh(context)
        return obj is not None and obj.name not in running

    def _start(self, context):
        obj = _mesh(context)
        try:
            self.job = bake.BakeJob(context, obj, rebake=self.rebake)
            self.job.start()
        except bake.BakeError as e:
            _report_lines(self, 'ERROR', e.lines)
            return False
        running[obj.name] = self.job
        return True

    def _end(self, context, state):
        running.pop(self.job.obj.name, None)
        if state != 'done':
            self.job.cancel()
            _report_lines(self, 'ERROR', self.job.errors)
            return {'CANCELLED'}
        try:
            self.job.finish()
        except bake.BakeError as e:
            _report_lines(self, 'ERROR', e.lines)
            return {'CANCELLED'}
        _report_lines(self, 'INFO', [n for n in self.job.notes if n.startswith('loop seam')])
        self.report({'INFO'}, f'Baked {os.path.basename(self.job.paths["cache"])}')
        return {'FINISHED'}

    def execute(self, context):
        if not self._start(context):
            return {'CANCELLED'}
        return self._end(context, self.job.wait())

    def invoke(self, context, event):
        if not self._start(context):
            return {'CANCELLED'}
        wm = context.window_manager
        self.timer = wm.event_timer_add(0.1, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 100)
        context.workspace.status_text_set('SoftTouch: baking the wobble (Esc cancels)')
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC':
            self._stop(context)
            running.pop(self.job.obj.name, None)
            self.job.cancel()
            self.report({'WARNING'}, 'Bake cancelled: the object is as it was')
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        context.window_manager.progress_update(int(100 * self.job.progress))
        context.workspace.status_text_set(f'SoftTouch: baking the wobble, {int(100 * self.job.progress)}% (Esc cancels)')
        for area in context.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()
        state = self.job.poll()
        if state == 'running':
            return {'PASS_THROUGH'}
        self._stop(context)
        return self._end(context, state)

    def _stop(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self.timer)
        wm.progress_end()
        context.workspace.status_text_set(None)


class SOFTTOUCH_OT_bake_wobble(_BakeOperator, bpy.types.Operator):
    """Bake the soft-body wobble over the object's animation and play it with a Mesh Cache modifier after the armature"""
    bl_idname = 'softtouch.bake_wobble'
    bl_label = 'Bake Wobble'


class SOFTTOUCH_OT_reload(_BakeOperator, bpy.types.Operator):
    """Re-bake from the project as saved in the SoftTouch editor"""
    bl_idname = 'softtouch.reload'
    bl_label = 'Reload'
    rebake = True


class SOFTTOUCH_OT_open_in_softtouch(bpy.types.Operator):
    """Write the object's project and open it in the SoftTouch editor; save there, then Reload here"""
    bl_idname = 'softtouch.open_in_softtouch'
    bl_label = 'Open in SoftTouch'

    @classmethod
    def poll(cls, context):
        return _mesh(context) is not None

    def execute(self, context):
        obj = _mesh(context)
        try:
            job = bake.BakeJob(context, obj)
            editor = programs.find_editor(job.cli)
            if not editor:
                raise bake.BakeError(f'The SoftTouch editor is not beside {job.cli}')
            job.write_project()
        except bake.BakeError as e:
            _report_lines(self, 'ERROR', e.lines)
            return {'CANCELLED'}
        subprocess.Popen([editor, job.paths['project']], start_new_session=True,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.report({'INFO'}, f'Opened {os.path.basename(job.paths["project"])} in SoftTouch')
        return {'FINISHED'}


class SOFTTOUCH_OT_set_preset(bpy.types.Operator):
    """Use this material preset"""
    bl_idname = 'softtouch.set_preset'
    bl_label = 'Material Preset'
    bl_options = {'REGISTER', 'UNDO', 'INTERNAL'}
    name: bpy.props.StringProperty()

    def execute(self, context):
        context.active_object.softtouch.preset = self.name
        return {'FINISHED'}


class SOFTTOUCH_MT_presets(bpy.types.Menu):
    bl_idname = 'SOFTTOUCH_MT_presets'
    bl_label = 'Material Presets'

    def draw(self, context):
        cli = programs.find_cli(bake._preference('cli_path'))
        presets = programs.material_presets(cli)
        if not presets:
            self.layout.label(text='No presets found (is softtouch-cli installed?)')
        for name in sorted(presets):
            self.layout.operator(SOFTTOUCH_OT_set_preset.bl_idname, text=name).name = name


classes = (SOFTTOUCH_OT_bake_wobble, SOFTTOUCH_OT_reload, SOFTTOUCH_OT_open_in_softtouch, SOFTTOUCH_OT_set_preset,
           SOFTTOUCH_MT_presets)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    _cancel_running()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

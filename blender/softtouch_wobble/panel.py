"""The SoftTouch tab of the 3D view's sidebar, for the active mesh object."""
import bpy

from . import operators


class VIEW3D_PT_softtouch(bpy.types.Panel):
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = 'SoftTouch'
    bl_label = 'SoftTouch Wobble'

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == 'MESH'

    def draw(self, context):
        obj = context.active_object
        s = obj.softtouch
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False

        row = layout.row()
        row.label(text='Material')
        row.menu(operators.SOFTTOUCH_MT_presets.bl_idname, text=s.preset)
        col = layout.column(align=True)
        col.prop(s, 'lattice_kind')
        col.prop(s, 'nodes')
        col = layout.column(align=True)
        col.prop(s, 'integrator')
        col.prop(s, 'steps_per_second')

        col = layout.column(align=True)
        col.prop_search(s, 'goal_group', obj, 'vertex_groups')
        if not s.goal_group:
            col.prop(s, 'goal_default')
        col.prop(s, 'goal_frequency')
        col.prop(s, 'goal_damping_ratio')
        layout.prop(s, 'gravity')

        col = layout.column(align=True)
        col.prop(s, 'use_scene_range')
        if not s.use_scene_range:
            col.prop(s, 'frame_start')
            col.prop(s, 'frame_end')
        col.prop(s, 'loop')
        layout.prop(s, 'folder')

        job = operators.running.get(obj.name)
        if job is not None:
            layout.label(text=f'Baking... {int(100 * job.progress)}% (Esc cancels)', icon='TIME')
        else:
            layout.operator(operators.SOFTTOUCH_OT_bake_wobble.bl_idname, icon='MOD_SOFT')
        row = layout.row(align=True)
        row.operator(operators.SOFTTOUCH_OT_open_in_softtouch.bl_idname, icon='WINDOW')
        row.operator(operators.SOFTTOUCH_OT_reload.bl_idname, icon='FILE_REFRESH')
        modifier = obj.modifiers.get('SoftTouch wobble')
        if modifier is not None:
            layout.prop(modifier, 'show_viewport', text='Show wobble')


def register():
    bpy.utils.register_class(VIEW3D_PT_softtouch)


def unregister():
    bpy.utils.unregister_class(VIEW3D_PT_softtouch)

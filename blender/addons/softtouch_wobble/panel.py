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

        col = layout.column()
        row = col.row()
        row.label(text='Material')
        row.menu(operators.SOFTTOUCH_MT_presets.bl_idname, text=s.preset)
        col.prop(s, 'lattice_kind')
        row = col.row(align=True)
        row.prop(s, 'nodes', text='Nodes')
        col.prop(s, 'integrator')
        col.prop(s, 'steps_per_second')
        col.prop(s, 'gravity')

        layout.label(text='Follow the animation')
        col = layout.column()
        col.prop_search(s, 'goal_group', obj, 'vertex_groups', text='Group')
        if not s.goal_group:
            col.prop(s, 'goal_default', text='Weight')
        col.prop(s, 'goal_frequency', text='Frequency')
        col.prop(s, 'goal_damping_ratio', text='Damping')

        layout.label(text='Frames')
        col = layout.column()
        col.prop(s, 'use_scene_range')
        if not s.use_scene_range:
            col.prop(s, 'frame_start')
            col.prop(s, 'frame_end')
        col.prop(s, 'loop')
        col.prop(s, 'folder')

        layout.use_property_split = False
        job = operators.running.get(obj.name)
        if job is not None:
            layout.label(text=f'Baking: {int(100 * job.progress)}% (Esc cancels)', icon='TIME')
        else:
            layout.operator(operators.SOFTTOUCH_OT_bake_wobble.bl_idname, icon='MOD_SOFT')
        modifier = obj.modifiers.get('SoftTouch wobble')
        if modifier is not None:
            layout.prop(modifier, 'show_viewport', text='Show the wobble')
        layout.operator(operators.SOFTTOUCH_OT_open_in_softtouch.bl_idname, icon='WINDOW')
        layout.operator(operators.SOFTTOUCH_OT_reload.bl_idname, text='Reload from SoftTouch', icon='FILE_REFRESH')


def register():
    bpy.utils.register_class(VIEW3D_PT_softtouch)


def unregister():
    bpy.utils.unregister_class(VIEW3D_PT_softtouch)

"""The add-on's settings: per object (saved in the .blend, so a file reopens with them) and its preferences."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, IntVectorProperty, StringProperty

# softtouch-cli's integrators (docs/user-guide.md); a project with another is refused by the program, not here.
INTEGRATORS = [
    ('verlet', 'Verlet', 'Explicit, second order: the default for secondary motion'),
    ('symplectic-euler', 'Symplectic Euler', 'Explicit, first order, keeps energy'),
    ('implicit-euler', 'Implicit Euler', 'Unconditionally stable, damps harder at large steps'),
    ('xpbd', 'XPBD', 'Position-based: stable at any stiffness, softer at large steps'),
]


class SoftTouchObjectSettings(bpy.types.PropertyGroup):
    preset: StringProperty(name='Material', default='fish-body',
                           description='Material preset (*.stpreset): the bundled ones and those saved in the editor')
    lattice_kind: EnumProperty(name='Lattice', default='bezier', items=[
        ('bezier', 'Bezier', 'Every node moves every vertex (2 to 8 nodes an axis)'),
        ('bspline', 'B-spline', 'Local: finer lattices along long bodies (2 to 64 nodes an axis)')])
    nodes: IntVectorProperty(name='Nodes', size=3, default=(4, 4, 4), min=2, max=64,
                             description='Lattice nodes along x, y and z of the box')
    integrator: EnumProperty(name='Integrator', items=INTEGRATORS, default='verlet')
    steps_per_second: IntProperty(name='Steps/s', default=240, min=24, max=100000,
                                  description='Simulation steps per second (the time step is its inverse)')
    goal_group: StringProperty(name='Goal group',
                               description='Vertex group of goal weights: 1 follows the animation, 0 is free '
                                           '(vertices outside the group are free). Empty: the default weight')
    goal_default: FloatProperty(name='Goal', default=0.5, min=0.0, max=1.0,
                                description='Goal weight of every vertex when no vertex group is chosen')
    goal_frequency: FloatProperty(name='Goal frequency', default=2.0, min=0.001, max=1000.0, unit='NONE',
                                  description='Hz: how fast a vertex of goal weight 0.5 swings back to the animation')
    goal_damping_ratio: FloatProperty(name='Goal damping', default=0.5, min=0.0, max=100.0,
                                      description='Damping ratio of that swing (1: no overshoot)')
    gravity: FloatProperty(name='Gravity', default=0.0, min=0.0, max=10000.0,
                           description='m/s² downwards on the wobble (0 for a fish in water, 9.81 on land)')
    use_scene_range: BoolProperty(name='Scene range', default=True, description="Bake the scene's frame range")
    frame_start: IntProperty(name='Start', default=1)
    frame_end: IntProperty(name='End', default=24)
    loop: BoolProperty(name='Loop', default=False,
                       description='A seamless cycle: the animation repeats, and the last frame leads into the first')
    folder: StringProperty(name='Folder', default='//softtouch/', subtype='DIR_PATH',
                           description='Where the project, its GLB and the cache are written (named after the object)')


class SoftTouchPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__
    cli_path: StringProperty(name='softtouch-cli', subtype='FILE_PATH',
                             description='The program to run; empty: found on the PATH or beside the add-on')

    def draw(self, context):
        from . import programs
        self.layout.prop(self, 'cli_path')
        found = programs.find_cli(self.cli_path)
        self.layout.label(text=f'Runs {found}' if found else 'softtouch-cli not found', icon='NONE' if found else 'ERROR')


classes = (SoftTouchObjectSettings, SoftTouchPreferences)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Object.softtouch = bpy.props.PointerProperty(type=SoftTouchObjectSettings)


def unregister():
    del bpy.types.Object.softtouch
    for c in reversed(classes):
        bpy.utils.unregister_class(c)

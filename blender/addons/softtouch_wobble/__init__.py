"""SoftTouch Wobble: layers SoftTouch's soft-body secondary motion on the active animated mesh.

The physics runs in the installed softtouch-cli (docs/blender.md); this add-on exports the object with its
animation, writes a SoftTouch project, runs the bake and plays the result with a Mesh Cache modifier after the
armature, so the rig and its keys are untouched and the wobble can be switched off.
"""
bl_info = {
    'name': 'SoftTouch Wobble',
    'author': 'SoftTouch',
    'version': (1, 0, 0),
    'blender': (3, 4, 0),
    'location': "3D View > Sidebar > SoftTouch",
    'description': 'Soft-body secondary motion on an animated mesh, baked by SoftTouch',
    'warning': '',
    'doc_url': '',
    'category': 'Animation',
}

from . import operators, panel, settings  # noqa: E402

_modules = (settings, operators, panel)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()

"""Where SoftTouch's programs and material presets are: the add-on runs the installed programs, never physics of
its own.

softtouch-cli is looked for in this order: the add-on's preference, $SOFTTOUCH_CLI, beside the add-on (the same
install's: <prefix>/bin for <prefix>/share/blender/scripts/addons/softtouch_wobble, build/bin for the source
tree's blender/addons/softtouch_wobble),
then the PATH. The editor, softtouch, sits beside it.
"""
import os
import shutil

_HERE = os.path.dirname(os.path.abspath(__file__))


def _candidates():
    # Installed: <prefix>/share/blender/scripts/addons/softtouch_wobble; the source tree: blender/addons/softtouch_wobble.
    for up in ('../../../../../bin', '../../../build/bin'):
        yield os.path.normpath(os.path.join(_HERE, up, 'softtouch-cli'))


def find_cli(preference=''):
    """The softtouch-cli to run, or None."""
    for path in (preference, os.environ.get('SOFTTOUCH_CLI', '')):
        if path:
            path = os.path.abspath(os.path.expanduser(path))
            return path if os.access(path, os.X_OK) else None
    for path in _candidates():
        if os.access(path, os.X_OK):
            return path
    return shutil.which('softtouch-cli')


def find_editor(cli):
    """The editor beside `cli`, or None."""
    path = os.path.join(os.path.dirname(cli), 'softtouch')
    return path if os.access(path, os.X_OK) else None


def preset_folders(cli):
    """The bundled material presets' folder (beside the program: installed or in the source tree) and the user's
    (where the editor's "Save as preset" writes)."""
    folders = []
    if cli:
        bin_dir = os.path.dirname(os.path.realpath(cli))
        for up in ('../share/softtouch/presets/materials', '../../presets/materials'):
            folder = os.path.normpath(os.path.join(bin_dir, up))
            if os.path.isdir(folder):
                folders.append(folder)
                break
    data = os.environ.get('XDG_DATA_HOME') or os.path.expanduser('~/.local/share')
    folders.append(os.path.join(data, 'SoftTouch', 'SoftTouch', 'presets'))
    return folders


def material_presets(cli):
    """{name: path} of every *.stpreset in the preset folders; a user's preset of a bundled name wins."""
    presets = {}
    for folder in preset_folders(cli):
        try:
            names = sorted(os.listdir(folder))
        except OSError:
            continue
        for name in names:
            if name.endswith('.stpreset'):
                presets[name[:-len('.stpreset')]] = os.path.join(folder, name)
    return presets

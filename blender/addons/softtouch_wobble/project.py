"""The SoftTouch project (*.softtouch, docs/project-format.md) the add-on writes for one object: its exported GLB
with the evaluated animation, the material preset, lattice, integrator and step, the goal weights at the mesh's
vertices ("goalWeightPoints") and one clip, "wobble", over the object's frame range."""
import json
import os

CLIP = 'wobble'  # the clip every bake of an add-on project asks for (softtouch-cli bake --clip wobble)


def sample_rate(fps):
    """The rig's samples per second: a whole multiple of the frame rate near 240 (frames land on samples),
    within the project's [1, 1000]."""
    return float(min(1000, fps * max(1, round(240 / fps))))


def build(settings, glb_name, points):
    """The project as a dict.

    settings: preset (path), lattice_kind ('bezier'|'bspline'), nodes (3 ints), integrator, steps_per_second,
      frame_start, frame_end (Blender frames, inclusive), fps (whole frames per second, as Blender's glTF exporter
      times keys: frame f at f / fps s), loop, goal_frequency (Hz), goal_damping_ratio, gravity (m/s², downwards),
      animation_end (the animation's last frame).
    glb_name: the GLB beside the project. points: [[x, y, z, weight], ...] in the GLB's frame.
    """
    fps = settings['fps']
    frames = settings['frame_end'] - settings['frame_start'] + 1
    start = settings['frame_start'] / fps
    # A loop's last frame runs on into its first: the take spans one frame more than the frames baked. A clip
    # that runs past the animation's end holds its last pose there, as Blender does.
    end = (min(settings['frame_end'], settings['animation_end']) + (1 if settings['loop'] else 0)) / fps
    clip = {'name': CLIP, 'source': 'drivers', 'frames': frames, 'fps': fps, 'loop': settings['loop']}
    if settings['loop']:
        # Two cycles of settling first; they are whole cycles, so frame k is still the rig's frame start + k.
        clip['start'] = 2 * frames / fps
        clip['blend'] = max(1, frames // 4)
    return {
        'format': 'softtouch-project',
        'version': 4,
        'objects': [{
            'name': settings['name'],
            'mesh': glb_name,
            'animation': {'start': start, 'end': end, 'loop': settings['loop'], 'sampleRate': sample_rate(fps),
                          'goal': {'frequency': settings['goal_frequency'],
                                   'dampingRatio': settings['goal_damping_ratio']}},
            'lattice': {'kind': settings['lattice_kind'], 'nodes': list(settings['nodes']), 'padding': 0.02},
            'material': {'preset': os.path.abspath(settings['preset'])},
            'goalWeightPoints': points,
        }],
        'world': {'gravity': [0, -settings['gravity'], 0]},  # glTF's up is +y
        'simulation': {'integrator': settings['integrator'], 'dt': 1.0 / settings['steps_per_second']},
        'clip': {'frames': frames, 'fps': fps},
        'clips': {'library': [clip]},
    }


def clip_loops(path):
    """Whether the project at `path` (as the add-on or the editor wrote it) plays its "wobble" clip as a loop."""
    with open(path) as f:
        clips = json.load(f).get('clips', {}).get('library', [])
    return any(c.get('name') == CLIP and c.get('loop', False) for c in clips)


def write(path, project):
    """Writes the project through a temporary file beside it."""
    partial = path + '.partial'
    with open(partial, 'w') as f:
        json.dump(project, f, indent=1)
    os.replace(partial, path)

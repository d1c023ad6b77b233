"""PC2 point caches (3ds Max's, read by Blender's Mesh Cache modifier): read SoftTouch's, write the object's.

Layout: 'POINTCACHE2\\0', int32 version (1), int32 points, float32 start frame, float32 frames per sample,
int32 samples, then samples x points x 3 little-endian float32.
"""
import os
import struct

import numpy as np

_MAGIC = b'POINTCACHE2\0'
_HEADER = struct.Struct('<12siiffi')


def read(path):
    """The frames as a (samples, points, 3) float32 array."""
    with open(path, 'rb') as f:
        header = f.read(_HEADER.size)
        if len(header) != _HEADER.size or header[:12] != _MAGIC:
            raise ValueError(f'{path}: not a PC2 file')
        _, _, points, _, _, samples = _HEADER.unpack(header)
        data = np.fromfile(f, dtype='<f4', count=samples * points * 3)
    if data.size != samples * points * 3:
        raise ValueError(f'{path}: ends after {data.size // 3} of {samples * points} points')
    return data.reshape(samples, points, 3)


def write(path, frames, start_frame):
    """Writes `frames` ((samples, points, 3)) to `path` through a temporary file beside it, so a failed write never
    leaves half a cache where a good one was."""
    frames = np.ascontiguousarray(frames, dtype='<f4')
    samples, points, _ = frames.shape
    partial = path + '.partial'
    try:
        with open(partial, 'wb') as f:
            f.write(_HEADER.pack(_MAGIC, 1, points, float(start_frame), 1.0, samples))
            frames.tofile(f)
        os.replace(partial, path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)

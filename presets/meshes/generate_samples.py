#!/usr/bin/env python3
"""Procedural sample meshes for SoftTouch (presets/meshes/).

Writes angelfish.obj, demekin.obj, guppy.obj and star.obj next to this file, and
guppy-rigged.glb: the guppy with a spine of six joints, smooth skin weights and a
one-second swim cycle (take "swim"), for secondary motion on a base animation.
Pure Python 3 standard library and fully deterministic (no randomness), so
re-running it produces byte-identical files.

Conventions
  * Fish: body axis +X with the head at +X, up +Y, lateral (left/right) Z.
    Snout-to-tail-tip length ~1.0, centred near the origin.
  * Star: lies in the XY plane, circumradius ~0.5, thickness along Z.
  * Every part (body, eye, fin, tail) is its own closed, consistently wound
    (counter-clockwise seen from outside => outward normals) triangle mesh,
    written as its own `o NAME` group. Parts may interpenetrate (eyes and fin
    roots are embedded in the body on purpose).

Usage
    python3 generate_samples.py           # (re)generate the OBJ files
    python3 generate_samples.py --check   # validate the OBJ files on disk
"""
import bisect
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


# ----------------------------------------------------------------- vectors
def add(a, b): return tuple(x + y for x, y in zip(a, b))
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def mul(a, s): return tuple(x * s for x in a)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def length(a): return math.sqrt(dot(a, a))
def normalize(a): return mul(a, 1.0 / length(a))
def lerp(a, b, t): return tuple(x + (y - x) * t for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def spow(x, p):
    """Signed power, used for super-ellipse cross sections."""
    return math.copysign(abs(x) ** p, x)


# ------------------------------------------------------------------ curves
def smooth_fn(knots):
    """1D cubic Hermite interpolant through (x, y) knots sorted by x.
    Used for body contours (top, bottom, width as functions of x)."""
    xs = [k[0] for k in knots]
    ys = [k[1] for k in knots]
    n = len(knots)
    sec = [(ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) for i in range(n - 1)]
    tan = [sec[0]] + [(sec[i - 1] + sec[i]) / 2 for i in range(1, n - 1)] + [sec[-1]]

    def f(x):
        x = min(max(x, xs[0]), xs[-1])
        i = 0
        while i < n - 2 and x > xs[i + 1]:
            i += 1
        h = xs[i + 1] - xs[i]
        t = (x - xs[i]) / h
        t2, t3 = t * t, t * t * t
        return ((2 * t3 - 3 * t2 + 1) * ys[i] + (t3 - 2 * t2 + t) * h * tan[i]
                + (-2 * t3 + 3 * t2) * ys[i + 1] + (t3 - t2) * h * tan[i + 1])
    return f


def spline(ctrl, closed=False, per_seg=32):
    """Dense polyline through 2D/3D control points (centripetal Catmull-Rom,
    which never forms cusps or loops between control points)."""
    pts = list(ctrl)
    if closed:
        ext = [pts[-1]] + pts + [pts[0], pts[1]]
    else:
        ext = [sub(mul(pts[0], 2), pts[1])] + pts + [sub(mul(pts[-1], 2), pts[-2])]
    out = []
    for s in range(len(ext) - 3):
        p0, p1, p2, p3 = ext[s:s + 4]
        t0 = 0.0
        t1 = t0 + max(length(sub(p1, p0)), 1e-9) ** 0.5
        t2 = t1 + max(length(sub(p2, p1)), 1e-9) ** 0.5
        t3 = t2 + max(length(sub(p3, p2)), 1e-9) ** 0.5
        for k in range(per_seg):
            t = t1 + (t2 - t1) * k / per_seg
            a1 = lerp(p0, p1, (t - t0) / (t1 - t0))
            a2 = lerp(p1, p2, (t - t1) / (t2 - t1))
            a3 = lerp(p2, p3, (t - t2) / (t3 - t2))
            b1 = lerp(a1, a2, (t - t0) / (t2 - t0))
            b2 = lerp(a2, a3, (t - t1) / (t3 - t1))
            out.append(lerp(b1, b2, (t - t1) / (t2 - t1)))
    if not closed:
        out.append(pts[-1])
    return out


def resample(poly, n, closed=False):
    """Resample a polyline at n equal arc-length steps (n+1 points when open,
    n points when closed) so that mesh vertices are evenly spaced."""
    pts = list(poly) + ([poly[0]] if closed else [])
    cum = [0.0]
    for a, b in zip(pts, pts[1:]):
        cum.append(cum[-1] + length(sub(b, a)))
    out, j = [], 0
    for k in range(n if closed else n + 1):
        d = cum[-1] * k / n
        while j < len(cum) - 2 and cum[j + 1] < d:
            j += 1
        seg = cum[j + 1] - cum[j]
        out.append(lerp(pts[j], pts[j + 1], 0.0 if seg == 0 else (d - cum[j]) / seg))
    return out


# ------------------------------------------------------------------- parts
class Part:
    """One closed triangle mesh, written as its own `o` group."""

    def __init__(self, name):
        self.name, self.verts, self.tris = name, [], []

    def vert(self, p):
        self.verts.append(tuple(float(c) for c in p))
        return len(self.verts) - 1

    def volume(self):
        v = self.verts
        return sum(dot(v[a], cross(v[b], v[c])) for a, b, c in self.tris) / 6.0

    def orient_outward(self):
        # Builders wind all triangles of a part consistently; if the
        # construction happened to face inwards, flip the whole part.
        if self.volume() < 0:
            self.tris = [(a, c, b) for a, b, c in self.tris]
        return self

    def mirrored_z(self, name):
        """Left/right counterpart (mirror in Z flips winding, so re-flip)."""
        m = Part(name)
        m.verts = [(x, y, -z) for x, y, z in self.verts]
        m.tris = [(a, c, b) for a, b, c in self.tris]
        return m


def tube(part, rings, p_start, p_end):
    """Close a stack of equal-length vertex rings into a watertight surface
    with a single pole vertex at each end (like a UV sphere)."""
    n = len(rings[0])
    ids = [[part.vert(p) for p in ring] for ring in rings]
    s, e = part.vert(p_start), part.vert(p_end)
    for k in range(n):
        k1 = (k + 1) % n
        part.tris.append((s, ids[0][k1], ids[0][k]))
        for r in range(len(ids) - 1):
            a, b, c, d = ids[r][k], ids[r][k1], ids[r + 1][k1], ids[r + 1][k]
            part.tris += [(a, b, c), (a, c, d)]
        part.tris.append((e, ids[-1][k], ids[-1][k1]))
    return part.orient_outward()


def revolve(name, profile, origin, axis, n_around):
    """Surface of revolution. profile: [(s, r), ...] along the axis with
    r == 0 at both ends (poles)."""
    d = normalize(axis)
    helper = (0.0, 1.0, 0.0) if abs(d[1]) < 0.9 else (1.0, 0.0, 0.0)
    e1 = normalize(cross(d, helper))
    e2 = cross(d, e1)
    rings = []
    for s, r in profile[1:-1]:
        c = add(origin, mul(d, s))
        rings.append([add(c, add(mul(e1, r * math.cos(2 * math.pi * k / n_around)),
                                 mul(e2, r * math.sin(2 * math.pi * k / n_around))))
                      for k in range(n_around)])
    return tube(Part(name), rings, add(origin, mul(d, profile[0][0])),
                add(origin, mul(d, profile[-1][0])))


def sphere(name, center, radius, axis, n_around=20, n_rings=11):
    prof = [(-radius * math.cos(math.pi * i / (n_rings + 1)),
             radius * math.sin(math.pi * i / (n_rings + 1))) for i in range(n_rings + 2)]
    return revolve(name, prof, center, axis, n_around)


class Body:
    """Fish body lofted along X: smooth top/bottom contours and half-width
    (functions of x) give an elliptical/super-elliptical cross section per
    station; an envelope rounds the snout and tail ends into single poles."""

    def __init__(self, x0, x1, top, bot, width, k=6.0, n=2.0):
        self.x0, self.x1, self.k, self.n = x0, x1, k, n
        self.top, self.bot, self.width = smooth_fn(top), smooth_fn(bot), smooth_fn(width)

    def section(self, x):
        t = (x - self.x0) / (self.x1 - self.x0)
        env = math.sqrt(max(0.0, 1.0 - abs(2 * t - 1) ** self.k))
        tp, bt = self.top(x), self.bot(x)
        return (tp + bt) / 2, (tp - bt) / 2 * env, self.width(x) * env

    def top_y(self, x):
        yc, h, _ = self.section(x)
        return yc + h

    def bot_y(self, x):
        yc, h, _ = self.section(x)
        return yc - h

    def surface_z(self, x, y):
        """+Z surface of the body at (x, y): where eyes and fins attach."""
        yc, h, w = self.section(x)
        s = min(abs(y - yc) / h, 1.0)
        return w * (1 - s ** self.n) ** (1 / self.n)

    def mesh(self, n_around, n_rings):
        rings = []
        for i in range(1, n_rings + 1):
            # cosine spacing puts more rings near the strongly curved ends
            t = 0.5 - 0.5 * math.cos(math.pi * i / (n_rings + 1))
            x = self.x0 + (self.x1 - self.x0) * t
            yc, h, w = self.section(x)
            ring = []
            for k in range(n_around):
                a = 2 * math.pi * k / n_around
                ring.append((x, yc + h * spow(math.sin(a), 2 / self.n),
                             w * spow(math.cos(a), 2 / self.n)))
            rings.append(ring)
        ends = [(x, self.section(x)[0], 0.0) for x in (self.x0, self.x1)]
        return tube(Part("body"), rings, ends[0], ends[1])


def sub_polyline(poly, f0, f1):
    """Piece of a polyline between arc-length fractions f0 <= f1."""
    cum = [0.0]
    for a, b in zip(poly, poly[1:]):
        cum.append(cum[-1] + length(sub(b, a)))

    def at(f):
        d = cum[-1] * f
        k = min(max(bisect.bisect_right(cum, d) - 1, 0), len(cum) - 2)
        seg = cum[k + 1] - cum[k]
        return lerp(poly[k], poly[k + 1], 0.0 if seg == 0 else min(1.0, (d - cum[k]) / seg))
    d0, d1 = cum[-1] * f0, cum[-1] * f1
    return [at(f0)] + [p for p, c in zip(poly, cum) if d0 < c < d1] + [at(f1)]


def fin_grid(root, edge, nu, nv, tip=(0.0, 1.0)):
    """2D (nu+1) x (nv+1) grid over a fin outline, as a Coons patch.
    Sides: v=0 the root curve; v=1 the part of the free edge between
    arc-length fractions tip[0]..tip[1]; u=0 / u=1 the rest of the free edge
    (leading / trailing edge) joined to the root ends. With tip=(0, 1) the
    sides u=0/1 are short straight rulings: a fan from the root (tails,
    paired fins). For swept sails a shorter tip section makes the grid lines
    run from root to tip like fin rays."""
    A = resample(spline(root), nu)
    E = spline(edge)
    T = resample(sub_polyline(E, tip[0], tip[1]), nu)
    L = resample([A[0]] + sub_polyline(E, 0.0, tip[0]), nv)
    R = resample([A[-1]] + sub_polyline(E, tip[1], 1.0)[::-1], nv)
    grid = []
    for i in range(nu + 1):
        u = i / nu
        row = []
        for j in range(nv + 1):
            v = j / nv
            row.append(tuple(
                (1 - v) * A[i][k] + v * T[i][k] + (1 - u) * L[j][k] + u * R[j][k]
                - ((1 - u) * (1 - v) * A[0][k] + u * (1 - v) * A[-1][k]
                   + (1 - u) * v * T[0][k] + u * v * T[-1][k]) for k in range(2)))
        grid.append(row)
    return grid


def fin(name, root, edge, frame, thick, nu, nv, bend=None, tip=(0.0, 1.0), taper=0.6):
    """Thin closed slab fin. root: 2D control points of the attachment line
    (hidden inside the body); edge: 2D control points of the free outline,
    running from near root[0] round to near root[-1] (see fin_grid). The
    sheet is mapped to 3D by frame = (origin, ex, ey) and thickened along
    the frame normal, thinning towards the free edges. bend(u, v) optionally
    displaces the sheet along the normal (ripples, cupping)."""
    origin, ex, ey = frame
    nrm = normalize(cross(ex, ey))
    grid = fin_grid(root, edge, nu, nv, tip)
    sign = None  # the 2D grid must not fold over itself
    for i in range(nu):
        for j in range(nv):
            p, q, r, s = grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1]
            for a, b, c in ((p, q, r), (p, r, s)):
                cz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
                if abs(cz) < 1e-8 or (sign is not None and (cz > 0) != sign):
                    raise ValueError("%s: fin grid folds at cell %d,%d" % (name, i, j))
                sign = cz > 0
    part = Part(name)
    F = [[0] * (nv + 1) for _ in range(nu + 1)]
    K = [[0] * (nv + 1) for _ in range(nu + 1)]
    for i in range(nu + 1):
        for j in range(nv + 1):
            u, v = i / nu, j / nv
            a, b = grid[i][j]
            base = add(origin, add(mul(ex, a), mul(ey, b)))
            off = bend(u, v) if bend else 0.0
            h = thick / 2 * (1 - taper * min(1.0, v * v + (2 * u - 1) ** 4))
            F[i][j] = part.vert(add(base, mul(nrm, off + h)))
            K[i][j] = part.vert(add(base, mul(nrm, off - h)))
    for i in range(nu):
        for j in range(nv):
            part.tris += [(F[i][j], F[i + 1][j], F[i + 1][j + 1]),
                          (F[i][j], F[i + 1][j + 1], F[i][j + 1]),
                          (K[i][j], K[i + 1][j + 1], K[i + 1][j]),
                          (K[i][j], K[i][j + 1], K[i + 1][j + 1])]
    # side wall along the boundary loop (counter-clockwise in grid space)
    loop = ([(i, 0) for i in range(nu)] + [(nu, j) for j in range(nv)] +
            [(i, nv) for i in range(nu, 0, -1)] + [(0, j) for j in range(nv, 0, -1)])
    for k, p in enumerate(loop):
        q = loop[(k + 1) % len(loop)]
        fp, fq, kp, kq = F[p[0]][p[1]], F[q[0]][q[1]], K[p[0]][p[1]], K[q[0]][q[1]]
        part.tris += [(fq, fp, kp), (fq, kp, kq)]
    return part.orient_outward()


def scaled(pts, s):
    return [(x * s, y * s) for x, y in pts]


# Generic paired-fin outline (root along local +y/-y at a=0, fin out along +a).
PAIRED_ROOT = [(0.0, 0.28), (0.0, -0.28)]
PAIRED_EDGE = [(0.04, 0.34), (0.45, 0.42), (0.85, 0.30), (1.0, 0.05),
               (0.75, -0.22), (0.30, -0.36), (0.04, -0.34)]


def paired_fins(base, body, x, y, out_dir, root_dir, size, thick=0.012,
                nu=12, nv=4, inset=0.012, cup=0.0):
    """Left/right fins attached to the body side at (x, y). out_dir: where the
    fin points (for the +Z side); root_dir: roughly along the attachment."""
    origin = (x, y, body.surface_z(x, y) - inset)
    ex = normalize(out_dir)
    ey = normalize(sub(root_dir, mul(ex, dot(root_dir, ex))))
    bend = (lambda u, v: cup * size * v * v) if cup else None   # slight cupping
    left = fin(base + "_left", scaled(PAIRED_ROOT, size), scaled(PAIRED_EDGE, size),
               (origin, ex, ey), thick, nu, nv, bend)
    return [left, left.mirrored_z(base + "_right")]


def eyes(body, x, y, r, axis=(0.25, 0.1, 1.0), protrude=0.6, n_around=20, n_rings=11):
    """Two spheres sitting in the body surface, `protrude` radii sticking out."""
    z = body.surface_z(x, y) + r * (protrude - 1)
    left = sphere("eye_left", (x, y, z), r, axis, n_around, n_rings)
    return [left, left.mirrored_z("eye_right")]


XY = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))  # fin frame = world XY


def contour_pts(fn, xs, dy):
    return [(x, fn(x) + dy) for x in xs]


# -------------------------------------------------------------------- fish
def angelfish():
    """Tall, laterally flattened disc with sail-like swept-back dorsal and
    anal fins, lyre tail with long filaments, small pectorals."""
    body = Body(-0.27, 0.5,
                top=[(-0.27, 0.035), (-0.19, 0.045), (-0.08, 0.15), (0.08, 0.265),
                     (0.22, 0.245), (0.36, 0.15), (0.5, 0.05)],
                bot=[(-0.27, -0.035), (-0.19, -0.045), (-0.08, -0.16), (0.08, -0.265),
                     (0.24, -0.22), (0.38, -0.10), (0.5, -0.015)],
                width=[(-0.27, 0.018), (-0.15, 0.024), (0.05, 0.07), (0.3, 0.06),
                       (0.5, 0.03)], k=8)
    parts = [body.mesh(40, 38)]
    parts += eyes(body, 0.385, 0.065, 0.034)
    xs = [0.20, 0.1, 0.0, -0.1, -0.18]
    parts.append(fin("dorsal_fin", contour_pts(body.top_y, xs, -0.025),
                     [(0.20, body.top_y(0.20) - 0.005), (0.09, 0.42), (-0.08, 0.56),
                      (-0.35, 0.625), (-0.43, 0.65), (-0.36, 0.57), (-0.27, 0.40),
                      (-0.22, 0.22),
                      (-0.185, body.top_y(-0.185) - 0.005)],
                     XY, 0.016, 12, 18, tip=(0.35, 0.75)))
    xs = [0.06, 0.0, -0.08, -0.18]
    parts.append(fin("anal_fin", contour_pts(body.bot_y, xs, 0.025),
                     [(0.06, body.bot_y(0.06) + 0.005), (-0.04, -0.44), (-0.16, -0.58),
                      (-0.37, -0.665), (-0.45, -0.695), (-0.37, -0.60), (-0.28, -0.42),
                      (-0.225, -0.22),
                      (-0.185, body.bot_y(-0.185) + 0.005)],
                     XY, 0.016, 12, 18, tip=(0.35, 0.75)))
    parts.append(fin("tail_fin", [(-0.2, 0.04), (-0.2, -0.04)],
                     [(-0.205, 0.05), (-0.30, 0.13), (-0.50, 0.28), (-0.40, 0.12),
                      (-0.36, 0.0), (-0.40, -0.12), (-0.50, -0.28), (-0.30, -0.13),
                      (-0.205, -0.05)], XY, 0.014, 16, 12, tip=(0.27, 0.73)))
    parts += paired_fins("pectoral_fin", body, 0.25, -0.03, (-0.8, -0.15, 0.5),
                         (0.2, 1.0, 0.0), 0.12, cup=0.15)
    return parts


def telescope_eye(name, base, axis, r_stalk, r_ball, ball_at, n_around=20, n_rings=16):
    """Stalk (capsule) blended smoothly into a big ball: one closed mesh."""
    c, end = ball_at, ball_at + r_ball

    def radius(s):
        stalk = math.sqrt(max(0.0, r_stalk ** 2 - (r_stalk - s) ** 2)) if s < r_stalk else (
            r_stalk if s <= c else math.sqrt(max(0.0, r_stalk ** 2 - (s - c) ** 2)))
        ball = math.sqrt(max(0.0, r_ball ** 2 - (s - c) ** 2))
        if ball == 0.0 or stalk == 0.0:
            return max(ball, stalk)
        kf = 0.6 * r_stalk   # polynomial smooth-max: fillet where stalk meets ball
        hh = max(kf - abs(ball - stalk), 0.0) / kf
        return max(ball, stalk) + hh * hh * kf / 4
    dense = [(end * i / 4000, radius(end * i / 4000)) for i in range(4001)]
    return revolve(name, resample(dense, n_rings + 1), base, axis, n_around)


def demekin():
    """Telescope-eye goldfish: round egg body, big eyes on short stalks,
    flowing double tail splayed left/right, dorsal/pectoral/pelvic fins."""
    body = Body(-0.16, 0.42,
                top=[(-0.16, 0.07), (-0.05, 0.15), (0.1, 0.2), (0.25, 0.19), (0.42, 0.12)],
                bot=[(-0.16, -0.06), (-0.05, -0.15), (0.1, -0.21), (0.25, -0.19),
                     (0.42, -0.08)],
                width=[(-0.16, 0.06), (-0.05, 0.11), (0.1, 0.16), (0.25, 0.15),
                       (0.42, 0.1)], k=3)
    parts = [body.mesh(40, 32)]
    ax = (0.35, 0.3, 1.0)
    left = telescope_eye("eye_left", (0.29, 0.06, 0.0), ax, 0.034, 0.068, 0.23)
    parts += [left, left.mirrored_z("eye_right")]
    parts.append(fin("dorsal_fin", contour_pts(body.top_y, [0.18, 0.1, 0.0, -0.06], -0.025),
                     [(0.18, body.top_y(0.18) - 0.005), (0.13, 0.30), (0.05, 0.35),
                      (-0.05, 0.335), (-0.13, 0.28), (-0.17, 0.2),
                      (-0.10, body.top_y(-0.10) - 0.005)],
                     XY, 0.014, 12, 10, tip=(0.3, 0.75)))
    # Double tail: two fan lobes, each forked, yawed outwards and rolled so
    # that seen from behind they form a splayed "butterfly".
    lobe_root = [(0.0, 0.045), (0.0, -0.045)]
    lobe_edge = [(0.01, 0.06), (0.14, 0.17), (0.38, 0.27), (0.40, 0.11), (0.31, 0.01),
                 (0.41, -0.10), (0.40, -0.27), (0.16, -0.17), (0.01, -0.06)]
    yaw, roll = math.radians(28), math.radians(22)
    ex = (-math.cos(yaw), 0.0, math.sin(yaw))
    ey = normalize(sub((0.0, math.cos(roll), math.sin(roll)),
                       mul(ex, dot((0.0, math.cos(roll), math.sin(roll)), ex))))
    ripple = lambda u, v: 0.025 * v * v * math.sin(2 * math.pi * 2.0 * u)  # flowing waves
    left = fin("tail_fin_left", lobe_root, lobe_edge, ((-0.11, 0.0, 0.012), ex, ey),
               0.014, 28, 7, ripple)
    parts += [left, left.mirrored_z("tail_fin_right")]
    parts += paired_fins("pectoral_fin", body, 0.22, -0.09, (-0.75, -0.35, 0.55),
                         (0.3, 1.0, 0.0), 0.13, cup=0.15)
    parts += paired_fins("pelvic_fin", body, 0.06, -0.16, (-0.6, -0.75, 0.3),
                         (1.0, -0.3, 0.0), 0.13, cup=0.1)
    return parts


def guppy():
    """Slim little body with a huge fanned (delta) tail and small dorsal."""
    body = Body(-0.16, 0.5,
                top=[(-0.16, 0.022), (-0.09, 0.03), (0.05, 0.068), (0.2, 0.078),
                     (0.38, 0.062), (0.5, 0.045)],
                bot=[(-0.16, -0.022), (-0.09, -0.028), (0.05, -0.062), (0.2, -0.088),
                     (0.38, -0.055), (0.5, -0.03)],
                width=[(-0.16, 0.014), (0.0, 0.035), (0.2, 0.048), (0.4, 0.042),
                       (0.5, 0.03)], k=6)
    parts = [body.mesh(40, 42)]
    parts += eyes(body, 0.43, 0.018, 0.03)
    # fan tail: rays show as radial ripples across the sheet
    rays = lambda u, v: 0.006 * v * math.sin(2 * math.pi * 5 * u)
    parts.append(fin("tail_fin", [(-0.125, 0.025), (-0.125, -0.025)],
                     [(-0.13, 0.035), (-0.26, 0.12), (-0.42, 0.215), (-0.49, 0.17),
                      (-0.515, 0.06), (-0.52, -0.04), (-0.50, -0.15), (-0.43, -0.215),
                      (-0.26, -0.12), (-0.13, -0.035)], XY, 0.012, 24, 12, rays,
                     tip=(0.28, 0.72)))
    parts.append(fin("dorsal_fin", contour_pts(body.top_y, [0.05, -0.02, -0.08], -0.015),
                     [(0.05, body.top_y(0.05) - 0.005), (0.0, 0.125), (-0.1, 0.15),
                      (-0.18, 0.11), (-0.125, body.top_y(-0.125) - 0.002)],
                     XY, 0.01, 8, 8, tip=(0.3, 0.8)))
    parts += paired_fins("pectoral_fin", body, 0.33, -0.02, (-0.8, -0.2, 0.55),
                         (0.2, 1.0, 0.0), 0.07, thick=0.008, cup=0.15)
    return parts


# -------------------------------------------------------------------- star
def star(n_out=160, n_prof=27):
    """Plump cartoon star: rounded five-point outline, scaled along a
    super-elliptic (radius, z) profile => flat-ish bulged faces and fully
    rounded sides. Triangles = 2 * n_out * n_prof = 8640."""
    r_out, r_in = 0.545, 0.545 * 0.5
    poly = []
    for i in range(10):
        a = math.pi / 2 + i * math.pi / 5
        r = r_out if i % 2 == 0 else r_in
        poly.append((r * math.cos(a), r * math.sin(a)))
    # round every corner with a quadratic Bezier fillet (tips more than valleys)
    path = []
    for i in range(10):
        v, prv, nxt = poly[i], poly[i - 1], poly[(i + 1) % 10]
        d = 0.09 if i % 2 == 0 else 0.06
        p0 = add(v, mul(normalize(sub(prv, v)), d))
        p2 = add(v, mul(normalize(sub(nxt, v)), d))
        for k in range(17):
            t = k / 16
            path.append(add(add(mul(p0, (1 - t) ** 2), mul(v, 2 * t * (1 - t))), mul(p2, t * t)))
    path = path[8:] + path[:8]          # start exactly at the top tip
    outline = resample(path, n_out, closed=True)
    zc, n = 0.13, 2.6                    # half thickness at centre, profile exponent
    dense = []
    for i in range(2001):
        a = math.pi * i / 2000
        dense.append((0.35 * abs(math.sin(a)) ** (2 / n), zc * spow(math.cos(a), 2 / n)))
    prof = resample(dense, n_prof + 1)   # even spacing over the (radius, z) profile
    rings = [[(q / 0.35 * x, q / 0.35 * y, z) for x, y in outline] for q, z in prof[1:-1]]
    return [tube(Part("star"), rings, (0.0, 0.0, zc), (0.0, 0.0, -zc))]


# ----------------------------------------------------------------- output
def fmt(x):
    s = "%.6f" % x
    return "0.000000" if s == "-0.000000" else s


def write_obj(path, parts):
    lines = ["# Generated by generate_samples.py -- do not edit by hand; "
             "re-run the script instead.",
             "# SoftTouch sample mesh %s: %d parts, %d triangles" %
             (os.path.basename(path), len(parts), sum(len(p.tris) for p in parts))]
    base = 1
    for p in parts:
        normals = [(0.0, 0.0, 0.0)] * len(p.verts)
        for a, b, c in p.tris:   # area-weighted smooth vertex normals
            n = cross(sub(p.verts[b], p.verts[a]), sub(p.verts[c], p.verts[a]))
            for i in (a, b, c):
                normals[i] = add(normals[i], n)
        lines.append("o " + p.name)
        lines += ["v %s %s %s" % tuple(fmt(c) for c in v) for v in p.verts]
        lines += ["vn %s %s %s" % tuple(fmt(c) for c in normalize(n)) for n in normals]
        lines += ["f %d//%d %d//%d %d//%d" % (a + base, a + base, b + base, b + base,
                                              c + base, c + base) for a, b, c in p.tris]
        base += len(p.verts)
    with open(path, "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")



# ------------------------------------------------------------ rigged guppy
GUPPY_JOINTS = [0.42, 0.28, 0.14, 0.0, -0.14, -0.28]   # x of each spine joint, head first
GUPPY_SWING = [0.03, 0.06, 0.09, 0.12, 0.16, 0.20]     # yaw amplitude of each joint, rad
GUPPY_LAG = 0.9                                          # phase lag per joint, rad: a wave to the tail
GUPPY_KEYS = 120                                         # keys over the one-second cycle


def guppy_skin(x):
    """(joint, weight) pairs of a vertex at x: between two joints it blends linearly
    from the one ahead to the one behind, so the body bends smoothly."""
    j = GUPPY_JOINTS
    if x >= j[0]:
        return [(0, 1.0)]
    for k in range(len(j) - 1):
        if x >= j[k + 1]:
            t = (x - j[k + 1]) / (j[k] - j[k + 1])
            return [(k, t), (k + 1, 1.0 - t)]
    return [(len(j) - 1, 1.0)]


def write_rigged_guppy(path):
    """The guppy as one skinned glTF mesh with a spine of joints (each the child of
    the one ahead of it) and a looping swim: every joint yaws about +Y, the swing
    growing and lagging toward the tail."""
    verts, tris, normals = [], [], []
    for part in guppy():
        base = len(verts)
        n = [(0.0, 0.0, 0.0)] * len(part.verts)
        for a, b, c in part.tris:
            fn = cross(sub(part.verts[b], part.verts[a]), sub(part.verts[c], part.verts[a]))
            for i in (a, b, c):
                n[i] = add(n[i], fn)
        verts += part.verts
        normals += [normalize(v) for v in n]
        tris += [(a + base, b + base, c + base) for a, b, c in part.tris]
    joints, weights = [], []
    for v in verts:
        skin = guppy_skin(v[0]) + [(0, 0.0)] * 2
        joints += [skin[0][0], skin[1][0], 0, 0]
        weights += [skin[0][1], skin[1][1], 0.0, 0.0]
    bin_ = bytearray()
    views, accessors = [], []

    def add_view(data, target=None):
        while len(bin_) % 4:
            bin_.append(0)
        view = {"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data)}
        if target:
            view["target"] = target
        bin_.extend(data)
        views.append(view)
        return len(views) - 1

    def add_accessor(fmt, values, count, kind, component, target=None, bounds=None):
        acc = {"bufferView": add_view(struct.pack("<%d%s" % (len(values), fmt), *values), target),
               "componentType": component, "count": count, "type": kind}
        if bounds:
            acc["min"], acc["max"] = bounds
        accessors.append(acc)
        return len(accessors) - 1

    flat = [c for v in verts for c in v]
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    position = add_accessor("f", flat, len(verts), "VEC3", 5126, 34962, (lo, hi))
    normal = add_accessor("f", [c for n in normals for c in n], len(verts), "VEC3", 5126, 34962)
    joint = add_accessor("B", joints, len(verts), "VEC4", 5121, 34962)
    weight = add_accessor("f", weights, len(verts), "VEC4", 5126, 34962)
    index = add_accessor("I", [i for t in tris for i in t], 3 * len(tris), "SCALAR", 5125, 34963)
    ibm = []
    for x in GUPPY_JOINTS:   # the inverse of each joint's bind transform, a translation to x
        ibm += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -x, 0, 0, 1]
    inverse_bind = add_accessor("f", ibm, len(GUPPY_JOINTS), "MAT4", 5126)
    times = [k / GUPPY_KEYS for k in range(GUPPY_KEYS + 1)]
    time = add_accessor("f", times, len(times), "SCALAR", 5126, bounds=([0.0], [1.0]))
    nodes = [{"name": "guppy", "mesh": 0, "skin": 0}]
    samplers, channels = [], []
    for k, x in enumerate(GUPPY_JOINTS):
        node = {"name": "spine%d" % k,
                "translation": [x if k == 0 else x - GUPPY_JOINTS[k - 1], 0.0, 0.0]}
        if k + 1 < len(GUPPY_JOINTS):
            node["children"] = [len(nodes) + 1]
        nodes.append(node)
        rotation = []
        for t in times:
            angle = GUPPY_SWING[k] * math.sin(2 * math.pi * t - GUPPY_LAG * k)
            rotation += [0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2)]
        out = add_accessor("f", rotation, len(times), "VEC4", 5126)
        samplers.append({"input": time, "output": out, "interpolation": "LINEAR"})
        channels.append({"sampler": k, "target": {"node": len(nodes) - 1, "path": "rotation"}})
    doc = {
        "asset": {"version": "2.0", "generator": "SoftTouch generate_samples.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1]}], "nodes": nodes,
        "meshes": [{"name": "guppy", "primitives": [{
            "attributes": {"POSITION": position, "NORMAL": normal, "JOINTS_0": joint, "WEIGHTS_0": weight},
            "indices": index, "mode": 4}]}],
        "skins": [{"joints": list(range(1, 1 + len(GUPPY_JOINTS))), "inverseBindMatrices": inverse_bind,
                   "skeleton": 1}],
        "animations": [{"name": "swim", "samplers": samplers, "channels": channels}],
        "buffers": [{"byteLength": len(bin_)}],
        "bufferViews": views, "accessors": accessors,
    }
    text = json.dumps(doc, separators=(",", ":"), sort_keys=True).encode()
    text += b" " * (-len(text) % 4)
    while len(bin_) % 4:
        bin_.append(0)
    glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(bin_))
    glb += struct.pack("<II", len(text), 0x4E4F534A) + text
    glb += struct.pack("<II", len(bin_), 0x004E4942) + bytes(bin_)
    with open(path, "wb") as f:
        f.write(glb)
    print("%-18s %5d triangles, %d joints, take 'swim' (1 s, %d keys)" %
          (os.path.basename(path), len(tris), len(GUPPY_JOINTS), GUPPY_KEYS + 1))

# ------------------------------------------------------------------ check
FILES = {  # name: (builder, (min_tris, max_tris), star?)
    "angelfish.obj": (angelfish, (5000, 8000), False),
    "demekin.obj": (demekin, (5000, 8000), False),
    "guppy.obj": (guppy, (5000, 8000), False),
    "star.obj": (star, (8640 * 0.97, 8640 * 1.03), True),
}


def check_obj(path, tri_range, is_star):
    """Reload an OBJ and verify it; returns a list of error strings."""
    verts, parts, errs = [], [], []
    for line in open(path):
        t = line.split()
        if not t:
            continue
        if t[0] == "v":
            verts.append(tuple(float(c) for c in t[1:4]))
        elif t[0] == "o":
            parts.append((t[1], []))
        elif t[0] == "f":
            if len(t) != 4:
                errs.append("non-triangle face")
            parts[-1][1].append(tuple(int(c.split("/")[0]) - 1 for c in t[1:]))
    if any(c != c for v in verts for c in v):
        errs.append("NaN vertex")
    ntri = sum(len(f) for _, f in parts)
    if not tri_range[0] <= ntri <= tri_range[1]:
        errs.append("triangle count %d out of range" % ntri)
    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]
    print("%s: %d triangles, %d vertices, bbox min (%.3f %.3f %.3f) max (%.3f %.3f %.3f)"
          % (os.path.basename(path), ntri, len(verts), *lo, *hi))
    ext = [h - l for h, l in zip(hi, lo)]
    if is_star:
        ok = (0.85 <= ext[0] <= 1.05 and 0.85 <= ext[1] <= 1.05 and 0.2 <= ext[2] <= 0.3
              and max(hi[0], hi[1], -lo[0], -lo[1]) <= 0.52)
    else:
        ok = 0.9 <= ext[0] <= 1.1 and abs(hi[0] + lo[0]) < 0.1
    if not ok:
        errs.append("bounding box out of spec")
    for name, faces in parts:
        if any(not 0 <= i < len(verts) for f in faces for i in f):
            errs.append("%s: invalid index" % name)
            continue
        edges, used, vol, minarea = set(), set(), 0.0, 1e9
        for a, b, c in faces:
            pa, pb, pc = verts[a], verts[b], verts[c]
            minarea = min(minarea, length(cross(sub(pb, pa), sub(pc, pa))) / 2)
            vol += dot(pa, cross(pb, pc)) / 6
            used.update((a, b, c))
            for e in ((a, b), (b, c), (c, a)):
                if e in edges:
                    errs.append("%s: edge %s used twice in same direction" % (name, e))
                edges.add(e)
        open_edges = sum(1 for a, b in edges if (b, a) not in edges)
        dupes = len(used) - len({verts[i] for i in used})
        print("  %-20s %5d tris  volume %+.6f  min area %.2e" % (name, len(faces), vol, minarea))
        if open_edges:
            errs.append("%s: %d open/non-manifold edges" % (name, open_edges))
        if minarea < 1e-9:
            errs.append("%s: degenerate triangle (area %.3g)" % (name, minarea))
        if dupes:
            errs.append("%s: %d duplicated vertex positions" % (name, dupes))
        if vol <= 0:
            errs.append("%s: non-positive signed volume (inward normals)" % name)
    return errs


def main():
    if "--check" in sys.argv[1:]:
        errs = []
        for fname, (_, rng, is_star) in FILES.items():
            errs += ["%s: %s" % (fname, e) for e in check_obj(os.path.join(HERE, fname), rng, is_star)]
        print("\n".join(errs) if errs else "all checks passed")
        return 1 if errs else 0
    for fname, (build, _, _) in FILES.items():
        parts = build()
        write_obj(os.path.join(HERE, fname), parts)
        print("%-14s %5d triangles (%s)" % (fname, sum(len(p.tris) for p in parts),
                                            ", ".join("%s %d" % (p.name, len(p.tris)) for p in parts)))
    write_rigged_guppy(os.path.join(HERE, "guppy-rigged.glb"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Can a per-cell calibration of the spring kinds make a cell of another shape reproduce the cubic cell's
solid? (docs/design/lattice.md, "The lattice's own error").

A cell's springs under a uniform strain store the energy of the solid C = sum over its springs of
share * coefficient * m m^T (core/body/network_elasticity.h), m = (n_u^2, n_v^2, n_w^2, ...) of each spring's
direction n. Central springs only reach C11, C22, C33 and C12 = C66, C13 = C55, C23 = C44 (Cauchy), so six
targets; the calibration has seven knobs, one scale per spring kind and direction (edges along u, v, w;
face diagonals in uv, uw, vw; body diagonals). For each cell shape this prints the closest non-negative
calibration to the cubic cell's C (exhaustive active sets, least squares) and how far it stays: 0 means the
shape can be calibrated, anything else needs springs of negative stiffness.

Usage: python3 scripts/cell-calibration.py
"""
import itertools
import math


def cell_elasticity(h, scale):
    """C11, C22, C33, C12, C13, C23 of one cell of spacings h, per unit of the coefficient (61/117 E)."""
    c = [0.0] * 6
    for a in range(3):  # four edges per axis, a quarter each
        c[a] += scale[a]
    for (a, b, k, pair) in [(0, 1, 3, 3), (0, 2, 4, 4), (1, 2, 5, 5)]:  # two faces x two diagonals, a half each
        length2 = h[a] ** 2 + h[b] ** 2
        na, nb = h[a] ** 2 / length2, h[b] ** 2 / length2
        c[a] += 2 * scale[k] * na * na
        c[b] += 2 * scale[k] * nb * nb
        c[pair] += 2 * scale[k] * na * nb
    length2 = sum(x * x for x in h)
    n = [x * x / length2 for x in h]
    for a in range(3):  # four body diagonals, whole
        c[a] += 4 * scale[6] * n[a] * n[a]
    c[3] += 4 * scale[6] * n[0] * n[1]
    c[4] += 4 * scale[6] * n[0] * n[2]
    c[5] += 4 * scale[6] * n[1] * n[2]
    return c


def least_squares(columns, target):
    """Least squares through the normal equations (Gauss-Jordan with pivoting); None when singular."""
    n = len(columns)
    m = [[sum(ci * cj for ci, cj in zip(columns[i], columns[j])) for j in range(n)] for i in range(n)]
    v = [sum(ci * t for ci, t in zip(columns[i], target)) for i in range(n)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        if abs(m[p][i]) < 1e-14:
            return None
        m[i], m[p], v[i], v[p] = m[p], m[i], v[p], v[i]
        for r in range(n):
            if r != i:
                f = m[r][i] / m[i][i]
                m[r] = [x - f * y for x, y in zip(m[r], m[i])]
                v[r] -= f * v[i]
    return [v[i] / m[i][i] for i in range(n)]


def closest_calibration(h, target):
    unit = [cell_elasticity(h, [1.0 if j == i else 0.0 for j in range(7)]) for i in range(7)]
    best = None
    for used in itertools.product([False, True], repeat=7):
        kinds = [i for i in range(7) if used[i]]
        if not kinds:
            continue
        x = least_squares([unit[i] for i in kinds], target)
        if x is None or min(x) < -1e-12:
            continue
        scale = [0.0] * 7
        for k, i in enumerate(kinds):
            scale[i] = x[k]
        miss = math.sqrt(sum((a - b) ** 2 for a, b in zip(cell_elasticity(h, scale), target)))
        if best is None or miss < best[0]:
            best = (miss, scale)
    return best


def main():
    target = cell_elasticity([1, 1, 1], [1.0] * 7)
    size = math.sqrt(sum(t * t for t in target))
    print("cell spacings (u, v, w) | closest miss, fraction of |C| | scales: edges u v w, faces uv uw vw, body")
    for h in ([1, 1, 1], [2 / 3, 1, 1], [1 / 3, 1, 1], [1 / 3, 1 / 3, 1], [1, 1, 0.2], [1, 1, 0.5]):
        miss, scale = closest_calibration(h, target)
        print("%-22s | %.3f | %s" % (" ".join("%.3g" % x for x in h), miss / size, " ".join("%.2f" % s for s in scale)))


if __name__ == "__main__":
    main()

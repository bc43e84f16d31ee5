"""The volume of OpenSCAD PR 6647's case grown by a ball: S = cube(10) minus the open ball
of radius 6 (both centred at the origin), and S + ball(r), from the exact distance to S
integrated on a fine grid (independent of octsolid: numpy only).

S is a cube with a spherical cavity breaking through each face in a round hole of radius
sqrt(11) (the cube's edges, at sqrt(50) > 6 from the centre, stay whole). Its boundary is
six faces minus their holes (the hole's rim included) and the sphere's patch inside the
cube, so the distance from a point outside S is the least of:

- each face region: the point projected on the face's plane and clamped to the square;
  when that lies inside the hole, the nearest point of the rim, in the plane, along
  the radius;
- the sphere patch: the radial projection 6 p / |p|, when it lies in the cube.

Grown by r: the points with distance < r. By symmetry one octant [0, 7]^3 is summed on a
grid of N^3 cell centres (midpoint rule) and multiplied by 8; N a multiple of 7
puts the faces on cell boundaries. Steiner's formula for the
whole cube grown by r, 1000 + 600 r + 30 pi r^2 + 4/3 pi r^3, bounds it from above.

    python offset_6647_volume.py [--radius 1] [--n 490]

Prints one JSON line: the volume of S (analytic), of S grown (grid) and the bound.
"""

import argparse
import json
import math

import numpy as np

HALF = 5.0  # the cube's half side
R = 6.0  # the sphere's radius
HOLE = math.sqrt(R * R - HALF * HALF)  # the holes' radius on the faces


def distance(x, y, z):
    """Distance from points with coordinates >= 0 (one octant) to S (0 inside S)."""
    p = np.stack((x, y, z))
    rho = np.sqrt(x * x + y * y + z * z)
    inside_cube = (x <= HALF) & (y <= HALF) & (z <= HALF)
    inside_s = inside_cube & (rho >= R)
    best = np.full(x.shape, np.inf)
    # The sphere patch: the radial projection, when it lies in the cube.
    with np.errstate(divide="ignore", invalid="ignore"):
        q = p * (R / np.maximum(rho, 1e-300))
    valid = np.all(q <= HALF, axis=0)
    best = np.where(valid, np.abs(rho - R), best)
    # The face regions (in the octant only the faces at +HALF are nearest).
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        u = np.minimum(p[others[0]], HALF)
        v = np.minimum(p[others[1]], HALF)
        r_in_plane = np.sqrt(u * u + v * v)
        in_hole = r_in_plane < HOLE
        # Inside the hole: the rim along the in-plane radius.
        scale = np.where(in_hole, HOLE / np.maximum(r_in_plane, 1e-300), 1.0)
        u, v = u * scale, v * scale
        d = np.sqrt((p[axis] - HALF) ** 2 + (p[others[0]] - u) ** 2 + (p[others[1]] - v) ** 2)
        best = np.minimum(best, d)
    return np.where(inside_s, 0.0, best)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--radius", type=float, default=1.0)
    ap.add_argument("--n", type=int, default=490)
    a = ap.parse_args()
    h = 7.0 / a.n
    c = (np.arange(a.n) + 0.5) * h
    count = 0
    for i in range(a.n):
        y, z = np.meshgrid(c, c, indexing="ij")
        x = np.full_like(y, c[i])
        count += int(np.count_nonzero(distance(x, y, z) < a.radius))
    grown = 8 * count * h**3
    cap = math.pi * (R - HALF) ** 2 * (3 * R - (R - HALF)) / 3  # one cap of the ball past a face
    solid = 1000 - (4 / 3 * math.pi * R**3 - 6 * cap)
    r = a.radius
    bound = 1000 + 600 * r + 30 * math.pi * r * r + 4 / 3 * math.pi * r**3
    print(json.dumps({"radius": r, "n": a.n, "solid": round(solid, 4), "grown": round(grown, 4), "cube_grown_bound": round(bound, 4)}))


if __name__ == "__main__":
    main()

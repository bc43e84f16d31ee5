"""The exact volume of offset_depth13.toml's bored ball grown by a ball of radius r
(independent of octsolid: numpy only), to check `octsolid offset big.octs --by r`.

The solid B is a ball of radius R = 0.35 minus the infinite-in-effect cylinder of radius
rho = 0.12 about z (its height, 1, reaches past the ball): a napkin ring of height
2 h0, h0 = sqrt(R^2 - rho^2), volume pi/6 (2 h0)^3. B is a solid of revolution, so a
point's distance to it is the distance, in the point's meridian half-plane (s, z), to
the profile P = {s >= rho, s^2 + z^2 <= R^2}, which is convex. Grown by r, P becomes
P + disk(r): bounded outside by the circle of radius R + r (where the outward normal
points between the rim corners (rho, +-h0)), around each corner by the circle of
radius r about it, and inside by the line s = rho - r for |z| <= h0. So at height z
the grown body is the ring s_min(z) <= s <= s_max(z), and (Pappus, slice by slice)

    V(r) = integral over z of pi (s_max(z)^2 - s_min(z)^2),

summed here piece by piece (the corner pieces in the angle about the corner, so the
square roots' ends cost no accuracy) by the midpoint rule.

    python offset_depth13_volume.py [--radius 0.0027] [--measured V]

Prints one JSON line: B's volume (analytic), B grown, and when --measured is given
its relative difference from the grown volume.
"""

import argparse
import json
import math

import numpy as np

R = 0.35  # the ball's radius
RHO = 0.12  # the bore's radius
H0 = math.sqrt(R * R - RHO * RHO)  # the rims' height


def midpoint(f, a, b, n=2_000_000):
    """The midpoint rule of f over [a, b] on n cells."""
    x = a + (np.arange(n) + 0.5) * (b - a) / n
    return float(np.sum(f(x)) * (b - a) / n)


def grown_volume(r):
    """V(r) of the module doc (both halves z > 0 and z < 0: twice the upper)."""
    if r == 0:
        return math.pi / 6 * (2 * H0) ** 3
    top = H0 + r * H0 / R  # where the outer circle meets the corner's circle
    outer = lambda z: (R + r) ** 2 - z * z  # noqa: E731
    # 0 <= z <= h0: the outer circle to the line s = rho - r.
    a = midpoint(lambda z: math.pi * (outer(z) - (RHO - r) ** 2), 0.0, H0)
    # Above the rim, z = h0 + r sin(t): inside, the corner's circle s = rho - r cos(t);
    # outside, the outer circle up to `top`, then the corner's circle s = rho + r cos(t).
    t_top = math.asin(H0 / R)  # r sin(t_top) = top - h0

    def ring_low(t):  # h0 <= z <= top, dz = r cos(t) dt
        z = H0 + r * np.sin(t)
        return math.pi * (outer(z) - (RHO - r * np.cos(t)) ** 2) * r * np.cos(t)

    def ring_high(t):  # top <= z <= h0 + r: (rho + c)^2 - (rho - c)^2 = 4 rho c
        c = r * np.cos(t)
        return math.pi * 4 * RHO * c * r * np.cos(t)

    b = midpoint(ring_low, 0.0, t_top)
    c = midpoint(ring_high, t_top, math.pi / 2)
    return 2 * (a + b + c)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--radius", type=float, default=0.0027)
    parser.add_argument("--measured", type=float)
    args = parser.parse_args()
    out = {
        "solid": grown_volume(0.0),
        "solid_check": midpoint(lambda z: math.pi * (R * R - z * z - RHO * RHO), 0.0, H0) * 2,
        "radius": args.radius,
        "grown": grown_volume(args.radius),
    }
    if args.measured is not None:
        out["measured"] = args.measured
        out["relative"] = args.measured / out["grown"] - 1
    print(json.dumps(out))


if __name__ == "__main__":
    main()

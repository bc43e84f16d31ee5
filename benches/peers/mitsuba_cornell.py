"""Radiosity against a path tracer: Mitsuba 3's built-in Cornell box, region by region.

Mitsuba's reference (`render`): `mi.cornell_box()` as it ships (its geometry, camera,
light and RGB reflectances), variant `scalar_rgb`, its path tracer with `max_depth`
raised to 64 (Russian roulette from depth 5, as Mitsuba does by default: unbiased),
2048 samples a pixel, written as linear float32 EXR. Two views: Mitsuba's own camera
(`front`, 256 x 256) and one looking straight down on the floor from just under the
ceiling (`top`, 128 x 128, 65 degrees), because the tall block's top lies above the
front camera's eye, and the blocks hide most of the floor's back from it.

The regions (`compare`): every pixel's primary ray is intersected with Mitsuba's scene
(the pixel centre, through the sensor itself), and a region is the pixels whose ray
first meets a given shape, on a face of a given normal and inside a given box of world
space; each mask is then shrunk by two pixels so that no pixel straddles an edge (the
two renderers filter pixels differently). The same masks are applied to Mitsuba's
pictures and to octsolid's (rendered from the same camera at the same size), and the
mean linear radiance of each region is compared channel by channel.

The nine regions: the back wall's top and bottom, the floor's front and back, the
ceiling, and both blocks' fronts (the face towards the camera) and tops.

The colour-bleeding ratio: the back wall's red/green ratio in a strip next to the red
wall (x in -0.95..-0.75) over the same ratio in the mirrored strip next to the green
wall (x in 0.75..0.95), both at mid height (y in -0.3..0.3). Light reflected off the red
wall reddens the strip beside it, off the green wall greens the other, so the ratio is
above 1 by how much the walls bleed; a renderer that loses interreflected light brings
it towards 1.

    mitsuba_cornell.py render  --out DIR [--spp 2048] [--views front,top]
    mitsuba_cornell.py params  (what decides the reference: views, cameras, depth, Mitsuba)
    mitsuba_cornell.py compare --out DIR --octsolid-front F.exr --octsolid-top T.exr [--json J]

`mitsuba_cornell.sh` installs Mitsuba into the peers venv, renders the reference (kept
in DIR while the script and Mitsuba's version are the same), renders the bundled
`scenes/cornell-mitsuba.toml` with octsolid, and prints and saves the comparison.
"""

import argparse
import json
import os
import sys
import time

import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")

FRONT_SIZE = 256
TOP_SIZE = 128
# The top view: from just under the ceiling (and the light), straight down on the floor.
TOP_EYE = (0.0, 0.95, 0.0)
TOP_TARGET = (0.0, -1.0, 0.0)
TOP_UP = (0.0, 0.0, -1.0)
TOP_FOV = 65.0
MAX_DEPTH = 64


def scene_dict(view, spp):
    """Mitsuba's Cornell box with the path tracer's depth raised and the view's sensor."""
    d = mi.cornell_box()
    d["integrator"] = {"type": "path", "max_depth": MAX_DEPTH}
    sensor = d["sensor"]
    sensor["sampler"] = {"type": "independent", "sample_count": spp}
    if view == "top":
        sensor["to_world"] = mi.ScalarTransform4f().look_at(origin=TOP_EYE, target=TOP_TARGET, up=TOP_UP)
        sensor["fov"] = TOP_FOV
        sensor["film"]["width"] = sensor["film"]["height"] = TOP_SIZE
    else:
        sensor["film"]["width"] = sensor["film"]["height"] = FRONT_SIZE
    return d


def render(out, spp, views):
    os.makedirs(out, exist_ok=True)
    for view in views:
        scene = mi.load_dict(scene_dict(view, spp))
        start = time.time()
        image = mi.render(scene)
        seconds = time.time() - start
        path = os.path.join(out, f"mitsuba-{view}.exr")
        mi.Bitmap(image).write(path)
        print(json.dumps({"view": view, "spp": spp, "seconds": round(seconds, 1), "exr": path}), flush=True)


def first_hits(view):
    """Per pixel (row, column): the point where the centre's ray first meets the scene
    and the normal there (NaN where it meets nothing)."""
    scene = mi.load_dict(scene_dict(view, 1))
    sensor = scene.sensors()[0]
    size = sensor.film().crop_size()
    w, h = int(size[0]), int(size[1])
    points = np.full((h, w, 3), np.nan)
    normals = np.full((h, w, 3), np.nan)
    for row in range(h):
        for col in range(w):
            ray, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f((col + 0.5) / w, (row + 0.5) / h), mi.Point2f(0.5, 0.5))
            si = scene.ray_intersect(ray)
            if not si.is_valid():
                continue
            points[row, col] = [si.p[0], si.p[1], si.p[2]]
            normals[row, col] = [si.n[0], si.n[1], si.n[2]]
    return points, normals


def params():
    """Everything that decides the reference pictures but the sample count."""
    return {"mitsuba": mi.__version__, "max_depth": MAX_DEPTH, "front": FRONT_SIZE, "top": [TOP_SIZE, TOP_EYE,
            TOP_TARGET, TOP_UP, TOP_FOV]}


def shrink(mask, pixels=2):
    """The mask less every pixel within `pixels` (4-neighbour steps) of its outside."""
    m = mask.copy()
    for _ in range(pixels):
        inner = m.copy()
        inner[1:, :] &= m[:-1, :]
        inner[:-1, :] &= m[1:, :]
        inner[:, 1:] &= m[:, :-1]
        inner[:, :-1] &= m[:, 1:]
        inner[0, :] = inner[-1, :] = False
        inner[:, 0] = inner[:, -1] = False
        m = inner
    return m


def region(hits, normal, box):
    """Pixels whose first hit lies on a face whose normal is within ~25 degrees of
    `normal`, inside the world box `box` ((xmin, xmax), (ymin, ymax), (zmin, zmax)),
    shrunk. (Mitsuba merges the shapes of one material into one mesh, so the faces are
    told apart by their normals and places, not by shape.)"""
    points, normals = hits
    with np.errstate(invalid="ignore"):
        m = normals @ np.asarray(normal, dtype=float) > 0.9
        for axis, (lo, hi) in enumerate(box):
            m &= (points[..., axis] >= lo) & (points[..., axis] <= hi)
    return shrink(m)


ANY = (-10.0, 10.0)
ON_LOW = (-1.01, -0.99)  # on the plane -1
SHORT = ((0.0, 0.75), (-0.99, -0.41), (0.0, 0.8))  # the short block's sides
TALL = ((-0.75, 0.1), (-0.99, 0.2), (-0.7, 0.15))  # the tall block's sides
SHORT_TOP = ((0.0, 0.75), (-0.41, -0.39), (0.0, 0.8))
TALL_TOP = ((-0.75, 0.1), (0.2, 0.22), (-0.7, 0.15))
# name: (view, face normal, world box)
REGIONS = {
    "back wall top": ("front", (0, 0, 1), ((-0.6, 0.6), (0.4, 0.9), ON_LOW)),
    "back wall bottom": ("front", (0, 0, 1), ((-0.6, 0.6), (-0.8, -0.4), ON_LOW)),
    "floor front": ("top", (0, 1, 0), ((-0.9, 0.9), ON_LOW, (0.5, 0.95))),
    "floor back": ("top", (0, 1, 0), ((-0.9, 0.9), ON_LOW, (-0.95, -0.6))),
    "ceiling": ("front", (0, -1, 0), ((-0.9, 0.9), (0.995, 1.01), (-0.9, 0.9))),  # not the light (y = 0.99)
    "short block front": ("front", (-0.292, 0, 0.956), SHORT),
    "short block top": ("top", (0, 1, 0), SHORT_TOP),
    "tall block front": ("front", (0.313, 0, 0.950), TALL),
    "tall block top": ("top", (0, 1, 0), TALL_TOP),
}
BLEED_RED_SIDE = ("front", (0, 0, 1), ((-0.95, -0.75), (-0.3, 0.3), ON_LOW))
BLEED_GREEN_SIDE = ("front", (0, 0, 1), ((0.75, 0.95), (-0.3, 0.3), ON_LOW))


def read_exr(path):
    image = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False))
    return image[..., :3].astype(float)


def measure(images, masks):
    """Mean RGB of each region, and the bleeding ratio."""
    out = {}
    for name, (view, mask) in masks.items():
        pixels = images[view][mask]
        out[name] = pixels.mean(axis=0).tolist()
    return out


def bleeding(rgb):
    (r1, g1, _), (r2, g2, _) = rgb["bleed red side"], rgb["bleed green side"]
    return (r1 / g1) / (r2 / g2)


def compare(args):
    hits = {view: first_hits(view) for view in ("front", "top")}
    masks = {name: (spec[0], region(hits[spec[0]], *spec[1:])) for name, spec in REGIONS.items()}
    masks["bleed red side"] = (BLEED_RED_SIDE[0], region(hits["front"], *BLEED_RED_SIDE[1:]))
    masks["bleed green side"] = (BLEED_GREEN_SIDE[0], region(hits["front"], *BLEED_GREEN_SIDE[1:]))
    for name, (_, m) in masks.items():
        if m.sum() < 20:
            sys.exit(f"region {name!r} has only {m.sum()} pixels")
    mitsuba = {v: read_exr(os.path.join(args.out, f"mitsuba-{v}.exr")) for v in ("front", "top")}
    ours = {"front": read_exr(args.octsolid_front), "top": read_exr(args.octsolid_top)}
    for v in ("front", "top"):
        if ours[v].shape != mitsuba[v].shape:
            sys.exit(f"octsolid's {v} picture is {ours[v].shape[1]}x{ours[v].shape[0]}, Mitsuba's "
                     f"{mitsuba[v].shape[1]}x{mitsuba[v].shape[0]}")
    ref, got = measure(mitsuba, masks), measure(ours, masks)
    rows, worst = [], 0.0
    lines = ["| region | pixels | Mitsuba (R, G, B) | octsolid (R, G, B) | difference (R, G, B) |",
             "|---|---:|---|---|---|"]
    for name in REGIONS:
        diff = [(g - r) / r for g, r in zip(got[name], ref[name])]
        worst = max(worst, max(abs(d) for d in diff))
        rows.append({"region": name, "pixels": int(masks[name][1].sum()), "mitsuba": ref[name],
                     "octsolid": got[name], "difference": diff})
        fmt = lambda c: ", ".join(f"{x:.4f}" for x in c)
        lines.append(f"| {name} | {int(masks[name][1].sum())} | {fmt(ref[name])} | {fmt(got[name])} | "
                     + ", ".join(f"{100 * d:+.1f}%" for d in diff) + " |")
    bleed_ref, bleed_got = bleeding(ref), bleeding(got)
    bleed_diff = (bleed_got - bleed_ref) / bleed_ref
    lines.append(f"| bleeding ratio | | {bleed_ref:.3f} | {bleed_got:.3f} | {100 * bleed_diff:+.1f}% |")
    lines.append("")
    lines.append(f"worst region channel: {100 * worst:.1f}%; bleeding ratio: {100 * bleed_diff:+.1f}%")
    text = "\n".join(lines)
    print(text)
    result = {"regions": rows, "bleeding": {"mitsuba": bleed_ref, "octsolid": bleed_got, "difference": bleed_diff},
              "worst": worst, "mitsuba_version": mi.__version__}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    if args.masks:
        # Both pictures side by side per view, regions outlined, tone-mapped for the eye.
        from PIL import Image
        for v in ("front", "top"):
            tiles = []
            for img in (mitsuba[v], ours[v]):
                rgb = np.clip(img / (1 + img), 0, 1) ** (1 / 2.2)
                for name, (view, m) in masks.items():
                    if view == v:
                        edge = m & ~shrink(m, 1)
                        rgb[edge] = [1, 0, 1]
                tiles.append((rgb * 255).astype(np.uint8))
            Image.fromarray(np.concatenate(tiles, axis=1)).save(os.path.join(args.out, f"side-by-side-{v}.png"))
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render")
    r.add_argument("--out", required=True)
    r.add_argument("--spp", type=int, default=2048)
    r.add_argument("--views", default="front,top")
    sub.add_parser("params")
    c = sub.add_parser("compare")
    c.add_argument("--out", required=True)
    c.add_argument("--octsolid-front", required=True)
    c.add_argument("--octsolid-top", required=True)
    c.add_argument("--json")
    c.add_argument("--masks", action="store_true", help="also write side-by-side PNGs with the regions outlined")
    args = p.parse_args()
    if args.command == "render":
        render(args.out, args.spp, args.views.split(","))
    elif args.command == "params":
        print(json.dumps(params()))
    else:
        compare(args)


if __name__ == "__main__":
    main()

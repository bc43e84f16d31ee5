"""A turntable of renders: the classic part seen from eight directions around its up
axis, each frame a numpy array from octsolid.render, laid side by side into one
contact sheet, written as a PNG.

Run: python examples/python/turntable.py [OUT_FOLDER] [--depth D] [--frames N]
(writes turntable.png into OUT_FOLDER, default example-output/python/).
"""

import argparse
import pathlib

import numpy as np

import octsolid as o
from classic_part import classic_part


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="example-output/python")
    parser.add_argument("--depth", type=int, default=7)
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--size", type=int, default=160)
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    solid = o.voxelize(classic_part(), args.depth, domain=((-1, -1, -1), 2.0))
    frames = [
        o.render(solid, size=(args.size, args.size), azimuth=360 * i / args.frames, elevation=25)
        for i in range(args.frames)
    ]
    sheet = np.concatenate(frames, axis=1)
    o.write_png(out / "turntable.png", sheet)
    print(f"{args.frames} frames of {args.size}x{args.size}; wrote {out / 'turntable.png'} {sheet.shape[1]}x{sheet.shape[0]}")


if __name__ == "__main__":
    main()

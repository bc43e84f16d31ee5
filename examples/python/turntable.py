"""A turntable of renders: the classic part seen from eight directions around its up
axis, each frame a numpy array from octsolid.render, laid side by side into one
contact sheet, written as a PNG.

Run: python examples/python/turntable.py [OUT_FOLDER] [--depth D] [--frames N]
(writes turntable.png into OUT_FOLDER, default example-output/python/).
"""

import numpy as np

import octsolid as o
from classic_part import classic_part
from command_line import command_line


def main():
    args = command_line(__doc__, depth=7, frames=8, size=160)
    out = args.out

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

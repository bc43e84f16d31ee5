"""A turntable of renders: the classic part seen from eight directions around its up
axis, each frame a numpy array from octsolid.render, laid side by side into one
contact sheet, written as a PNG with the standard library's zlib.

Run: python examples/python/turntable.py [OUT_FOLDER] [--depth D] [--frames N]
(writes turntable.png into OUT_FOLDER, default example-output/python/).
"""

import argparse
import pathlib
import struct
import zlib

import numpy as np

import octsolid as o
from classic_part import classic_part


def write_png(path, rgb):
    """An (h, w, 3) uint8 array as an 8-bit RGB PNG (no filter), standard library only."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    header = struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")
    pathlib.Path(path).write_bytes(png)


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
    write_png(out / "turntable.png", sheet)
    print(f"{args.frames} frames of {args.size}x{args.size}; wrote {out / 'turntable.png'} {sheet.shape[1]}x{sheet.shape[0]}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""How alike two pictures of one scene are (octsolid's and a peer's): mean absolute
difference of the 8-bit sRGB values, the share of pixels that differ by more than
16 levels in some channel, and optionally a picture of the difference (x4).

    target/peers-venv/bin/python benches/peers/compare_images.py A.png B.png [--diff D.png]
"""

import argparse
import json

import numpy as np
from PIL import Image


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--diff", help="write |a - b| x 4 here")
    args = ap.parse_args()
    a = np.asarray(Image.open(args.a).convert("RGB"), dtype=np.int16)
    b = np.asarray(Image.open(args.b).convert("RGB"), dtype=np.int16)
    if a.shape != b.shape:
        raise SystemExit(f"compare_images: sizes differ: {a.shape[1]}x{a.shape[0]} and {b.shape[1]}x{b.shape[0]}")
    d = np.abs(a - b)
    if args.diff:
        Image.fromarray(np.clip(4 * d, 0, 255).astype(np.uint8)).save(args.diff)
    print(json.dumps({
        "a": args.a,
        "b": args.b,
        "mean_abs_diff": [round(float(x), 3) for x in d.reshape(-1, 3).mean(axis=0)],
        "pixels_over_16": round(float((d.max(axis=2) > 16).mean()), 5),
        "mean_a": [round(float(x), 2) for x in a.reshape(-1, 3).mean(axis=0)],
        "mean_b": [round(float(x), 2) for x in b.reshape(-1, 3).mean(axis=0)],
    }))


if __name__ == "__main__":
    main()

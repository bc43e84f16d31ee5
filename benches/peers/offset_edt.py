"""A solid grown by D voxels by the `edt` package (PyPI `edt`, Multi-Label Anisotropic
Euclidean Distance Transform 3D): the dense exact Euclidean distance transform of the
solid's complement, thresholded. The peer of `octsolid offset IN --voxels D`.

Whole process, as a user would run it: read a `.binvox` (the solid as octsolid exports
it, `octsolid convert part.oct part.binvox`: a cubic grid of 2^depth), unpack its runs
into a dense numpy bool array, `edt.edt` of the complement on one core (`parallel=1`):
each empty voxel's distance from its centre to the nearest solid voxel's centre, keep
the voxels with distance < D + 1/2, write the grown grid as a `.binvox` with the same
header.

Departure from octsolid's rule: octsolid measures from a voxel's centre to the nearest
solid voxel as a cube (`src/octree/offset/mod.rs`); `edt` measures centre to centre.
`d_cube <= d_centre - 1/2` with equality along the axes, so `d_centre < D + 1/2` is the
cube rule along the axes and a little thinner elsewhere (the counts are printed; the
work, one dense transform, is the same either way).

    python offset_edt.py IN.binvox --voxels D -o OUT.binvox

Prints one JSON line: the times (read, transform, threshold, write), the voxel counts
before and after, and the package's version.
"""

import argparse
import json
import os
import sys
import time
from importlib.metadata import version

import edt
import numpy as np


def read_binvox(path):
    """The header lines (bytes, up to and including `data`) and the dense grid, in the
    file's own order (x slowest, then z, y fastest)."""
    with open(path, "rb") as f:
        raw = f.read()
    header = []
    pos = 0
    dims = None
    while True:
        end = raw.index(b"\n", pos)
        line = raw[pos : end + 1]
        pos = end + 1
        header.append(line)
        words = line.split()
        if words and words[0].lower() == b"dim":
            dims = tuple(int(w) for w in words[1:4])
        if words and words[0].lower() == b"data":
            break
    if dims is None:
        sys.exit(f"{path}: no dim line in the header")
    pairs = np.frombuffer(raw, dtype=np.uint8, offset=pos)
    if pairs.size % 2:
        sys.exit(f"{path}: odd number of bytes after the header")
    values = pairs[0::2].astype(bool)
    counts = pairs[1::2].astype(np.int64)
    grid = np.repeat(values, counts)
    if grid.size != dims[0] * dims[1] * dims[2]:
        sys.exit(f"{path}: runs cover {grid.size} voxels, dims {dims}")
    return b"".join(header), grid.reshape(dims)


def write_binvox(path, header, grid):
    """The grid as runs of at most 255 (value, count) pairs after `header`."""
    flat = grid.reshape(-1).view(np.uint8)
    starts = np.concatenate(([0], np.flatnonzero(np.diff(flat)) + 1))
    lengths = np.diff(np.concatenate((starts, [flat.size])))
    # Split each run into pieces of at most 255.
    pieces = (lengths + 254) // 255
    values = np.repeat(flat[starts], pieces)
    counts = np.full(values.size, 255, dtype=np.int64)
    last = np.cumsum(pieces) - 1
    counts[last] = lengths - 255 * (pieces - 1)
    out = np.empty(2 * values.size, dtype=np.uint8)
    out[0::2] = values
    out[1::2] = counts
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header)
        f.write(out.tobytes())
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("input")
    ap.add_argument("--voxels", type=float, required=True)
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--parallel", type=int, default=1)
    a = ap.parse_args()
    t0 = time.perf_counter()
    header, solid = read_binvox(a.input)
    t1 = time.perf_counter()
    # Distance of every empty voxel to the nearest solid one (zero on the solid).
    dist = edt.edt(~solid, parallel=a.parallel)
    t2 = time.perf_counter()
    grown = dist < a.voxels + 0.5
    t3 = time.perf_counter()
    write_binvox(a.output, header, grown)
    t4 = time.perf_counter()
    print(
        json.dumps(
            {
                "version": version("edt"),
                "dims": list(solid.shape),
                "voxels_in": int(solid.sum()),
                "voxels_out": int(grown.sum()),
                "read_s": round(t1 - t0, 3),
                "edt_s": round(t2 - t1, 3),
                "threshold_s": round(t3 - t2, 3),
                "write_s": round(t4 - t3, 3),
            }
        )
    )


if __name__ == "__main__":
    main()

"""What the tests share: the `octsolid` command they compare against (the binary in
target/release, or OCTSOLID_BIN), a PNG reader (standard library and numpy only), and
the repository's folders."""

import json
import os
import pathlib
import struct
import subprocess
import zlib

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples" / "python"
MODELS = REPO / "models"
SCENES = REPO / "scenes"


def binary():
    path = pathlib.Path(os.environ.get("OCTSOLID_BIN", REPO / "target" / "release" / "octsolid"))
    if not path.is_file():
        pytest.fail(f"the octsolid binary is not at {path}: build it (cargo build --release -p octsolid-cli)")
    return path


def cli(*args, cwd=None):
    """Runs `octsolid ARGS...`, failing the test when it fails; returns its stdout."""
    done = subprocess.run([str(binary()), *map(str, args)], capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, f"octsolid {' '.join(map(str, args))} failed:\n{done.stderr}"
    return done.stdout


def cli_info(path):
    """`octsolid info PATH --json` as a dict."""
    return json.loads(cli("info", path, "--json").strip().splitlines()[-1])


def summary_value(stdout, key):
    """The first number on the summary line `KEY ...` (nodes, voxels, volume)."""
    for line in stdout.splitlines():
        words = line.split()
        if words and words[0] == key:
            return float(words[1])
    raise AssertionError(f"no {key!r} line in:\n{stdout}")


def read_png(path):
    """An 8-bit RGB PNG's pixels as an (h, w, 3) uint8 array (every filter type)."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind, body = data[pos + 4 : pos + 8], data[pos + 8 : pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, bits, colour, _, _, interlace = header
    assert (bits, colour, interlace) == (8, 2, 0), f"{path}: only 8-bit RGB, not interlaced"
    raw = zlib.decompress(idat)
    stride, bpp = 3 * w, 3
    out = np.zeros((h, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=y * (stride + 1) + 1).astype(np.int32)
        row = np.zeros(stride, dtype=np.int32)
        for x in range(stride):
            a = row[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 0:
                p = 0
            elif f == 1:
                p = a
            elif f == 2:
                p = b
            elif f == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            row[x] = (line[x] + p) & 0xFF
        out[y] = row
        prev = row
    return out.reshape(h, w, 3).astype(np.uint8)

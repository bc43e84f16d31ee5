"""Pictures against `octsolid render`, bit for bit: a solid (saved, then rendered by
the CLI), a scene file, a solid file, with camera and option flags; HDR against the
8-bit picture; the notebook PNG."""

import numpy as np
import pytest

import octsolid as o
from conftest import cli, read_png

SCENE = """
[image]
size = [80, 60]
samples = 1

[domain]
min = [-1.5, -1.5, -1.5]
edge = 3.0
depth = 6

[[solid]]
name = "ball"
material = { color = [0.8, 0.3, 0.2] }
shape = { sphere = { center = [0, 0, 0.2], radius = 0.8 } }

[[solid]]
name = "floor"
shape = { box = { center = [0, 0, -1.0], size = [2.8, 2.8, 0.2] } }
"""


def test_a_solid_renders_as_the_cli_renders_its_file(tmp_path):
    solid = o.voxelize(o.Torus((0, 0, 0), "z", 0.7, 0.25) | o.Sphere((0, 0, 0), 0.4), 6)
    path = tmp_path / "ring.oct"
    solid.save(path)
    picture = o.render(solid, size=(96, 72))
    assert picture.shape == (72, 96, 3) and picture.dtype == np.uint8
    cli("render", path, "-o", tmp_path / "cli.png", "--size", "96x72")
    assert np.array_equal(picture, read_png(tmp_path / "cli.png"))
    assert np.array_equal(o.render(path, size=(96, 72)), picture)


def test_camera_and_options_match_the_flags(tmp_path):
    path = tmp_path / "part.oct"
    o.voxelize(o.Box((0, 0, 0), (1, 0.6, 0.4)) - o.Cylinder((0, 0, 0), "z", 0.2, 1), 6).save(path)
    cases = [
        (dict(view="top", spp=1), ["--view", "top", "--spp", "1"]),
        (dict(eye=(2, -3, 1.5), target=(0, 0, 0), fov=30), ["--eye", "2,-3,1.5", "--target", "0,0,0", "--fov", "30"]),
        (dict(method="trace", spp=1), ["--method", "trace", "--spp", "1"]),
        (dict(method="zbuffer", azimuth=40, elevation=20), ["--method", "zbuffer", "--azimuth", "40", "--elevation", "20"]),
    ]
    for kwargs, flags in cases:
        png = tmp_path / "cli.png"
        cli("render", path, "-o", png, "--size", "64x48", *flags)
        assert np.array_equal(o.render(path, size=(64, 48), **kwargs), read_png(png)), kwargs


def test_a_scene_file_renders_as_the_cli_renders_it(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(SCENE)
    cli("render", scene, "-o", tmp_path / "cli.png", "--no-cache")
    picture = o.render(str(scene), cache=False)
    assert picture.shape == (60, 80, 3)
    assert np.array_equal(picture, read_png(tmp_path / "cli.png"))


def test_hdr_is_the_linear_radiance_of_the_picture():
    solid = o.voxelize(o.Sphere((0, 0, 0), 1), 5)
    srgb = o.render(solid, size=(40, 30))
    hdr = o.render(solid, size=(40, 30), hdr=True)
    assert hdr.dtype == np.float32 and hdr.shape == (30, 40, 3)
    # The sRGB transfer function of the radiance, independent of the library.
    c = np.clip(hdr.astype(np.float64), 0, 1)
    encoded = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    assert np.abs(np.round(encoded * 255) - srgb).max() <= 1


def test_repr_png_is_a_png_of_the_solid():
    solid = o.voxelize(o.Box((0, 0, 0), 1), 4)
    png = solid._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(o.ArgumentError, match="empty"):
        (solid - solid)._repr_png_()


def test_pictures_write_the_cli_png_bytes(tmp_path):
    path = tmp_path / "part.oct"
    solid = o.voxelize(o.Sphere((0, 0, 0), 1) - o.Box((0.5, 0.5, 0.5), 1), 6)
    solid.save(path)
    (tmp_path / "py").mkdir()
    o.write_png(tmp_path / "py" / "r.png", o.render(solid, size=(64, 48)))
    cli("render", path, "-o", tmp_path / "r.png", "--size", "64x48")
    assert (tmp_path / "py" / "r.png").read_bytes() == (tmp_path / "r.png").read_bytes()
    for axis, at in [("z", 0.25), ("x", -0.5)]:
        o.write_png(tmp_path / "py" / "s.png", solid.slice(axis, at, 100))
        cli("slice", path, "--axis", axis, "--at", at, "--size", 100, "-o", tmp_path / "s.png")
        assert (tmp_path / "py" / "s.png").read_bytes() == (tmp_path / "s.png").read_bytes()
        written = solid.save_slice(tmp_path / "py" / "direct.png", axis, at, 100)
        assert (tmp_path / "py" / "direct.png").read_bytes() == (tmp_path / "s.png").read_bytes()
        assert written == (tmp_path / "s.png").stat().st_size
    middle = solid.slice()
    assert middle.shape == (768, 768, 3)

"""octsolid: solid modeling and rendering on linear octrees.

Shapes (``Sphere``, ``Box``, ``Cylinder``, ... combined with ``| & - ^ ~``) are
voxelized into a ``Solid``, which combines, measures, moves, offsets, saves, exports
and renders; meshes come in as numpy arrays (``from_mesh``) or files (``load_mesh``),
solids as files (``load``). Every call is the Rust library's, with the GIL released
while it works, and gives what the ``octsolid`` command gives on the same input.
"""

from ._octsolid import (
    Box,
    Cone,
    Cylinder,
    Ellipsoid,
    HalfSpace,
    Shape,
    Solid,
    Sphere,
    Torus,
    from_mesh,
    linear_array,
    load,
    load_mesh,
    polar_array,
    radiosity,
    render,
    voxelize,
    write_png,
)
from .errors import ArgumentError, BudgetError, ClippedWarning, Error, FileError, FormatError, InputWarning

__all__ = [
    "ArgumentError",
    "Box",
    "BudgetError",
    "ClippedWarning",
    "Cone",
    "Cylinder",
    "Ellipsoid",
    "Error",
    "FileError",
    "FormatError",
    "HalfSpace",
    "InputWarning",
    "Shape",
    "Solid",
    "Sphere",
    "Torus",
    "from_mesh",
    "linear_array",
    "load",
    "load_mesh",
    "polar_array",
    "radiosity",
    "render",
    "voxelize",
    "write_png",
]


def _to_trimesh(self, surface="smooth", tolerance=0.0, normal_tolerance=None):
    """The boundary as a ``trimesh.Trimesh`` (needs trimesh): ``Solid.mesh``'s arrays."""
    try:
        import trimesh
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("Solid.to_trimesh needs trimesh: pip install trimesh") from e
    vertices, faces = self.mesh(surface=surface, tolerance=tolerance, normal_tolerance=normal_tolerance)
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


Solid.to_trimesh = _to_trimesh

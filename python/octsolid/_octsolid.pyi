"""Type stubs of the extension module ``octsolid._octsolid`` (re-exported by ``octsolid``)."""

from os import PathLike
from typing import Callable, Literal, Optional, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

Vec3 = Union[Tuple[float, float, float], Sequence[float], npt.NDArray[np.float64]]
AxisLike = Union[Literal["x", "y", "z", "X", "Y", "Z"], Vec3]
Domain = Tuple[Vec3, float]
PathLikeStr = Union[str, "PathLike[str]"]
Bounds = Tuple[list[float], list[float]]
# ``memory_budget=``: bytes, or a size as ``--memory-budget`` takes it (``"512MiB"``, ``"2GiB"``).
MemoryBudget = Union[int, str]
# ``progress=``: ``True`` for a bar on the terminal, or ``f(done, total)``. Whatever it is,
# Ctrl-C stops a long call at the library's next step and raises ``KeyboardInterrupt``.
ProgressLike = Union[bool, Callable[[int, int], object], None]
Metric = Literal["euclidean", "manhattan", "chebyshev"]

class Shape:
    """A shape: a CSG tree of primitives, set operations, moves and patterns.

    Combine with ``|`` (union), ``&`` (intersection), ``-`` (difference), ``^``
    (symmetric difference) and ``~`` (complement); move with ``translate``, ``rotate``,
    ``scale``; make a solid of it with :func:`voxelize`.
    """

    def __or__(self, other: Shape) -> Shape: ...
    def __and__(self, other: Shape) -> Shape: ...
    def __sub__(self, other: Shape) -> Shape: ...
    def __xor__(self, other: Shape) -> Shape: ...
    def __invert__(self) -> Shape: ...
    def translate(self, v: Vec3) -> Shape:
        """The shape moved by the vector ``v``."""
    def rotate(self, axis: AxisLike, degrees: float) -> Shape:
        """The shape turned by ``degrees`` (right-handed) about ``axis`` through the origin."""
    def scale(self, s: Union[float, Vec3]) -> Shape:
        """The shape scaled about the origin by ``s``: a number, or factors along x, y, z."""
    def offset(self, by: float, voxels: bool = False) -> Shape:
        """An offset node: grown (``by`` > 0) or shrunk by a ball, made on the lattice :func:`voxelize` uses."""
    def shell(self, thickness: float, outward: bool = False) -> Shape:
        """A shell node: the wall ``thickness`` thick inside the surface (``outward``: outside)."""
    def round(self, radius: float, convex: bool = False, concave: bool = False) -> Shape:
        """A round node: edges rounded to ``radius``, both kinds unless ``convex`` or ``concave`` picks one."""
    @property
    def bounds(self) -> Optional[Bounds]:
        """The bounding box ``(min, max)``, or ``None`` when the shape is unbounded."""
    @property
    def volume(self) -> Optional[float]:
        """The exact volume where there is a closed form (a primitive, a moved one), else ``None``."""

class Sphere(Shape):
    """A ball of ``radius`` around ``center``."""

    def __init__(self, center: Vec3, radius: float) -> None: ...

class Ellipsoid(Shape):
    """An axis-aligned ellipsoid of semi-axes ``radii`` around ``center``."""

    def __init__(self, center: Vec3, radii: Vec3) -> None: ...

class Box(Shape):
    """An axis-aligned box of edge lengths ``size`` (a number: a cube) around ``center``."""

    def __init__(self, center: Vec3, size: Union[float, Vec3]) -> None: ...

class Cylinder(Shape):
    """A capped cylinder along ``axis`` (``"x"``, ``"y"``, ``"z"``), its middle at ``center``."""

    def __init__(self, center: Vec3, axis: AxisLike, radius: float, height: float) -> None: ...

class Cone(Shape):
    """A capped cone along ``axis``, apex towards ``+axis``; its base of ``radius`` lies
    ``height / 2`` below ``center`` (as ``octsolid shape cone --center``)."""

    def __init__(self, center: Vec3, axis: AxisLike, radius: float, height: float) -> None: ...

class Torus(Shape):
    """A torus around ``axis`` through ``center``: ``radius`` to the tube's middle, ``tube`` its radius."""

    def __init__(self, center: Vec3, axis: AxisLike, radius: float, tube: float) -> None: ...

class HalfSpace(Shape):
    """The points ``p`` with ``normal . p <= offset`` (unbounded: voxelize it with a domain)."""

    def __init__(self, normal: Vec3, offset: float) -> None: ...

def linear_array(shape: Shape, counts: Union[int, Tuple[int, int, int]], step: Union[float, Vec3]) -> Shape:
    """``counts`` copies of ``shape`` along x, y and z (a number: along x), ``step`` apart."""

def polar_array(
    shape: Shape, axis: AxisLike, center: Vec3, count: int, step_degrees: Optional[float] = None
) -> Shape:
    """``count`` copies of ``shape`` turned about ``axis`` through ``center``: a bolt circle."""

class Measures(TypedDict):
    """What :meth:`Solid.measure` returns."""

    volume: float
    area: float
    voxel_face_area: float
    centroid: Optional[list[float]]
    inertia: npt.NDArray[np.float64]
    components: int

class Solid:
    """A solid: the full nodes of a linear octree over a cubic domain.

    Combine with ``|``, ``&``, ``-`` and ``^`` (operands over other domains are brought
    into one as ``octsolid csg`` does); measure, save, export, mesh, move, offset and
    render it. ``len(solid)`` is its node count.
    """

    def __or__(self, other: Solid) -> Solid: ...
    def __and__(self, other: Solid) -> Solid: ...
    def __sub__(self, other: Solid) -> Solid: ...
    def __xor__(self, other: Solid) -> Solid: ...
    def __len__(self) -> int: ...
    def union(self, other: Solid, memory_budget: Optional[MemoryBudget] = None) -> Solid:
        """``self | other`` as ``octsolid csg union``, the whole job within ``memory_budget``."""
    def intersection(self, other: Solid, memory_budget: Optional[MemoryBudget] = None) -> Solid:
        """``self & other`` as ``octsolid csg intersection``, within ``memory_budget``."""
    def difference(self, other: Solid, memory_budget: Optional[MemoryBudget] = None) -> Solid:
        """``self - other`` as ``octsolid csg difference``, within ``memory_budget``."""
    def symmetric_difference(self, other: Solid, memory_budget: Optional[MemoryBudget] = None) -> Solid:
        """``self ^ other`` as ``octsolid csg xor``, within ``memory_budget``."""
    @property
    def volume(self) -> float:
        """Volume in world units: full voxels times the voxel's volume."""
    @property
    def node_count(self) -> int:
        """Number of full octree nodes (8 bytes each in memory)."""
    @property
    def voxel_count(self) -> int:
        """Number of full voxels."""
    @property
    def bounds(self) -> Optional[Bounds]:
        """The full voxels' bounding box ``(min, max)``, or ``None`` for the empty solid."""
    @property
    def depth(self) -> int:
        """Octree depth: the domain is 2^depth voxels a side."""
    @property
    def domain(self) -> Tuple[list[float], float]:
        """The domain cube ``(min, edge)``."""
    @property
    def voxel_size(self) -> float:
        """A voxel's edge in world units."""
    def measure(self) -> Measures:
        """Volume, boundary area, centre of mass, inertia (3x3 about it) and face-connected components."""
    def save(
        self,
        path: PathLikeStr,
        surface: bool = True,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
    ) -> int:
        """Writes the solid in the format the extension names (``.oct`` with its surface data
        unless ``surface=False``, ``.octs``, ``.vox``, ``.binvox``, ``.vdb``, or the true
        surface as ``.obj``, ``.stl``, ``.ply``, ``.3mf``, ``.glb``, estimated from the voxels with
        ``surface=False``); returns the bytes written."""
    def export(
        self,
        path: PathLikeStr,
        surface: Literal["smooth", "voxels"] = "smooth",
        tolerance: float = 0.0,
        normal_tolerance: Optional[float] = None,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
    ) -> int:
        """Writes the boundary as a mesh as ``octsolid export`` does (``.obj``, ``.stl``, ``.ply``,
        ``.3mf``, ``.glb``); returns the bytes written."""
    def mesh(
        self,
        surface: Literal["smooth", "voxels"] = "smooth",
        tolerance: float = 0.0,
        normal_tolerance: Optional[float] = None,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]:
        """The boundary as ``(vertices, faces)``: float64 ``(n, 3)`` and uint32 ``(m, 3)``."""
    def to_trimesh(self, surface: Literal["smooth", "voxels"] = "smooth", tolerance: float = 0.0, normal_tolerance: Optional[float] = None) -> "trimesh.Trimesh":  # type: ignore[name-defined]  # noqa: F821
        """The boundary as a ``trimesh.Trimesh`` (needs trimesh)."""
    def keys(self) -> npt.NDArray[np.uint64]:
        """The nodes' Morton keys, a read-only uint64 array sharing the solid's memory."""
    def to_numpy(self, max_voxels: int = 2**27, memory_budget: Optional[MemoryBudget] = None) -> npt.NDArray[np.bool_]:
        """The solid as a dense bool array ``a[x, y, z]``, refused above ``max_voxels`` voxels or past ``memory_budget``."""
    def transform(
        self,
        translate: Optional[Vec3] = None,
        rotate: Optional[Sequence[Tuple[AxisLike, float]]] = None,
        scale: float = 1.0,
        domain: Optional[Domain] = None,
        depth: Optional[int] = None,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
    ) -> Solid:
        """The solid scaled, turned (each ``(axis, degrees)`` in order) and moved, as ``octsolid transform``."""
    def offset(
        self,
        by: float,
        voxels: bool = False,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
        metric: Metric = "euclidean",
    ) -> Solid:
        """Grown (``by`` > 0) or shrunk (``by`` < 0) by a ball, world units (``voxels=True``: voxels).

        ``metric``: ``"manhattan"`` (an octahedron) or ``"chebyshev"`` (a cube) instead of
        the ball, over the voxels (the result carries no surface data)."""
    def shell(
        self,
        thickness: float,
        outward: bool = False,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
        metric: Metric = "euclidean",
    ) -> Solid:
        """Hollowed to a wall ``thickness`` thick inside the surface (``outward``: outside)."""
    def round(
        self,
        radius: float,
        convex: bool = False,
        concave: bool = False,
        memory_budget: Optional[MemoryBudget] = None,
        progress: ProgressLike = None,
        metric: Metric = "euclidean",
    ) -> Solid:
        """Edges rounded to ``radius``: both kinds unless ``convex`` or ``concave`` picks one."""
    def slice(
        self, axis: Literal["x", "y", "z"] = "z", at: Optional[float] = None, size: int = 768
    ) -> npt.NDArray[np.uint8]:
        """A cross-section as a ``(size, size, 3)`` uint8 picture, as ``octsolid slice`` draws it."""
    def save_slice(
        self,
        path: PathLikeStr,
        axis: Literal["x", "y", "z"] = "z",
        at: Optional[float] = None,
        size: int = 768,
    ) -> int:
        """Writes ``slice``'s cross-section as a PNG (as ``octsolid slice -o``), no numpy needed; the bytes written."""
    def contains(self, p: Vec3) -> bool:
        """Whether the point ``p`` lies in a full voxel."""
    def _repr_png_(self) -> bytes:
        """A 480x360 PNG of the solid, so a notebook shows it."""

def voxelize(
    shape: Shape,
    depth: int,
    domain: Optional[Domain] = None,
    memory_budget: Optional[MemoryBudget] = None,
    progress: ProgressLike = None,
) -> Solid:
    """Voxelizes ``shape`` at ``depth`` over ``domain`` ``(min, edge)`` (default: a cube around it),
    refused above ``memory_budget`` (default half the RAM); ``progress``: ``True`` for a bar on
    the terminal, or ``f(done, total)``."""

def from_mesh(
    vertices: npt.ArrayLike,
    faces: npt.ArrayLike,
    depth: int,
    inside: Literal["auto", "parity", "winding"] = "auto",
    domain: Optional[Domain] = None,
    memory_budget: Optional[MemoryBudget] = None,
    progress: ProgressLike = None,
) -> Solid:
    """The solid a triangle mesh ``(n, 3)`` vertices, ``(m, 3)`` faces encloses, voxelized at ``depth``."""

def load_mesh(
    path: PathLikeStr,
    depth: int = 8,
    inside: Literal["auto", "parity", "winding"] = "auto",
    domain: Optional[Domain] = None,
    memory_budget: Optional[MemoryBudget] = None,
    progress: ProgressLike = None,
) -> Solid:
    """The solid a mesh or patch file encloses, as ``octsolid voxelize PATH --depth DEPTH``."""

def load(path: PathLikeStr, memory_budget: Optional[MemoryBudget] = None) -> Solid:
    """The solid in a ``.oct``, ``.octs``, ``.vox``, ``.binvox`` or ``.vdb`` file (several: their union)."""

@overload
def render(
    solid_or_scene: Union[Solid, PathLikeStr],
    size: Optional[Tuple[int, int]] = None,
    view: Optional[str] = None,
    eye: Optional[Vec3] = None,
    target: Optional[Vec3] = None,
    fov: Optional[float] = None,
    spp: Optional[int] = None,
    method: Optional[str] = None,
    hdr: Literal[False] = False,
    azimuth: Optional[float] = None,
    elevation: Optional[float] = None,
    zoom: Optional[float] = None,
    up: Optional[str] = None,
    exposure: Optional[float] = None,
    cache: bool = True,
    progress: ProgressLike = None,
    memory_budget: Optional[MemoryBudget] = None,
) -> npt.NDArray[np.uint8]: ...
@overload
def render(
    solid_or_scene: Union[Solid, PathLikeStr],
    size: Optional[Tuple[int, int]] = None,
    view: Optional[str] = None,
    eye: Optional[Vec3] = None,
    target: Optional[Vec3] = None,
    fov: Optional[float] = None,
    spp: Optional[int] = None,
    method: Optional[str] = None,
    *,
    hdr: Literal[True],
    azimuth: Optional[float] = None,
    elevation: Optional[float] = None,
    zoom: Optional[float] = None,
    up: Optional[str] = None,
    exposure: Optional[float] = None,
    cache: bool = True,
    progress: ProgressLike = None,
    memory_budget: Optional[MemoryBudget] = None,
) -> npt.NDArray[np.float32]:
    """Renders a solid or a file as ``octsolid render`` does: ``(h, w, 3)`` uint8 sRGB, the
    PNG's pixels bit for bit, or with ``hdr=True`` float32 linear radiance; ``progress=True``
    shows a bar on the terminal (only there) while it draws."""

class RadiosityStats(TypedDict):
    solver: str
    patches: int
    elements: int
    shots: int
    unshot_fraction: float
    iterations: int
    residual: float
    emitted: float
    absorbed: float
    escaped: float
    bytes: int

def radiosity(
    scene: PathLikeStr,
    output: Optional[PathLikeStr] = None,
    solver: Literal["shooting", "gathering"] = "shooting",
    until: float = 0.001,
    max_shots: Optional[int] = None,
    tolerance: float = 1e-6,
    patch_size: Optional[float] = None,
    subdivide: Optional[float] = None,
    max_elements: Optional[int] = None,
    progress: ProgressLike = None,
    memory_budget: Optional[MemoryBudget] = None,
) -> RadiosityStats:
    """Solves a scene file's radiosity as ``octsolid radiosity`` does, writing the ``.rad``
    solution to ``output`` when given (the CLI's bytes); returns its ``--json`` summary
    with the energy book and the bytes written; ``progress=True`` shows a bar on the terminal."""

def write_png(path: PathLikeStr, picture: npt.NDArray[np.uint8]) -> int:
    """Writes an ``(h, w, 3)`` uint8 picture (a render, a slice) as a PNG, as ``octsolid`` writes
    its pictures; returns the bytes written."""

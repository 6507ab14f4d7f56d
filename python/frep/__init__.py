"""frep: exact implicit geometry.

Exact signed distances of meshes and expressions, a modeling API with unit gradient field
operations, dual contouring meshing and rendering, over frep's C++ library (frep._core).

    import frep, numpy as np
    part = frep.load("part.stl")                    # a mesh's exact signed distance
    d = part.sdf(np.random.rand(1000, 3))           # float32 distances, negative inside
    shape = frep.subtract(frep.box((-1, -1, -1), (1, 1, 1)), frep.sphere((0, 0, 0), 1.2))
    vertices, faces = frep.ugf.offset(shape, 0.05).mesh(resolution=64)
    image = shape.render(size=256)                  # uint8 H x W x 3

docs/python.md lists the whole API.
"""

from . import _core
from ._core import (
    Field,
    FieldInfo,
    InputError,
    set_threads,
    get_threads,
    hardware_threads,
    load,
    parse,
    check,
    repair,
    convert,
    read_mesh,
    write_mesh,
    mesh_field,
    x,
    y,
    z,
    constant,
    sphere,
    box,
    circle,
    rectangle,
    plane,
    unite,
    intersect,
    subtract,
    inverse,
    union,
    intersection,
    blend,
    move,
    scale,
    rotate,
    reflect,
    revolve_y,
    extrude_z,
    loft_z,
    remap,
    sqrt,
    square,
    sin,
    cos,
    tan,
    asin,
    acos,
    atan,
    exp,
    ln,
    floor,
    ceil,
    recip,
    abs,
    min,
    max,
    atan2,
    mod,
)
from . import ugf
from ._core import round  # noqa: A004 (the opcode; Python's round stays builtins.round)

__version__ = "0.1.0"


def dataset(*args, **kwargs):
    """Builds a dataset of signed-distance samples (frep.dataset.dataset; needs Dask).

    Imported on first call, so that importing frep never needs Dask.
    """
    from .dataset import dataset as build

    # Importing the submodule binds frep.dataset to it: keep this function there instead.
    globals()["dataset"] = _dataset_entry
    return build(*args, **kwargs)


_dataset_entry = dataset

# `from frep import *` leaves Python's own abs, min, max and round alone.
__all__ = [n for n in dir() if not n.startswith("_") and n not in ("abs", "min", "max", "round")]

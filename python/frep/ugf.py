"""Unit gradient field operations (frep/ugf in the C++ library, docs/ugf.md): offsets, shells,
exact booleans, smooth blends, chamfers and rounds, as functions on frep.Field."""

from ._core import ugf as _ugf

offset = _ugf.offset
shell = _ugf.shell
shell_biased = _ugf.shell_biased
shell_inward = _ugf.shell_inward
shell_outward = _ugf.shell_outward
normalize = _ugf.normalize
intersect_exact = _ugf.intersect_exact
unite_exact = _ugf.unite_exact
subtract_exact = _ugf.subtract_exact
intersect_right_angle = _ugf.intersect_right_angle
unite_right_angle = _ugf.unite_right_angle
subtract_right_angle = _ugf.subtract_right_angle
smooth_union = _ugf.smooth_union
smooth_intersection = _ugf.smooth_intersection
smooth_difference = _ugf.smooth_difference
chamfer_intersection = _ugf.chamfer_intersection
chamfer_union = _ugf.chamfer_union
round_intersection = _ugf.round_intersection
round_union = _ugf.round_union
gyroid = _ugf.gyroid

__all__ = [n for n in dir() if not n.startswith("_")]

// The umbrella header: everything public in frep, for `#include <frep/frep.hpp>`.
#pragma once

#include "frep/error.hpp"
#include "frep/math/vec.hpp"
#include "frep/math/morton.hpp"
#include "frep/util/large_allocator.hpp"
#include "frep/util/memory_budget.hpp"
#include "frep/util/thread_pool.hpp"

#include "frep/expr/opcode.hpp"
#include "frep/expr/semantics.hpp"
#include "frep/expr/graph.hpp"
#include "frep/expr/expr.hpp"
#include "frep/expr/model.hpp"
#include "frep/expr/derivative.hpp"

#include "frep/eval/interval.hpp"
#include "frep/eval/grad.hpp"
#include "frep/eval/tape.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/interval_batch.hpp"
#include "frep/eval/point_cloud.hpp"
#include "frep/eval/subdivision.hpp"

#include "frep/io/atomic_file.hpp"
#include "frep/io/frep_file.hpp"
#include "frep/io/load.hpp"
#include "frep/io/npy.hpp"
#include "frep/io/points.hpp"
#include "frep/io/rhai.hpp"
#include "frep/io/save.hpp"
#include "frep/io/vm.hpp"

#include "frep/mesh/mesh.hpp"
#include "frep/mesh/mesh_io.hpp"
#include "frep/mesh/weld.hpp"
#include "frep/mesh/topology.hpp"
#include "frep/mesh/bvh.hpp"
#include "frep/mesh/validate.hpp"
#include "frep/mesh/mesh_distance.hpp"

#include "frep/render/image.hpp"
#include "frep/render/render2d.hpp"
#include "frep/render/camera.hpp"
#include "frep/render/render3d.hpp"
#include "frep/render/shade.hpp"
#include "frep/render/slice.hpp"

#include "frep/convert/convert.hpp"

#include "frep/sample/grid.hpp"
#include "frep/sample/mesh_field.hpp"
#include "frep/sample/points.hpp"

#include "frep/contour/bounds.hpp"
#include "frep/contour/cell_topology.hpp"
#include "frep/contour/mesh_options.hpp"
#include "frep/contour/mesher.hpp"
#include "frep/contour/qef.hpp"
#include "frep/contour/snap.hpp"

#include "frep/export/c_source.hpp"
#include "frep/export/glsl.hpp"
#include "frep/export/latex.hpp"

#include "frep/ugf.hpp"

// Unit gradient field modeling (docs/ugf.md, whose "The mathematics" says what each computes): offsets, shells, exact booleans,
// blends, the edge frame, chamfers, rounds, pencils, two-body fields, clearance, normalization,
// the gyroid lattice and medial-axis tracking, each a function that builds an expression.
#pragma once

#include "frep/expr/derivative.hpp"
#include "frep/ugf/blend.hpp"
#include "frep/ugf/boolean.hpp"
#include "frep/ugf/chamfer.hpp"
#include "frep/ugf/clearance.hpp"
#include "frep/ugf/edge_frame.hpp"
#include "frep/ugf/gyroid.hpp"
#include "frep/ugf/medial.hpp"
#include "frep/ugf/mesh_clearance.hpp"
#include "frep/ugf/normalize.hpp"
#include "frep/ugf/offset.hpp"
#include "frep/ugf/pencil.hpp"
#include "frep/ugf/round.hpp"
#include "frep/ugf/two_body.hpp"

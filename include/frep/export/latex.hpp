// Export an expression as mathematics: a LaTeX document (or fragment) that defines f(x, y, z)
// through numbered definitions, with piecewise selects as cases and long sums and minima wrapped.
#pragma once

#include <ostream>
#include <string>

#include "frep/expr/graph.hpp"

namespace frep {

struct LatexOptions {
  // A complete document (\documentclass{article}, amsmath, geometry); false writes only the
  // align* environments, for \input into a document that loads amsmath.
  bool standalone = true;
  // Significant digits of constants; 0 writes the shortest text that reads back as the same f32
  // (exact), 1 to 9 round for readability.
  int digits = 0;
  // Rough width of a display line, in characters of mathematics: sums, products, minima and
  // maxima wider than this wrap at the top level of a definition, and subexpressions that cannot
  // wrap are given their own definition when they would not fit. 80 suits A4 with 2 cm margins.
  int line_width = 80;
  // Where the expression came from, shown in the title (e.g. the input file name).
  std::string source;
};

// Writes f as mathematics. Subexpressions used more than once (except ones made only of
// variables and constants, like x^2) become definitions d_1, d_2, ... in dependency order;
// or(and(c, a), and(not(c), b)) selects and chains of them become cases (tried top to bottom);
// single-use chains of +/-, *, min and max become n-ary sums, products, \min and \max.
// Mathematics, not f32: the flattening regroups sums and the text says nothing about NaN or
// rounding. Iterative: fine for million-node inputs (the document is then very long).
// Throws InputError on bad options.
void write_latex(std::ostream& out, const Graph& g, NodeId root, const LatexOptions& opt = {});

}  // namespace frep

// Rhai's operators on values: Rhai's own rules for numbers (checked i64, f64, mixed -> f64),
// strings, arrays and maps; Fidget's for expressions (`+ - * / %` build nodes, `%` is mod, and
// comparing expressions is an error).
#pragma once

#include <cstdint>

#include "rhai_ast.hpp"
#include "rhai_value.hpp"

namespace frep::rhai {

class Interp;

Value negate(Interp& in, const Value& v, std::uint32_t pos);
Value binary_op(Interp& in, BinOp op, const Value& a, const Value& b, std::uint32_t pos);
// `target op= v`, appending in place for strings and arrays.
void compound_assign(Interp& in, BinOp op, Value& target, const Value& v, std::uint32_t pos);
Value index_value(Interp& in, const Value& base, const Value& key, std::uint32_t pos);
Value property_value(Interp& in, const Value& base, std::uint32_t sym, std::uint32_t pos);

// Checked 64-bit integer arithmetic as Rhai does it (overflow and division by zero are errors).
std::int64_t int_arith(Interp& in, BinOp op, std::int64_t a, std::int64_t b, std::uint32_t pos);

}  // namespace frep::rhai

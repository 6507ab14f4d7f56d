// SIMD helpers shared by the Highway-compiled evaluators (included once per target, after
// <hwy/highway.h>, the Highway way).
#if defined(FREP_EVAL_SIMD_OPS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef FREP_EVAL_SIMD_OPS_INL_H_
#undef FREP_EVAL_SIMD_OPS_INL_H_
#else
#define FREP_EVAL_SIMD_OPS_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace frep {
namespace HWY_NAMESPACE {

// v != 0 as IEEE defines it: true for NaN. (Highway's operator!= is false for NaN on AVX-512
// but true on AVX2 and SSE4, which made targets disagree; equality is ordered everywhere.)
template <class V>
HWY_INLINE auto NotZero(V v) {
  namespace hn = hwy::HWY_NAMESPACE;
  return hn::Not(v == hn::Zero(hn::DFromV<V>()));
}

// min and max with frep's semantics: NaN if either argument is NaN, else p < q ? p : q (q on
// ties). x86's minps/maxps compute exactly p < q ? p : q, returning q when either is NaN, so
// only a NaN in p needs fixing; elsewhere the comparison is spelled out.
template <class V>
HWY_INLINE V MinNaN(V p, V q) {
  namespace hn = hwy::HWY_NAMESPACE;
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
  return hn::IfThenElse(hn::IsNaN(p), p, hn::Min(p, q));
#else
  return hn::IfThenElse(hn::Or(p < q, hn::IsNaN(p)), p, q);
#endif
}
template <class V>
HWY_INLINE V MaxNaN(V p, V q) {
  namespace hn = hwy::HWY_NAMESPACE;
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
  return hn::IfThenElse(hn::IsNaN(p), p, hn::Max(p, q));
#else
  return hn::IfThenElse(hn::Or(p > q, hn::IsNaN(p)), p, q);
#endif
}

}  // namespace HWY_NAMESPACE
}  // namespace frep
HWY_AFTER_NAMESPACE();

#endif  // include guard toggled per target

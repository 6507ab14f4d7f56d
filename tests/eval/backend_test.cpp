// The evaluator seam: backends by name, and a backend plugged in as the default reaches every
// caller (here the mesher, which makes its evaluators without naming one).
#include <gtest/gtest.h>

#include <atomic>

#include "frep/contour/mesher.hpp"
#include "frep/error.hpp"
#include "frep/eval/backend.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/eval/jit.hpp"
#include "frep/expr/expr.hpp"

namespace frep {
namespace {

TEST(Backend, TheJitIsTheDefaultAndUnknownNamesAreErrors) {
  EXPECT_STREQ(interpreter_backend().name(), "interp");
  EXPECT_EQ(&backend_by_name("interp"), &interpreter_backend());
  EXPECT_EQ(&default_backend(), &jit_backend());  // the tests run without FREP_BACKEND
  try {
    backend_by_name("warp-drive");
    ADD_FAILURE() << "an unknown backend was found";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("interp"), std::string::npos) << e.what();
  }
}

// Counts the kernels' calls and runs the interpreter's.
struct Counting final : Backend {
  mutable std::atomic<int> batch_calls{0}, grad_calls{0}, interval_calls{0};
  const char* name() const override { return "counting"; }
  struct B final : BatchKernel {
    std::unique_ptr<BatchKernel> base;
    std::atomic<int>* calls;
    void eval(const Tape& t, const float* x, const float* y, const float* z, float* o, std::size_t n) override {
      ++*calls;
      base->eval(t, x, y, z, o, n);
    }
  };
  struct G final : GradKernel {
    std::unique_ptr<GradKernel> base;
    std::atomic<int>* calls;
    void eval(const Tape& t, const float* x, const float* y, const float* z, Grad* o, std::size_t n) override {
      ++*calls;
      base->eval(t, x, y, z, o, n);
    }
  };
  struct I final : IntervalBatchKernel {
    std::unique_ptr<IntervalBatchKernel> base;
    std::atomic<int>* calls;
    void eval(const Tape& t, const float* box, int count, std::uint32_t lanes, IntervalRecord& r) override {
      ++*calls;
      base->eval(t, box, count, lanes, r);
    }
  };
  std::unique_ptr<BatchKernel> batch() const override {
    auto k = std::make_unique<B>();
    k->base = interpreter_backend().batch();
    k->calls = &batch_calls;
    return k;
  }
  std::unique_ptr<GradKernel> grad() const override {
    auto k = std::make_unique<G>();
    k->base = interpreter_backend().grad();
    k->calls = &grad_calls;
    return k;
  }
  std::unique_ptr<IntervalBatchKernel> interval_batch() const override {
    auto k = std::make_unique<I>();
    k->base = interpreter_backend().interval_batch();
    k->calls = &interval_calls;
    return k;
  }
};

TEST(Backend, APluggedBackendRunsEveryCallersWork) {
  Graph g;
  const Expr x = g.x(), y = g.y(), z = g.z();
  const Tape t = Tape::compile(g, (sqrt(x * x + y * y + z * z) - 0.8f).id());
  MeshOptions mo;
  mo.resolution = 24;
  mo.bounds = Box3{{-1, -1, -1}, {1, 1, 1}};
  const TriMesh reference = mesh_expression(t, mo);
  Counting counting;
  set_default_backend(&counting);
  const TriMesh plugged = mesh_expression(t, mo);
  set_default_backend(nullptr);
  EXPECT_EQ(&default_backend(), &jit_backend());
  EXPECT_GT(counting.batch_calls.load(), 0);
  EXPECT_GT(counting.grad_calls.load(), 0);
  EXPECT_GT(counting.interval_calls.load(), 0);
  EXPECT_EQ(plugged.vertices, reference.vertices);
  EXPECT_EQ(plugged.triangles, reference.triangles);
}

}  // namespace
}  // namespace frep

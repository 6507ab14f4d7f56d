// The backend registry: the interpreter and the JIT, and the choice of the default (library
// option, else FREP_BACKEND, else the JIT).
#include "frep/eval/backend.hpp"

#include <atomic>
#include <cstdlib>

#include "eval/interp_kernels.hpp"
#include "frep/error.hpp"
#include "frep/eval/jit.hpp"

namespace frep {
namespace {

class Interpreter final : public Backend {
 public:
  const char* name() const override { return "interp"; }
  std::unique_ptr<BatchKernel> batch() const override { return interp::make_batch_kernel(); }
  std::unique_ptr<GradKernel> grad() const override { return interp::make_grad_kernel(); }
  std::unique_ptr<IntervalBatchKernel> interval_batch() const override { return interp::make_interval_batch_kernel(); }
};

std::atomic<const Backend*> g_chosen{nullptr};

}  // namespace

const Backend& interpreter_backend() {
  static const Interpreter interpreter;
  return interpreter;
}

std::vector<const Backend*> available_backends() { return {&interpreter_backend(), &jit_backend()}; }

const Backend& backend_by_name(const std::string& name) {
  std::string names;
  for (const Backend* b : available_backends()) {
    if (name == b->name()) return *b;
    names += std::string(names.empty() ? "" : ", ") + b->name();
  }
  throw InputError("FREP_BACKEND", 0, "unknown evaluator backend '" + name + "' (this build has: " + names + ")");
}

const Backend& default_backend() {
  if (const Backend* b = g_chosen.load(std::memory_order_acquire)) return *b;
  // The environment's choice, looked up once.
  static const Backend* from_env = [] {
    const char* e = std::getenv("FREP_BACKEND");
    return e && *e ? &backend_by_name(e) : &jit_backend();
  }();
  return *from_env;
}

void set_default_backend(const Backend* backend) { g_chosen.store(backend, std::memory_order_release); }

}  // namespace frep

// Uses frep through the umbrella header only: builds a field, evaluates it with the scalar and
// SIMD evaluators, and checks the results. Exit code 0 on success.
#include <frep/frep.hpp>

#include <cstdio>

int main() {
  frep::Graph g;
  auto x = g.x(), y = g.y(), z = g.z();
  auto sphere = sqrt(square(x) + square(y) + square(z)) - 1.0f;
  const frep::Tape tape = frep::Tape::compile(g, sphere.id());
  frep::PointEvaluator point;
  const float a = point.eval(tape, 2, 0, 0);
  frep::BatchEvaluator batch;
  const float xs[2] = {0, 3}, ys[2] = {0, 0}, zs[2] = {0, 4};
  float out[2];
  batch.eval(tape, xs, ys, zs, out, 2);
  std::printf("f(2,0,0) = %g, f(0,0,0) = %g, f(3,0,4) = %g (%s)\n", a, out[0], out[1],
              frep::BatchEvaluator::target_name());
  return (a == 1.0f && out[0] == -1.0f && out[1] == 4.0f) ? 0 : 1;
}

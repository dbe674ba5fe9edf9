#pragma once
// Vectors of random draws in a fixed order.
//
// `Eigen::Vector2d(d(rng), d(rng))` leaves the order of the two draws to the
// compiler: the order in which a call's arguments are evaluated is
// unspecified (GCC evaluates them last to first, clang first to last), so
// one seed would give other numbers with another compiler. DrawVector draws
// one component per statement, the last component first: the order in which
// the simulator's and the tests' seeds have always been drawn.

#include <Eigen/Core>

namespace groundline::core {

template <int N, class Distribution, class Engine>
Eigen::Matrix<double, N, 1> DrawVector(Distribution& distribution, Engine& engine) {
  Eigen::Matrix<double, N, 1> v;
  for (int i = N - 1; i >= 0; --i) v(i) = distribution(engine);
  return v;
}

}  // namespace groundline::core

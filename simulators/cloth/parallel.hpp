// Parallel loops over [0, n) on OpenMP threads: the project's one way to
// run work in parallel (docs/architecture.md, "Parallel work"). Each index
// must write only its own data, so results never depend on the thread count
// or schedule.
#pragma once

#include <omp.h>

#include <algorithm>
#include <exception>
#include <vector>

namespace cloth {

// threads <= 0 means OpenMP's default: OMP_NUM_THREADS, else every hardware
// thread.
inline int resolve_threads(int threads) {
  return threads > 0 ? threads : omp_get_max_threads();
}

// Many short iterations (the rows of a distance field, the vertices of a
// mesh), split evenly between the threads. (A cloth step runs its loops in
// one parallel region of its own, ClothSimulation::step.)
template <class Function>
void parallel_for(int n, int threads, Function&& function) {
  const int count = resolve_threads(threads);
  if (count <= 1 || n <= 64) {
    // A plain loop: even an inactive OpenMP region costs a runtime call.
    for (int i = 0; i < n; ++i) function(i);
    return;
  }
#pragma omp parallel for schedule(static) num_threads(count)
  for (int i = 0; i < n; ++i) function(i);
}

// A few long tasks of uneven length (trials): each thread takes the next
// index as it comes free. An exception thrown by a task is rethrown here,
// once every task has ended (that of the lowest index when several throw).
template <class Function>
void parallel_tasks(int n, int threads, Function&& function) {
  const int count = std::min(resolve_threads(threads), n);
  if (count <= 1) {
    for (int i = 0; i < n; ++i) function(i);
    return;
  }
  // An exception must not leave an OpenMP region: each task keeps its own.
  std::vector<std::exception_ptr> failures(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(dynamic, 1) num_threads(count)
  for (int i = 0; i < n; ++i) {
    try {
      function(i);
    } catch (...) {
      failures[static_cast<std::size_t>(i)] = std::current_exception();
    }
  }
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

}  // namespace cloth

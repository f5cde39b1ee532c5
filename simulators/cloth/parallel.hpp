// A parallel loop over [0, n) on OpenMP threads. Each index must write only
// its own data, so results never depend on the thread count or schedule.
#pragma once

#include <omp.h>

namespace cloth {

// threads <= 0 means every hardware thread.
inline int resolve_threads(int threads) {
  return threads > 0 ? threads : omp_get_max_threads();
}

template <class Function>
void parallel_for(int n, int threads, Function&& function) {
  const int count = resolve_threads(threads);
  if (count <= 1 || n <= 64) {
    // A plain loop: even an inactive OpenMP region costs a runtime call per
    // loop, and a cloth step runs over a hundred loops (one per colour class
    // and iteration). The wearability test runs its trials single-threaded.
    for (int i = 0; i < n; ++i) function(i);
    return;
  }
#pragma omp parallel for schedule(static) num_threads(count)
  for (int i = 0; i < n; ++i) function(i);
}

}  // namespace cloth

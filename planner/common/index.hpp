// Element indices: the planner numbers vertices, faces and half-edges with
// int (-1 is "none"); containers are indexed by std::size_t.
#pragma once

#include <cstddef>

namespace planner {

// The container index of element `i` (which must not be negative).
constexpr std::size_t at(int i) {
  return static_cast<std::size_t>(i);
}

}  // namespace planner

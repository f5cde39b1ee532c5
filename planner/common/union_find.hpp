// Disjoint sets over 0..n-1 with path halving. `unite(a, b)` puts a's set
// under b's root, so the root of a merged set is the root of the second
// argument's set: callers that number components by root rely on that.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace planner {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  int find(int x) {
    while (parent_[index(x)] != x) {
      parent_[index(x)] = parent_[index(parent_[index(x)])];
      x = parent_[index(x)];
    }
    return x;
  }
  void unite(int a, int b) { parent_[index(find(a))] = find(b); }

 private:
  static std::size_t index(int x) { return static_cast<std::size_t>(x); }
  std::vector<int> parent_;
};

}  // namespace planner

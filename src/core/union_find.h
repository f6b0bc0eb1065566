#pragma once
// Disjoint sets over 0..n-1 (connected pieces of a mesh or of a voxel band). The smaller index
// becomes the root, so the result does not depend on the order the unions come in.
#include <cstdint>
#include <numeric>
#include <vector>

namespace vf {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), int32_t(0)); }

  int32_t root(int32_t v) {
    while (parent_[size_t(v)] != v) v = parent_[size_t(v)] = parent_[size_t(parent_[size_t(v)])];  // path halving
    return v;
  }
  void unite(int32_t a, int32_t b) {
    a = root(a), b = root(b);
    if (a != b) parent_[size_t(a > b ? a : b)] = a < b ? a : b;
  }
  // Every element's root, after which root(v) == roots()[v] costs one step.
  const std::vector<int32_t>& flatten() {
    for (int32_t v = 0; v < int32_t(parent_.size()); ++v) parent_[size_t(v)] = root(v);
    return parent_;
  }
  size_t size() const { return parent_.size(); }

 private:
  std::vector<int32_t> parent_;
};

}  // namespace vf

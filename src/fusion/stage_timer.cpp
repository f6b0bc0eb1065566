#include "fusion/stage_timer.h"

#include <algorithm>
#include <numeric>

namespace vf {

double StageTimer::median(const std::string& stage) const {
  auto it = series_.find(stage);
  if (it == series_.end() || it->second.empty()) return 0.0;
  std::vector<double> v = it->second;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double StageTimer::total(const std::string& stage) const {
  auto it = series_.find(stage);
  if (it == series_.end()) return 0.0;
  return std::accumulate(it->second.begin(), it->second.end(), 0.0);
}

double StageTimer::mean(const std::string& stage) const {
  auto it = series_.find(stage);
  if (it == series_.end() || it->second.empty()) return 0.0;
  return total(stage) / double(it->second.size());
}

}  // namespace vf

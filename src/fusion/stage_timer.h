#pragma once
// Per-stage wall-clock times of every frame, for the timing table and the benchmark medians.
#include <chrono>
#include <map>
#include <string>
#include <vector>

namespace vf {

class StageTimer {
 public:
  void add(const std::string& stage, double ms) {
    if (!series_.count(stage)) order_.push_back(stage);
    series_[stage].push_back(ms);
  }
  const std::vector<std::string>& stages() const { return order_; }
  const std::vector<double>& samples(const std::string& stage) const { return series_.at(stage); }
  double median(const std::string& stage) const;
  double mean(const std::string& stage) const;
  double total(const std::string& stage) const;

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::vector<double>> series_;
};

// Adds the time from construction to destruction to one stage.
class ScopedStage {
 public:
  ScopedStage(StageTimer& timer, std::string stage)
      : timer_(timer), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedStage() {
    timer_.add(stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
  }

 private:
  StageTimer& timer_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace vf

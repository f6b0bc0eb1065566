#include "fusion/stage_timer.h"

#include <algorithm>
#include <numeric>

#include "fusion/cuda_api.h"

namespace vf {

StageTimer::StageTimer(const StageTimer& other) : order_(other.order_) {
  other.resolve(true);
  series_ = other.series_;
}

StageTimer& StageTimer::operator=(const StageTimer& other) {
  if (this == &other) return *this;
  other.resolve(true);
  releaseEvents();
  order_ = other.order_;
  series_ = other.series_;
  return *this;
}

StageTimer::~StageTimer() { releaseEvents(); }

void StageTimer::releaseEvents() noexcept {
  for (const DeviceSpan& span : pending_) {
    cuda::destroyEvent(span.start);
    cuda::destroyEvent(span.end);
  }
  pending_.clear();
  for (void* event : spare_events_) cuda::destroyEvent(event);
  spare_events_.clear();
}

void StageTimer::add(const std::string& stage, double ms) {
  if (!series_.count(stage)) order_.push_back(stage);
  series_[stage].push_back(ms);
}

void StageTimer::addDeviceSpan(const std::string& stage, void* start, void* end) {
  if (!series_.count(stage)) {
    order_.push_back(stage);
    series_[stage];
  }
  pending_.push_back({stage, start, end});
  // Spans the GPU has passed become samples now, so that few events are held. A CUDA error here
  // is reported by the next call that waits (the pipeline's own, or reading the samples).
  try {
    resolve(false);
  } catch (...) {
  }
}

void* StageTimer::takeEvent() {
  if (spare_events_.empty()) return cuda::createEvent();
  void* event = spare_events_.back();
  spare_events_.pop_back();
  return event;
}

void StageTimer::resolve(bool wait) const {
  size_t done = 0;
  auto forgetDone = [&] { pending_.erase(pending_.begin(), pending_.begin() + std::ptrdiff_t(done)); };
  try {
    for (; done < pending_.size(); ++done) {
      const DeviceSpan& span = pending_[done];
      if (!wait && !cuda::eventReached(span.end)) break;
      series_[span.stage].push_back(double(cuda::elapsedMs(span.start, span.end)));
      spare_events_.push_back(span.start);
      spare_events_.push_back(span.end);
    }
  } catch (...) {  // (a CUDA error): the spans resolved so far are not resolved twice
    forgetDone();
    throw;
  }
  forgetDone();
}

const std::vector<double>& StageTimer::samples(const std::string& stage) const {
  resolve(true);
  return series_.at(stage);
}

double StageTimer::median(const std::string& stage) const {
  resolve(true);
  auto it = series_.find(stage);
  if (it == series_.end() || it->second.empty()) return 0.0;
  std::vector<double> v = it->second;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double StageTimer::total(const std::string& stage) const {
  resolve(true);
  auto it = series_.find(stage);
  if (it == series_.end()) return 0.0;
  return std::accumulate(it->second.begin(), it->second.end(), 0.0);
}

double StageTimer::mean(const std::string& stage) const {
  resolve(true);
  auto it = series_.find(stage);
  if (it == series_.end() || it->second.empty()) return 0.0;
  return total(stage) / double(it->second.size());
}

ScopedStage::ScopedStage(StageTimer& timer, std::string stage, Device device)
    : timer_(timer), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {
  if (device == Device::Cuda) {
    start_event_ = timer_.takeEvent();
    cuda::recordEvent(start_event_);
  }
}

ScopedStage::~ScopedStage() {
  if (!start_event_) {
    timer_.add(stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
    return;
  }
  // A destructor must not throw: after a CUDA error (which the stage's own calls or the next
  // wait report) the stage is simply not timed.
  void* end = nullptr;
  try {
    end = timer_.takeEvent();
    cuda::recordEvent(end);
  } catch (...) {
    cuda::destroyEvent(end);
    cuda::destroyEvent(start_event_);
    return;
  }
  timer_.addDeviceSpan(stage_, start_event_, end);
}

}  // namespace vf

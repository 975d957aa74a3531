// Time as the reference controller sees it. Tests and the in-process runner
// drive a VirtualClock (deterministic, instant); `sabus sim` a SteadyClock.
#pragma once

#include <chrono>
#include <cstdint>

namespace sabus::harness {

using Duration = std::chrono::microseconds;
using TimePoint = std::chrono::time_point<std::chrono::steady_clock, Duration>;

class Clock {
 public:
  virtual ~Clock() = default;
  virtual TimePoint now() const = 0;
};

class VirtualClock : public Clock {
 public:
  TimePoint now() const override { return now_; }
  void advance(Duration d) { now_ += d; }
  void set(TimePoint t) { now_ = t; }

 private:
  TimePoint now_{};
};

class SteadyClock : public Clock {
 public:
  TimePoint now() const override {
    return std::chrono::time_point_cast<Duration>(std::chrono::steady_clock::now());
  }
};

}  // namespace sabus::harness

// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>

namespace omesh
{
/// Thrown when a meshing run has used up its time limit (MesherOptions::timeLimit). A failure, not
/// a partial mesh: a mesh cut by the clock would depend on the machine's load (the vertex budget
/// gives a reproducible partial mesh). The message names the phase and how far the run got;
/// `statistics` holds the same figures (vertices, tetrahedra, time.elapsed, time_limit, ...).
struct TimeLimitReached : std::runtime_error
{
  TimeLimitReached(const std::string& message, std::string phase, std::map<std::string, double> statistics)
    : std::runtime_error(message)
    , phase(std::move(phase))
    , statistics(std::move(statistics))
  {
  }
  std::string phase;
  std::map<std::string, double> statistics;
};

/// The wall-clock limit of one meshing run, asked by every phase (between steps, and inside the
/// long ones every few hundred calls).
class MeshingDeadline
{
public:
  using Clock = std::chrono::steady_clock;
  /// What the run has done so far, added to the statistics when the limit strikes.
  using Measure = std::function<void(std::map<std::string, double>&)>;

  /// `seconds` <= 0 or infinite: no limit. The clock starts now.
  explicit MeshingDeadline(double seconds);

  double limit() const { return seconds_; }
  bool limited() const { return seconds_ > 0; }
  double elapsed() const;
  bool passed() const { return limited() && Clock::now() >= end_; }

  /// The figures that say how far the run got (set by the mesher as its phases go; the latest wins).
  void setMeasure(Measure measure) { measure_ = std::move(measure); }

  /// Throws TimeLimitReached naming `phase` when the limit has passed.
  void check(const char* phase) const
  {
    if (passed())
      fail(phase);
  }
  /// As check(), reading the clock only every 256th call: for loops whose steps take microseconds.
  void tick(const char* phase) const
  {
    if (((ticks_.fetch_add(1, std::memory_order_relaxed) + 1) & 255u) == 0) // also from parallel passes
      check(phase);
  }

  /// Throws TimeLimitReached for `phase`, with the statistics so far.
  [[noreturn]] void fail(const char* phase) const;

private:
  double seconds_;
  Clock::time_point start_, end_;
  Measure measure_;
  mutable std::atomic<std::size_t> ticks_{ 0 };
};
}

// SPDX-License-Identifier: GPL-3.0-or-later
#include "MeshingDeadline.h"

#include <cmath>
#include <sstream>

namespace omesh
{
MeshingDeadline::MeshingDeadline(double seconds)
  : seconds_(seconds > 0 && std::isfinite(seconds) ? seconds : 0.0)
  , start_(Clock::now())
  , end_(start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds_)))
{
}

double MeshingDeadline::elapsed() const
{
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void MeshingDeadline::fail(const char* phase) const
{
  std::map<std::string, double> st;
  if (measure_)
    measure_(st);
  st["time_limit"] = seconds_;
  st["time.elapsed"] = elapsed();
  std::ostringstream o;
  o.precision(3);
  o << "time limit of " << seconds_ << " s reached in " << phase << " after " << st["time.elapsed"] << " s";
  const char* sep = ": ";
  for (const char* key : { "vertices", "tetrahedra", "feature_points" })
    if (const auto it = st.find(key); it != st.end() && (it->second > 0 || std::string(key) != "feature_points"))
    {
      o << sep << static_cast<long long>(it->second) << " " << (std::string(key) == "feature_points" ? "feature-line points" : key);
      sep = ", ";
    }
  o << " so far; the criteria ask for more than the time allows: loosen them, or raise the time limit "
       "(a partial mesh: set a vertex budget, which ends refinement reproducibly)";
  // dense feature lines (a noisy surface's sharp edges) are the usual cause when their points are
  // a large share of the vertices
  const auto points = st.find("feature_points"), vertices = st.find("vertices");
  if (points != st.end() && vertices != st.end() && points->second * 3 > vertices->second && points->second > 1000)
    o << "; the feature lines are dense (" << static_cast<long long>(points->second)
      << " of the points so far lie on them): resample them (ResampleFeatureLines) or raise the feature angle "
         "that found them";
  throw TimeLimitReached(o.str(), phase, std::move(st));
}
}

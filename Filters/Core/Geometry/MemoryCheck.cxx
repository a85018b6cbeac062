// SPDX-License-Identifier: GPL-3.0-or-later
#include "MemoryCheck.h"

#include "InputError.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <sys/resource.h>
#include <unistd.h>

namespace omesh
{
namespace
{
std::string bytes(double b)
{
  const char* units[] = { "bytes", "KB", "MB", "GB", "TB", "PB", "EB" };
  int u = 0;
  while (b >= 1024.0 && u < 6)
  {
    b /= 1024.0;
    ++u;
  }
  char text[64];
  std::snprintf(text, sizeof text, u ? "%.1f %s" : "%.0f %s", b, units[u]);
  return text;
}
}

double availableMemory()
{
  double available = -1;
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double value;
  std::string unit;
  while (meminfo >> key >> value >> unit)
    if (key == "MemAvailable:")
    {
      available = value * 1024.0;
      break;
    }
  if (available < 0)
  {
    const long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    available = (pages > 0 && size > 0) ? static_cast<double>(pages) * size : 1e18;
  }
  struct rlimit limit;
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    available = std::min(available, static_cast<double>(limit.rlim_cur));
  return available;
}

void checkMemory(const std::string& who, const std::string& what, double count, double bytesEach)
{
  const double needed = count * bytesEach, available = availableMemory();
  if (needed <= available)
    return;
  std::ostringstream o;
  o << who << ": " << what << " (" << count << ") would need " << bytes(needed) << " of memory (" << bytesEach
    << " bytes each); " << bytes(available) << " available";
  throw InputError(o.str());
}
}

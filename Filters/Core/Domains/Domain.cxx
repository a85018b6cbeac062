// SPDX-License-Identifier: GPL-3.0-or-later
#include "Domain.h"

#include "InputError.h"

namespace omesh
{
void Domain::checkMaterialId(int id, const std::string& who)
{
  if (id < 0)
  {
    throw InputError(who + ": material id " + std::to_string(id) +
      " is negative; material ids must be >= 0 (-1 means outside)");
  }
}
}

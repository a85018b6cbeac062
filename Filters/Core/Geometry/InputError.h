// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <stdexcept>
#include <string>

namespace omesh
{
/// Thrown for input the core cannot work with; the message names the input and what is wrong,
/// so adapters can pass it to the user unchanged.
class InputError : public std::runtime_error
{
public:
  explicit InputError(const std::string& what)
    : std::runtime_error(what)
  {
  }
};
}

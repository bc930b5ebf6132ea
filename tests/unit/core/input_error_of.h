// The message of the InputError that a callable throws ("" if none), shared by the
// core tests that check error messages.
#pragma once
#include <string>

#include "pliant/core/error.h"

namespace pliant::test {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace pliant::test

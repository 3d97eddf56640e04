#pragma once
/// \file
/// MEDSPHERES_ASSERT(cond): checks an internal invariant when the build defines
/// MEDSPHERES_ENABLE_ASSERTS (CMake option MEDSPHERES_ASSERTS), and compiles to
/// nothing otherwise. A failed check throws std::logic_error naming the file and line,
/// so that tests see it and an FCL callback can still catch it.

#include <stdexcept>
#include <string>

#if defined(MEDSPHERES_ENABLE_ASSERTS) && MEDSPHERES_ENABLE_ASSERTS
#define MEDSPHERES_ASSERT(cond)                                                       \
  do {                                                                                \
    if (!(cond))                                                                      \
      throw std::logic_error(std::string(__FILE__) + ":" + std::to_string(__LINE__) + \
                             ": internal invariant failed: " #cond);                  \
  } while (false)
#else
#define MEDSPHERES_ASSERT(cond) \
  do {                          \
  } while (false)
#endif

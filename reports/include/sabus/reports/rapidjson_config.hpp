// How sabus builds RapidJSON (the run JSON's writer and schema check):
// include this before any RapidJSON header, in every file that uses one, so
// that all of them see the same definitions.
//
// A misuse of a RapidJSON writer or document (a value where a key belongs,
// an end without a start) is a std::logic_error, where RapidJSON's default
// is assert(), which a release build compiles out.
#pragma once

#include <stdexcept>

#define RAPIDJSON_ASSERT(x)                                  \
  do {                                                       \
    if (!(x)) throw std::logic_error("RapidJSON: " #x);      \
  } while (0)
#define RAPIDJSON_HAS_STDSTRING 1
// Not RAPIDJSON_SSE2: Debian's RapidJSON 1.1 writes an invalid escape with
// it (a string of controls, quotes and 8-bit bytes; the hostile-text test of
// tests/reports/checks_test.cpp read it back as "Invalid escape character").

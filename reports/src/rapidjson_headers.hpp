// The RapidJSON headers sabus uses (the run JSON's writer and the journal's
// reader, reports/src/json_out.hpp), as sabus builds them. Include this, not
// RapidJSON's own headers.
#pragma once

#include <stdexcept>

// A misuse of a writer (a value where a key belongs, an end without a start)
// is a std::logic_error, where RapidJSON's default is assert(), which a
// release build compiles out.
#define RAPIDJSON_ASSERT(x)                              \
  do {                                                   \
    if (!(x)) throw std::logic_error("RapidJSON: " #x);  \
  } while (0)
#define RAPIDJSON_HAS_STDSTRING 1
// Not RAPIDJSON_SSE2: Debian's RapidJSON 1.1 writes an invalid escape with
// it (a string of controls, quotes and 8-bit bytes; the hostile-text test of
// tests/reports/checks_test.cpp read it back as "Invalid escape character").

// RapidJSON 1.1's internal stack (internal/stack.h, Stack::Reserve) adds to
// its null top pointer before its first allocation: undefined behaviour that
// does no harm on any compiler sabus is built with, and that clang's UBSan
// reports (pointer-overflow) on the first object any writer starts. That one
// check is off for RapidJSON's own functions, and only for them: sabus's
// code keeps it.
#if defined(__clang__)
#pragma clang attribute push(__attribute__((no_sanitize("pointer-overflow"))), apply_to = function)
#endif
#include <rapidjson/prettywriter.h>
#include <rapidjson/reader.h>
#include <rapidjson/stringbuffer.h>
#include <rapidjson/writer.h>
#if defined(__clang__)
#pragma clang attribute pop
#endif

// A double as text that reads back as the same double ("%.17g": 17 significant digits always
// suffice for IEEE binary64), for the CSV and TUM files the tests write, so that what a reader
// gets back is exactly the number the test computed with.
#pragma once

#include <cstdio>
#include <string>

namespace imuconv::test {

inline std::string Num17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace imuconv::test

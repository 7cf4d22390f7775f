// The labelled 15x15 table that `convert` and `conversion` print (PrintLabelledMatrix,
// apps/cli_common.cpp): columns never run together, whatever the numbers' signs and widths.
// It printed each "%.4g" at width 10 with the separator only in the padding, so a 10-character
// negative such as -1.041e-16 touched its neighbour ("2.429e-16-1.041e-16").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../pipeline/pipeline_test_util.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv_test.h"

namespace {
using namespace imuconv::test;
using imuconv::Mat15;
using nlohmann::json;

std::vector<std::string> Tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> t;
  for (std::string w; in >> w;) t.push_back(w);
  return t;
}

TEST(TableColumns, NegativeNumbersOfEveryWidthStaySeparated) {
  const TempDir tmp;
  // Negative values whose "%.4g" text has every width from 2 to 11 characters (the widest
  // "%.4g" prints: "-1.234e-100"), positive ones of the same widths, and zeros, spread so that
  // each row holds a mix and every value sits beside a negative of the largest widths.
  const std::vector<double> values{-1,         -12,        -1.5,        -12.5,       -123.4,
                                   -0.0125,    -0.01234,   -0.001234,   -1.234e-05,  -2.429e-16,
                                   -1.041e-16, -1.234e+05, -1.234e-100, -9.876e+100, 1.234e-100,
                                   2.429e-16,  7,          0.0,         123456789.0};
  Mat15 Phi;
  for (int r = 0; r < 15; ++r)
    for (int c = 0; c < 15; ++c)
      Phi(r, c) = values[static_cast<std::size_t>(r * 15 + c) % values.size()];
  const std::string state = SourcePath("examples/hover.state.json");
  json rows = json::array();
  for (int r = 0; r < 15; ++r) {
    json row = json::array();
    for (int c = 0; c < 15; ++c) row.push_back(Phi(r, c));
    rows.push_back(row);
  }
  const std::string m = tmp.write("phi.json", rows.dump());
  // left to left at one state: the transition's conversion is the identity, so the table shows
  // the values above; the expected numbers are computed by the library all the same.
  const CommandResult r =
      RunImuconv("convert --what transition --from left --to left --state " + ShellQuote(state) +
                     " --state-end " + ShellQuote(state) + " --matrix " + ShellQuote(m),
                 tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto x = imuconv::pipeline::ReadStateFile(state);
  const Mat15 expect = Plugins().convert_transition("left", "left", x, x, Phi);

  const std::set<std::string> labels{"p.x",     "p.y",  "p.z",  "theta.x", "theta.y",
                                     "theta.z", "v.x",  "v.y",  "v.z",     "bg.x",
                                     "bg.y",    "bg.z", "ba.x", "ba.y",    "ba.z"};
  std::istringstream out(r.out);
  int row = 0;
  std::size_t width = 0;
  std::set<std::size_t> widths_seen;
  for (std::string line; std::getline(out, line);) {
    const std::vector<std::string> t = Tokens(line);
    // A row starts with its label at the first column (the header line starts with blanks).
    if (t.empty() || line[0] == ' ' || labels.count(t[0]) == 0) continue;
    ASSERT_LT(row, 15) << r.out;
    // A label and 15 numbers: two numbers run together would make 14 tokens (or fewer).
    ASSERT_EQ(t.size(), 16u) << line;
    for (int c = 0; c < 15; ++c) {
      const std::string& s = t[static_cast<std::size_t>(c + 1)];
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      ASSERT_EQ(*end, '\0') << "not one number: '" << s << "' in\n" << line;
      widths_seen.insert(s.size());
      const double want = expect(row, c);
      if (want == 0.0) {
        EXPECT_EQ(s, "0") << line;
      } else {
        // "%.4g" keeps 4 significant digits: the printed value is within half a unit of the
        // 4th digit, at most 5e-4 of the value (relative), of what was computed.
        EXPECT_LE(std::abs(v - want), 5e-4 * std::abs(want)) << s << " vs " << want;
      }
    }
    // Every row is as wide as the others: the columns stay aligned for any width of number.
    if (width == 0) width = line.size();
    EXPECT_EQ(line.size(), width) << line;
    ++row;
  }
  EXPECT_EQ(row, 15) << r.out;
  // The test did see the widths it is about: 2 ("-1") up to 11 ("-1.234e-100").
  for (std::size_t w = 2; w <= 11; ++w)
    EXPECT_EQ(widths_seen.count(w), 1u) << "no number of width " << w;
  // And the header's labels are one token each, 15 of them after no row label.
  std::istringstream again(r.out);
  bool header_seen = false;
  for (std::string line; std::getline(again, line);) {
    const std::vector<std::string> t = Tokens(line);
    if (!line.empty() && line[0] == ' ' && t.size() == 15) {
      header_seen = true;
      for (const auto& s : t) EXPECT_EQ(labels.count(s), 1u) << line;
    }
  }
  EXPECT_TRUE(header_seen) << r.out;
}

}  // namespace

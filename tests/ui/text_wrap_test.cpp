// Wrapping at spaces only (random texts of numbers with units and words, random widths, fixed
// seed): no token is ever split ("0.1" stays whole), every line but a one-word line fits the
// width, and the words come back in order.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "ui/text_wrap.hpp"

using namespace gmslab;

namespace {
std::vector<std::string> tokens(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}
}  // namespace

TEST(TextWrap, BreaksOnlyAtSpacesAndFitsTheWidth) {
  std::mt19937 rng(8);
  const char* words[] = {"0.1", "m/s", "1.5", "N", "about", "every", "6.53", "s;", "stick-slip,", "Fs", "=",
                         "0.000123", "kg", "spring", "whose", "end", "moves", "at", "a", "1e-05"};
  auto measure = [](std::string_view s) { return 7.0f * static_cast<float>(s.size()); };
  for (int trial = 0; trial < 200; ++trial) {
    std::string text;
    const int n = 1 + static_cast<int>(rng() % 40);
    for (int i = 0; i < n; ++i) text += (i ? " " : "") + std::string(words[rng() % 20]);
    const float width = 7.0f * static_cast<float>(3 + rng() % 60);
    const std::string w = ui::wrap_at_spaces(text, width, measure);
    EXPECT_EQ(tokens(w), tokens(text)) << w;
    std::istringstream lines(w);
    for (std::string line; std::getline(lines, line);)
      if (tokens(line).size() > 1) EXPECT_LE(measure(line), width) << line;
  }
}

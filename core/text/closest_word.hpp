// gmslab core: the closest of a set of words to a mistyped one, for "did you mean" in messages
// (command names, options, preset names).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace gmslab {

// Edit distance of a and b (insert, delete, substitute: 1 each).
std::size_t edit_distance(const std::string& a, const std::string& b);
// The closest of `known` to `word` (edit distance at most max(2, |word| / 3); on a tie, the first
// in sort order), or "" when none is that close.
std::string closest_word(const std::string& word, const std::vector<std::string>& known);

}  // namespace gmslab

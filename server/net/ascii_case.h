// ASCII case folding for protocol text (HTTP header values, host names),
// where the locale must not matter.
#pragma once

#include <algorithm>
#include <string_view>

namespace tumble::net {

// `c` with A-Z lowered; every other byte as it is.
inline char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

// True when `a` and `b` differ at most in the case of ASCII letters.
inline bool equal_ignoring_ascii_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return ascii_lower(x) == ascii_lower(y); });
}

}  // namespace tumble::net

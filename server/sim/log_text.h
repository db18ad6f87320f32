// Text from a client or a file made fit for one line of the log (or of an
// error message that quotes it): escaped so that it cannot break the line,
// forge another, or drive a terminal, and bounded so that it cannot flood
// the log. Thread: any; a pure function.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tumble::sim {

// How much escaped text log_text() keeps by default, in bytes: enough for
// a name, a token's mistake or a request line.
inline constexpr std::size_t kLogTextBytes = 96;

// The bound for a whole message that may quote such text (an error from a
// client's request or a file), in bytes.
inline constexpr std::size_t kLogMessageBytes = 1024;

// `text` with every byte that is not printable UTF-8 escaped: \n, \r, \t,
// \\ for a backslash, \xHH for other control bytes (ESC is \x1b), for DEL
// and for each byte of invalid UTF-8, and \u{HHHH} for the C1 controls and
// the Unicode line, paragraph and direction-override characters. When the
// escaped text is longer than `max_bytes`, it is cut at a character before
// that and "...(N more bytes)" appended, N counting the bytes of `text` left
// out. The result is valid UTF-8 on one line.
std::string log_text(std::string_view text, std::size_t max_bytes = kLogTextBytes);

}  // namespace tumble::sim

#include "sim/log_text.h"

#include <cstdio>

namespace tumble::sim {
namespace {

bool continuation(unsigned char byte) { return (byte & 0xC0) == 0x80; }

// The length of the well-formed UTF-8 sequence at text[at] (RFC 3629: no
// overlong forms, no surrogates, nothing above U+10FFFF), with its code
// point in `code_point`; 0 when the bytes there are not one.
std::size_t utf8_sequence(std::string_view text, std::size_t at, char32_t* code_point) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[at + i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  unsigned char low = 0x80;  // the second byte's range, narrowed for some leads
  unsigned char high = 0xBF;
  if (lead < 0x80) {
    *code_point = lead;
    return 1;
  } else if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;   // overlong below U+0800
    if (lead == 0xED) high = 0x9F;  // surrogates U+D800 to U+DFFF
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;   // overlong below U+10000
    if (lead == 0xF4) high = 0x8F;  // above U+10FFFF
  } else {
    return 0;
  }
  if (at + length > text.size() || byte(1) < low || byte(1) > high) return 0;
  char32_t value = lead & (0xFF >> (length + 1));
  for (std::size_t i = 1; i < length; ++i) {
    if (!continuation(byte(i))) return 0;
    value = (value << 6) | (byte(i) & 0x3F);
  }
  *code_point = value;
  return length;
}

// Characters that move or restyle a terminal's text, or start a new line in
// some viewers, though they are valid UTF-8: the C1 controls, the line and
// paragraph separators, and the bidirectional overrides and isolates.
bool invisible_control(char32_t c) {
  return (c >= 0x80 && c <= 0x9F) || (c >= 0x2028 && c <= 0x202E) || (c >= 0x2066 && c <= 0x2069);
}

std::string hex_byte(unsigned char byte) {
  char text[5];
  std::snprintf(text, sizeof text, "\\x%02x", byte);
  return text;
}

// How the bytes text[at, at + *length) are written in the log; sets *length.
std::string escaped_piece(std::string_view text, std::size_t at, std::size_t* length) {
  char32_t c = 0;
  *length = utf8_sequence(text, at, &c);
  if (*length == 0) {
    *length = 1;
    return hex_byte(static_cast<unsigned char>(text[at]));
  }
  switch (c) {
    case '\n':
      return "\\n";
    case '\r':
      return "\\r";
    case '\t':
      return "\\t";
    case '\\':
      return "\\\\";
    default:
      break;
  }
  if (c < 0x20 || c == 0x7F) return hex_byte(static_cast<unsigned char>(c));
  if (invisible_control(c)) {
    char code[16];  // "\\u{" + up to 8 hex digits + "}" + NUL
    std::snprintf(code, sizeof code, "\\u{%04x}", static_cast<unsigned>(c));
    return code;
  }
  return std::string(text.substr(at, *length));
}

}  // namespace

std::string log_text(std::string_view text, std::size_t max_bytes) {
  std::string out;
  out.reserve(text.size() < max_bytes ? text.size() : max_bytes);
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t length = 0;
    const std::string piece = escaped_piece(text, at, &length);
    if (out.size() + piece.size() > max_bytes) {
      out += "...(" + std::to_string(text.size() - at) + " more bytes)";
      break;
    }
    out += piece;
    at += length;
  }
  return out;
}

}  // namespace tumble::sim

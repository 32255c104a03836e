#include "model/inert_text.hpp"

#include <charconv>
#include <cstdint>
#include <cstdio>

namespace sweepgen {
namespace {

// The length of the valid UTF-8 sequence of two or more bytes at text[i], or 0 (RFC 3629: no
// overlong forms, no surrogates, nothing above U+10FFFF); its code point in `code`.
std::size_t utf8_sequence(std::string_view text, std::size_t i, std::uint32_t& code) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[i + k]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xbf;  // the second byte's range
  if (lead >= 0xc2 && lead <= 0xdf) length = 2;
  else if (lead >= 0xe0 && lead <= 0xef) length = 3, low = lead == 0xe0 ? 0xa0 : 0x80, high = lead == 0xed ? 0x9f : 0xbf;
  else if (lead >= 0xf0 && lead <= 0xf4) length = 4, low = lead == 0xf0 ? 0x90 : 0x80, high = lead == 0xf4 ? 0x8f : 0xbf;
  if (length == 0 || i + length > text.size() || byte(1) < low || byte(1) > high) return 0;
  code = lead & (length == 2 ? 0x1f : length == 3 ? 0x0f : 0x07);
  for (std::size_t k = 1; k < length; ++k) {
    if (byte(k) < 0x80 || byte(k) > 0xbf) return 0;
    code = (code << 6) | (byte(k) & 0x3f);
  }
  return length;
}

// C1 controls, and the bidirectional and invisible format characters that make text display
// otherwise than it reads (gcc's -Wbidi-chars, "Trojan Source").
bool hidden(std::uint32_t code) {
  return code <= 0x9f || code == 0x061c || (code >= 0x200b && code <= 0x200f) || (code >= 0x2028 && code <= 0x202e) ||
         (code >= 0x2060 && code <= 0x206f) || code == 0xfeff;
}

}  // namespace

std::string escaped_text(std::string_view text, char quote, std::size_t shown) {
  std::string out;
  if (quote) out += quote;
  std::size_t i = 0;
  char previous = 0;
  while (i < text.size() && i < shown) {
    const char c = text[i];
    const auto byte = static_cast<unsigned char>(c);
    char escape[16];
    if (byte >= 0x80) {
      std::uint32_t code = 0;
      const std::size_t length = utf8_sequence(text, i, code);
      if (length == 0) {
        std::snprintf(escape, sizeof escape, "\\x%02x", byte);
        out += escape;
        ++i;
      } else {
        if (hidden(code)) {
          std::snprintf(escape, sizeof escape, "\\u{%04x}", static_cast<unsigned>(code));
          out += escape;
        } else {
          out.append(text.substr(i, length));
        }
        i += length;
      }
      previous = 0;
      continue;
    }
    switch (c) {
      case '\\': out += "\\\\"; break;
      case '\0': out += "\\0"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (quote && c == quote) {
          out += '\\';
          out += c;
        } else if ((c == '/' && previous == '*') || (c == '*' && previous == '/') || (c == '?' && previous == '?')) {
          out += '\\';
          out += c;
        } else if (byte < 0x20 || byte == 0x7f) {
          std::snprintf(escape, sizeof escape, "\\x%02x", byte);
          out += escape;
        } else {
          out += c;
        }
    }
    previous = c;
    ++i;
  }
  if (quote) out += quote;
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

std::string quote_name(std::string_view name) { return escaped_text(name, '\'', kShownBytes); }

std::string shortest(double value) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

std::string inert_text(std::string_view name, std::size_t shown) {
  bool plain = !name.empty() && name.size() <= shown;
  for (std::size_t i = 0; plain && i < name.size(); ++i) {
    const char c = name[i], next = i + 1 < name.size() ? name[i + 1] : '\0';
    plain = c >= 0x20 && c <= 0x7e && c != '\\' && c != '\'' && !(c == '/' && next == '*') && !(c == '*' && next == '/') &&
            !(c == '?' && next == '?');
  }
  return plain ? std::string(name) : escaped_text(name, '\'', shown);
}

std::string listed(const std::vector<std::string>& items, std::size_t shown) {
  std::string out;
  for (std::size_t k = 0; k < items.size() && k < shown; ++k) out += (k ? ", " : "") + items[k];
  if (items.size() > shown) out += " and " + std::to_string(items.size() - shown) + " more";
  return out;
}

}  // namespace sweepgen

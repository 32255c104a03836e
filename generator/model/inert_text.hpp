// Text taken from an input file (a link or joint name, a file name, a token the reader could not
// read) as sweepgen writes it anywhere: in the comments of the generated code, in `sweepgen info`,
// in messages. Such text may hold anything the file format can carry: a line break (in XML as
// `&#10;`), a comment's end `*/`, a backslash (which before a line break continues a `//`
// comment into the next line), `??/` (a trigraph that -Wall reports), bidirectional controls
// (which -Wbidi-chars reports and which make code read otherwise than it compiles), NUL (YAML
// "\0"), bytes that are not UTF-8, a megabyte of one token. Written through these functions it is
// inert: one line of printable text, valid UTF-8, at most kShownBytes of the input and a count
// of the rest.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace sweepgen {

// How much of one input text is shown (of a path, which the system bounds, all); the rest is
// counted.
constexpr std::size_t kShownBytes = 100;
constexpr std::size_t kShownPathBytes = 4096;

// `text` escaped: backslash as \\, `quote` (if not NUL) as \<quote>, NUL as \0, newline \n, tab \t,
// carriage return \r, other control bytes and bytes that are not part of valid UTF-8 as \xNN;
// C1 controls, bidirectional and invisible format characters (U+061C, U+200B..U+200F,
// U+2028..U+202E, U+2060..U+206F, U+FEFF) as \u{XXXX}; a '/' after '*' and a '*' after '/' with
// a backslash before them (no comment starts or ends inside), a '?' after '?' as \? (no
// trigraph). Other valid UTF-8 stays as it is. Cut after `shown` bytes of the input, at a
// character's end, with "..." and the input's size in bytes after `quote` closes it.
std::string escaped_text(std::string_view text, char quote, std::size_t shown);

// A name taken from the input, as messages print it: in single quotes, escaped and cut
// (escaped_text), so that a name holding ": ", a quote or a line break cannot blur where the
// element ends and the reason begins.
std::string quote_name(std::string_view name);

// The shortest text that reads back as `value` (std::to_chars): a number in a message.
std::string shortest(double value);

// The one way a name or path from an input file reaches generated code (comments of the .hpp,
// .cpp and .cmake) and `sweepgen info`: a plain name (printable ASCII but for '\' and '\'', no
// "/*", "*/" or "??", at most `shown` bytes) as it is, so that bundled robots read as before,
// anything else quoted and escaped as quote_name (but cut after `shown` bytes): never a line
// break, a comment's end or a trailing backslash.
std::string inert_text(std::string_view name, std::size_t shown = kShownBytes);

// Texts (already inert) joined by ", ", at most `shown` of them, then "and N more".
std::string listed(const std::vector<std::string>& items, std::size_t shown = 10);

}  // namespace sweepgen

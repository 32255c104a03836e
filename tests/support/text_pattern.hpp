// A regular expression for the tests' checks of text (generated code, command output, docs),
// compiled once: libstdc++'s <regex> is all templates, and each test object that searched,
// matched or replaced with it instantiated them again (2.4 to 4.1 s of g++ each); here only
// text_pattern.cpp includes it. The same expressions and answers as std::regex's defaults
// (ECMAScript; a bad expression throws std::regex_error).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace sweepgen::test {

// One match: [0] the whole match, [i] group i. As std::smatch's, a group that took no part in the
// match reads "" (matched(i) tells it from an empty one), and so does every group of no match (a
// failed search or match leaves it empty).
struct Match {
  std::vector<std::string> groups;
  std::vector<bool> took_part;

  bool empty() const { return groups.empty(); }
  std::size_t size() const { return groups.size(); }
  const std::string& operator[](std::size_t i) const;
  bool matched(std::size_t i) const { return i < took_part.size() && took_part[i]; }
};

class Pattern {
 public:
  explicit Pattern(const std::string& expression);
  ~Pattern();
  Pattern(Pattern&&) noexcept;
  Pattern& operator=(Pattern&&) noexcept;

  // std::regex_search: somewhere in `text`; with `match`, its groups (empty where none).
  bool search(const std::string& text) const;
  bool search(const std::string& text, Match& match) const;
  // std::regex_match: the whole of `text`.
  bool matches(const std::string& text) const;
  bool matches(const std::string& text, Match& match) const;
  // std::regex_replace: every match replaced by `format` ("$&" the match, "$1" its first group).
  std::string replace(const std::string& text, const std::string& format) const;
  // std::sregex_iterator: every match in `text`, in order.
  std::vector<Match> all(const std::string& text) const;

 private:
  struct Compiled;
  std::unique_ptr<const Compiled> compiled_;
};

}  // namespace sweepgen::test

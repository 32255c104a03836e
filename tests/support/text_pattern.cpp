// The tests' regular expressions over std::regex, instantiated here alone (text_pattern.hpp).
#include "support/text_pattern.hpp"

#include <regex>

namespace sweepgen::test {

namespace {

Match groups_of(const std::smatch& m) {
  Match match;
  for (const auto& group : m) {
    match.groups.push_back(group.str());
    match.took_part.push_back(group.matched);
  }
  return match;
}

// `found`, with `match` set to m's groups where it is, else empty.
bool record(bool found, const std::smatch& m, Match& match) {
  match = found ? groups_of(m) : Match{};
  return found;
}

}  // namespace

const std::string& Match::operator[](std::size_t i) const {
  static const std::string none;
  return i < groups.size() ? groups[i] : none;
}

struct Pattern::Compiled {
  std::regex regex;
};

Pattern::Pattern(const std::string& expression) : compiled_(new Compiled{std::regex(expression)}) {}
Pattern::~Pattern() = default;
Pattern::Pattern(Pattern&&) noexcept = default;
Pattern& Pattern::operator=(Pattern&&) noexcept = default;

bool Pattern::search(const std::string& text) const { return std::regex_search(text, compiled_->regex); }

bool Pattern::search(const std::string& text, Match& match) const {
  std::smatch m;
  return record(std::regex_search(text, m, compiled_->regex), m, match);
}

bool Pattern::matches(const std::string& text) const { return std::regex_match(text, compiled_->regex); }

bool Pattern::matches(const std::string& text, Match& match) const {
  std::smatch m;
  return record(std::regex_match(text, m, compiled_->regex), m, match);
}

std::string Pattern::replace(const std::string& text, const std::string& format) const {
  return std::regex_replace(text, compiled_->regex, format);
}

std::vector<Match> Pattern::all(const std::string& text) const {
  std::vector<Match> found;
  for (std::sregex_iterator it(text.begin(), text.end(), compiled_->regex), end; it != end; ++it)
    found.push_back(groups_of(*it));
  return found;
}

}  // namespace sweepgen::test

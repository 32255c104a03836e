#include "model/error.hpp"

#include <algorithm>

namespace sweepgen {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

// The candidate that is `name` with a prefix or suffix added or dropped at a '_' (left_hand for
// left_hand_link, panda_link8 for link8): vendors' names differ by such affixes, which an edit
// distance counts letter by letter. The closest in length; none for names shorter than 3.
const std::string* affix_match(const std::string& name, const std::vector<std::string>& candidates) {
  const auto joins = [](const std::string& shorter, const std::string& longer) {
    if (shorter.size() < 3 || shorter.size() >= longer.size()) return false;
    const std::size_t extra = longer.size() - shorter.size();
    return (longer.compare(0, shorter.size(), shorter) == 0 && longer[shorter.size()] == '_') ||
           (longer.compare(extra, shorter.size(), shorter) == 0 && longer[extra - 1] == '_');
  };
  const std::string* best = nullptr;
  const auto gap = [&name](const std::string& c) { return c.size() > name.size() ? c.size() - name.size() : name.size() - c.size(); };
  for (const auto& candidate : candidates)
    if ((joins(name, candidate) || joins(candidate, name)) && (best == nullptr || gap(candidate) < gap(*best)))
      best = &candidate;
  return best;
}

}  // namespace

std::string element_path(const std::string& parent, const std::string& key) {
  const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
  const std::string shown = plain ? key : quote_name(key);
  return parent.empty() ? shown : parent + "." + shown;
}

std::string nearest_name_hint(const std::string& name, const std::vector<std::string>& candidates) {
  const std::string* best = nullptr;
  std::size_t best_distance = 0;
  // A hint is for a slip of a few letters: names far apart in length, or too long to be shown
  // whole, are not compared (the distance takes the product of the lengths).
  const std::size_t most = std::max<std::size_t>(3, name.size() / 2);
  if (name.size() > kShownBytes) return "";
  for (const auto& candidate : candidates) {
    if (candidate.size() > name.size() + most || name.size() > candidate.size() + most) continue;
    const std::size_t d = edit_distance(name, candidate);
    if (best == nullptr || d < best_distance) {
      best = &candidate;
      best_distance = d;
    }
  }
  // A slip of a letter or two first, then a name with an affix added or dropped, then a larger slip.
  if (best == nullptr || best_distance > 2) {
    if (const std::string* affixed = affix_match(name, candidates)) {
      best = affixed;
      best_distance = 0;
    }
  }
  if (best == nullptr || best_distance > most) return "";
  return " (did you mean " + quote_name(*best) + "?)";
}

}  // namespace sweepgen

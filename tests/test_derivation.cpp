// docs/derivation.md is the one statement of the equations: every equation there has
// one tag, written "(TAG)" at the start of its line; the code, the generated files and the docs
// cite tags as "(TAG)" or "(TAG, TAG, ...)". This test reads the repository's text files and
// checks that every cited tag is defined, every defined tag is cited by the generator's code
// (generator/), and no file depends on documents outside the repository.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/bundled_robots.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;

const fs::path kSource = SWEEPGEN_SOURCE_DIR;
const fs::path kDerivation = kSource / "docs" / "derivation.md";

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The repository's text files, by path relative to the source directory: the folders and files
// a clone has, without build trees, git's own files and the fuzz inputs (arbitrary bytes).
std::map<std::string, std::string> repository_texts() {
  static const std::set<std::string> extensions = {".cpp", ".hpp", ".h", ".in", ".md", ".mustache", ".cmake",
                                                   ".txt", ".sh", ".yaml", ".urdf", ".json", ".py", ""};
  std::map<std::string, std::string> texts;
  for (const char* top : {"generator", "templates", "generated", "tests", "docs", "bench", "cmake", "fuzz", "robots", ".ci"}) {
    const fs::path dir = kSource / top;
    if (!fs::exists(dir)) continue;
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
      const std::string relative = fs::relative(it->path(), kSource).generic_string();
      if (it->is_directory() && (relative == "fuzz/corpus" || relative == "fuzz/regressions")) {
        it.disable_recursion_pending();
        continue;
      }
      if (it->is_regular_file() && extensions.count(it->path().extension().string()))
        texts[relative] = read(it->path());
    }
  }
  for (const char* file : {"README.md", "CMakeLists.txt", "CMakePresets.json"}) texts[file] = read(kSource / file);
  return texts;
}

// Tags defined in docs/derivation.md: "(TAG)" first on a line (indentation allowed).
std::vector<std::string> defined_tags() {
  std::vector<std::string> tags;
  std::istringstream lines(read(kDerivation));
  const test::Pattern definition(R"(^\s*\(([A-Z][0-9]+)\)\s)");
  test::Match match;
  for (std::string line; std::getline(lines, line);)
    if (definition.search(line, match)) tags.push_back(match[1]);
  return tags;
}

// Tags cited in `text`: "(TAG)" or "(TAG, TAG, ...)", except definitions (a tag first on its line).
// In C++ (`comments_only`) only comments cite: a call with one argument such as a tag is code.
std::vector<std::string> cited_tags(const std::string& text, bool comments_only) {
  std::vector<std::string> tags;
  const test::Pattern citation(R"(\(([A-Z][0-9]+(?:, [A-Z][0-9]+)*)\))");
  const test::Pattern definition(R"(^\s*\([A-Z][0-9]+\)\s)");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (comments_only) line = line.find("//") == std::string::npos ? "" : line.substr(line.find("//"));
    std::string rest = definition.search(line) ? line.substr(line.find(')') + 1) : line;
    for (const test::Match& cited : citation.all(rest)) {
      std::istringstream list(cited[1]);
      for (std::string tag; std::getline(list, tag, ',');) tags.push_back(tag.substr(tag.find_first_not_of(' ')));
    }
  }
  return tags;
}

TEST(Derivation, EveryEquationHasOneTag) {
  const std::vector<std::string> tags = defined_tags();
  const std::set<std::string> unique(tags.begin(), tags.end());
  EXPECT_EQ(unique.size(), tags.size()) << "a tag is defined twice in docs/derivation.md";
  // The sections of the derivation: frames and model, outward, inward, joint-inertia policy,
  // constraint multipliers, solver sweeps, exact saturation, commanded torque.
  for (const char* tag : {"F1", "F4", "O1", "O4", "I0", "I5", "J1", "C1", "C3", "S1", "S5", "X1", "T1", "T2"})
    EXPECT_TRUE(unique.count(tag)) << tag << " is not defined in docs/derivation.md";
}

TEST(Derivation, EveryCitedTagExistsAndEveryTagIsCitedByTheCode) {
  const std::vector<std::string> defined = defined_tags();
  const std::set<std::string> tags(defined.begin(), defined.end());
  std::set<std::string> cited_by_code;
  std::size_t citations = 0, generated_citations = 0;
  for (const auto& [path, text] : repository_texts()) {
    const std::string extension = fs::path(path).extension().string();
    const bool cpp = extension == ".cpp" || extension == ".hpp" || extension == ".h" || extension == ".in" ||
                     extension == ".mustache";
    for (const std::string& tag : cited_tags(text, cpp)) {
      ++citations;
      EXPECT_TRUE(tags.count(tag)) << path << " cites (" << tag << "), which docs/derivation.md does not define";
      if (path.rfind("generator/", 0) == 0) cited_by_code.insert(tag);
      if (path.rfind("generated/", 0) == 0) ++generated_citations;
    }
  }
  for (const std::string& tag : tags)
    EXPECT_TRUE(cited_by_code.count(tag)) << "(" << tag << ") is cited by no file of generator/";
  // The generated files cite the tags of what they store (generator/emit/equations.cpp).
  EXPECT_GT(generated_citations, 100u);
  std::cout << "[derivation] " << tags.size() << " tags, " << citations << " citations, " << generated_citations
            << " of them in generated/" << std::endl;
}

TEST(Derivation, NoFileNeedsDocumentsOutsideTheRepository) {
  // Spelt in two pieces so that this file does not name them itself.
  const std::vector<std::string> outside = {std::string("../") + "shared", std::string("achd") + "-equations"};
  for (const auto& [path, text] : repository_texts())
    for (const std::string& name : outside)
      EXPECT_EQ(text.find(name), std::string::npos) << path << " refers to " << name << ", which a clone does not have";
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

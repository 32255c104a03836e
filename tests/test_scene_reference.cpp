// docs/scene.md, the scene format's reference, against the parser: the page documents exactly the
// keys the parser accepts (scene::scene_keys(), the one table the parser takes each mapping's keys
// from), and every key's example, added to the page's minimal scene, is read and its chain loaded.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "model/error.hpp"
#include "scene/scene.hpp"
#include "support/temp_dir.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;

const fs::path kSource = SWEEPGEN_SOURCE_DIR;
const fs::path kPage = kSource / "docs" / "scene.md";
const fs::path kUrdf = kSource / "robots" / "mobile_panda_gripper" / "mobile_panda_gripper.urdf";

struct DocumentedKey {
  std::string key;      // its path, as the heading "### `key`" writes it
  std::string example;  // the first ```yaml block after the heading
};

struct Page {
  std::string minimal_scene;  // the first ```yaml block of the page, before any key's heading
  std::vector<DocumentedKey> keys;
};

Page read_page() {
  Page page;
  std::istringstream lines(test::read_text(kPage));
  const test::Pattern heading(R"(^### `([^`]+)`\s*$)");
  test::Match match;
  std::string* block = nullptr;  // the block being read, if any
  bool want_block = true;        // the next block is the minimal scene's or a key's example
  for (std::string line; std::getline(lines, line);) {
    if (block) {
      if (line == "```") {
        block = nullptr;
      } else {
        *block += line + "\n";
      }
    } else if (heading.matches(line, match)) {
      page.keys.push_back({match[1], ""});
      want_block = true;
    } else if (line == "```yaml" && want_block) {
      block = page.keys.empty() ? &page.minimal_scene : &page.keys.back().example;
      want_block = false;
    }
  }
  return page;
}

// Whether `node` holds the key path `key` ("a.b", "a[].b": b in some element of a's list).
bool holds(const YAML::Node& node, const std::string& key) {
  const std::size_t dot = key.find('.');
  std::string first = key.substr(0, dot);
  const bool list = first.size() > 2 && first.compare(first.size() - 2, 2, "[]") == 0;
  if (list) first.resize(first.size() - 2);
  if (!node.IsMap() || !node[first]) return false;
  if (dot == std::string::npos) return !list;
  const YAML::Node value = node[first];
  const std::string rest = key.substr(dot + 1);
  if (!list) return holds(value, rest);
  if (!value.IsSequence()) return false;
  for (const YAML::Node& element : value)
    if (holds(element, rest)) return true;
  return false;
}

TEST(SceneReference, DocumentsExactlyTheKeysTheParserAccepts) {
  const Page page = read_page();
  ASSERT_FALSE(page.keys.empty()) << kPage;
  std::vector<std::string> documented;
  for (const DocumentedKey& k : page.keys) documented.push_back(k.key);
  const std::vector<std::string>& accepted = scene::scene_keys();
  for (const std::string& key : accepted)
    EXPECT_EQ(std::count(documented.begin(), documented.end(), key), 1) << "accepted key '" << key << "': " << kPage
                                                                         << " must document it once";
  for (const std::string& key : documented)
    EXPECT_NE(std::find(accepted.begin(), accepted.end(), key), accepted.end())
        << kPage << " documents '" << key << "', which the parser does not accept";
}

TEST(SceneReference, EveryExampleIsReadAndItsChainLoads) {
  const Page page = read_page();
  ASSERT_FALSE(page.minimal_scene.empty()) << kPage << ": no minimal scene";
  test::TempDir dir;
  fs::copy_file(kUrdf, dir.path() / kUrdf.filename());
  std::vector<std::pair<std::string, std::string>> cases{{"minimal scene", page.minimal_scene}};
  for (const DocumentedKey& k : page.keys) {
    SCOPED_TRACE(k.key);
    ASSERT_FALSE(k.example.empty()) << kPage << ": no example for '" << k.key << "'";
    EXPECT_TRUE(holds(YAML::Load(k.example), k.key)) << "the example does not use the key:\n" << k.example;
    cases.emplace_back(k.key, k.example);
  }
  for (const auto& [key, example] : cases) {
    SCOPED_TRACE(key);
    YAML::Node scene = YAML::Load(page.minimal_scene);
    const YAML::Node added = YAML::Load(example);
    if (added["tips"]) scene.remove("tip");  // the two are alternatives
    for (const auto& entry : added) scene[entry.first.Scalar()] = entry.second;
    YAML::Emitter text;
    text << scene;
    const std::string file = dir.write("example.yaml", std::string(text.c_str()) + "\n");
    try {
      scene::load_scene_chain(scene::load_scene(file));
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what() << "\n--- scene:\n" << text.c_str();
    }
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

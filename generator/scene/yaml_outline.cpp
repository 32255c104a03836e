#include "scene/yaml_outline.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/mark.h>
#include <yaml-cpp/parser.h>

#include <sstream>
#include <vector>

#include "model/error.hpp"
#include "model/input_limits.hpp"

namespace sweepgen::scene {
namespace {

// Counts each collection's entries and the document's nodes as the parser reports them, and
// stops the parse where a count passes its limit.
class OutlineCounter : public YAML::EventHandler {
 public:
  explicit OutlineCounter(std::string file) : file_(std::move(file)) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, ""); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { node(mark, ""); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string& value) override {
    node(mark, value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, false);
  }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, true);
  }
  void OnSequenceEnd() override { collections_.pop_back(); }
  void OnMapEnd() override { collections_.pop_back(); }

 private:
  struct Collection {
    YAML::Mark mark;
    bool mapping = false;
    std::size_t entries = 0;  // items of a sequence, keys and values of a mapping
    std::string key;          // a mapping's last scalar key
  };

  // A node inside the innermost collection (a mapping's key or value, or a sequence's item).
  void node(const YAML::Mark& mark, const std::string& scalar) {
    if (++nodes_ > kMaxYamlNodes)
      fail(mark, "more than " + std::to_string(kMaxYamlNodes) + " values in the scene, the limit (README, \"Limits\")");
    if (collections_.empty()) return;
    Collection& c = collections_.back();
    if (c.mapping && c.entries % 2 == 0) c.key = scalar;
    if (++c.entries > (c.mapping ? 2 : 1) * kMaxYamlItems)
      fail(c.mark, std::string(c.mapping ? "a mapping" : "a sequence") + " of more than " + std::to_string(kMaxYamlItems) +
                       " entries, more than any scene key takes (the limit; README, \"Limits\")");
  }
  void open(const YAML::Mark& mark, bool mapping) {
    node(mark, "");
    collections_.push_back({mark, mapping, 0, ""});
  }

  // The element path of the innermost collection, as the scene's messages spell it.
  std::string element() const {
    std::string path;
    for (std::size_t k = 0; k + 1 < collections_.size(); ++k) {
      const Collection& c = collections_[k];
      if (c.mapping && c.key.size() <= kShownBytes)
        path = element_path(path, c.key);
      else if (c.mapping)  // a long key, cut
        path += (path.empty() ? "" : ".") + quote_name(c.key);
      else
        path += "[" + std::to_string(c.entries - 1) + "]";
    }
    return path.empty() ? "scene" : path;
  }
  [[noreturn]] void fail(const YAML::Mark& mark, const std::string& reason) const {
    throw InputError(file_ + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1), element(), reason);
  }

  std::string file_;
  std::vector<Collection> collections_;
  std::size_t nodes_ = 0;
};

}  // namespace

void check_yaml_outline(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  OutlineCounter counter(file);
  parser.HandleNextDocument(counter);
}

}  // namespace sweepgen::scene

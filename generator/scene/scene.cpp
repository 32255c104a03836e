#include "scene/scene.hpp"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "model/error.hpp"
#include "model/input_limits.hpp"
#include "scene/cpp_names.hpp"
#include "scene/yaml_outline.hpp"
#include "solver/constraint_row_steps.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen::scene {
namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

std::string format_mark(const std::string& file, const YAML::Mark& mark) {
  if (mark.is_null()) return file;
  return file + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
}

// What YAML::Load passes over without a word: a second document (it reads the first), and tags
// (`!!str`, `!custom`), which the reader would not honour. Seen in the parser's events, each
// once: an alias is not followed again.
class UnreadYaml : public YAML::EventHandler {
 public:
  explicit UnreadYaml(std::string file) : file_(std::move(file)) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1)
      throw InputError(format_mark(file_, mark), "YAML", "a second document; a scene file holds one ('---' starts another)");
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, const std::string&) override { check(mark, tag); }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, YAML::EmitterStyle::value) override {
    check(mark, tag);
  }
  void OnMapStart(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t, YAML::EmitterStyle::value) override {
    check(mark, tag);
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnSequenceEnd() override {}
  void OnMapEnd() override {}

 private:
  // "?": untagged, "!": quoted (or the bare '!', which means just that).
  void check(const YAML::Mark& mark, const std::string& tag) const {
    if (tag != "?" && tag != "!" && !tag.empty())
      throw InputError(format_mark(file_, mark), "YAML",
                       "a tag (" + quote_name(tag) + "): the scene reads none; write the value without it");
  }

  std::string file_;
  std::size_t documents_ = 0;
};

// Throws InputError where `text` holds more than one document or a tag (UnreadYaml).
void refuse_unread_yaml(const std::string& text, const std::string& file) {
  std::istringstream stream(text);
  YAML::Parser parser(stream);
  UnreadYaml handler(file);
  while (parser.HandleNextDocument(handler)) {
  }
}

// A node of the scene document with its element path and position.
struct Item {
  YAML::Node node;
  std::string element;
  YAML::Mark mark;
};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const Item& item) const { return format_mark(file_, item.mark); }
  [[noreturn]] void fail(const Item& item, const std::string& reason) const {
    // The top level has no element path of its own (a non-scalar or empty top-level key): name it.
    throw InputError(where(item), item.element.empty() ? "scene" : item.element, reason);
  }

  // The mapping's entries, in order; fails on a non-mapping, non-string keys, duplicate keys and
  // keys not in `allowed` (with a hint).
  std::vector<std::pair<Item, Item>> entries(const Item& map, const std::vector<std::string>& allowed) const {
    if (!map.node.IsMap()) fail(map, "expected a mapping (key: value), got " + kind(map.node));
    std::vector<std::pair<Item, Item>> out;
    std::map<std::string, YAML::Mark> seen;
    for (auto it = map.node.begin(); it != map.node.end(); ++it) {
      const YAML::Node key = it->first;
      Item key_item{key, map.element, mark_of(key, map.mark)};
      if (!key.IsScalar()) fail(key_item, "keys must be plain names, got " + kind(key));
      const std::string name = key.Scalar();
      key_item.element = element_path(map.element, name);
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
        fail(key_item, "unknown key " + quote_name(name) + nearest_name_hint(name, allowed) +
                           " (allowed here: " + join(allowed) + ")");
      if (const auto previous = seen.find(name); previous != seen.end())
        fail(key_item, "duplicate key (first given at " + format_mark(file_, previous->second) + ")");
      seen.emplace(name, key_item.mark);
      // An empty value (null) has no position of its own worth reporting: use the key's.
      const YAML::Node value = it->second;
      out.push_back({key_item, Item{value, key_item.element, value.IsNull() ? key_item.mark : mark_of(value, key_item.mark)}});
    }
    return out;
  }

  std::vector<Item> sequence(const Item& item) const {
    if (!item.node.IsSequence()) fail(item, "expected a list, got " + kind(item.node));
    std::vector<Item> out;
    for (std::size_t i = 0; i < item.node.size(); ++i) {
      const YAML::Node element = item.node[i];
      out.push_back(Item{element, item.element + "[" + std::to_string(i) + "]", mark_of(element, item.mark)});
    }
    return out;
  }

  std::string string(const Item& item) const {
    if (!item.node.IsScalar()) fail(item, "expected a string, got " + kind(item.node));
    return item.node.Scalar();
  }

  double number(const Item& item) const {
    if (!item.node.IsScalar()) fail(item, "expected a number, got " + kind(item.node));
    double value = 0;
    if (!YAML::convert<double>::decode(item.node, value)) fail(item, "expected a number, got " + quote_name(item.node.Scalar()));
    if (!std::isfinite(value)) fail(item, "number is not finite (NaN or Inf)");
    return value;
  }

  long long integer(const Item& item) const {
    if (!item.node.IsScalar()) fail(item, "expected an integer, got " + kind(item.node));
    long long value = 0;
    if (!YAML::convert<long long>::decode(item.node, value))
      fail(item, "expected an integer, got " + quote_name(item.node.Scalar()));
    return value;
  }

  // One of `choices`, with a hint otherwise.
  std::string choice(const Item& item, const std::vector<std::string>& choices, const std::string& what) const {
    const std::string text = string(item);
    if (std::find(choices.begin(), choices.end(), text) == choices.end())
      fail(item, "unknown " + what + " " + quote_name(text) + nearest_name_hint(text, choices) + " (expected one of: " +
                     join(choices) + ")");
    return text;
  }


 private:
  static YAML::Mark mark_of(const YAML::Node& node, const YAML::Mark& fallback) {
    const YAML::Mark mark = node.Mark();
    return mark.is_null() ? fallback : mark;
  }
  static std::string kind(const YAML::Node& node) {
    switch (node.Type()) {
      case YAML::NodeType::Null: return "nothing";
      case YAML::NodeType::Scalar: return quote_name(node.Scalar());
      case YAML::NodeType::Sequence: return "a list";
      case YAML::NodeType::Map: return "a mapping";
      default: return "nothing";
    }
  }

  std::string file_;
};

// The keys of the mapping at `parent` (a path of scene_keys(): "" for the top level), in order.
std::vector<std::string> keys_under(const std::string& parent) {
  std::vector<std::string> keys;
  const std::string prefix = parent.empty() ? "" : parent + ".";
  for (const std::string& key : scene_keys())
    if (key.rfind(prefix, 0) == 0 && key.find('.', prefix.size()) == std::string::npos) keys.push_back(key.substr(prefix.size()));
  return keys;
}

std::vector<std::string> policy_names() {
  std::vector<std::string> names;
  for (solver::Policy p : {solver::Policy::original, solver::Policy::prioritize_external, solver::Policy::saturate,
                           solver::Policy::saturate_exact})
    names.push_back(solver::name(p));
  return names;
}

const std::vector<std::string>& scalar_names() {
  static const std::vector<std::string> names = {"double", "float"};
  return names;
}

// Fixed directions: a list of 6-vectors [moment; force], 1..6 of them, each taken as its unit
// vector; one not written as unit is said in the scene's notes (as the URDF loader says of joint
// axes). Each direction's position is recorded under its element path ("...directions[k]"), for
// the check against the chain (unmovable_direction).
std::vector<spatial::Force<double>> read_directions(const Reader& reader, const Item& list, Scene& scene) {
  const auto directions = reader.sequence(list);
  if (directions.empty() || directions.size() > solver::kMaxSetDirections)
    reader.fail(list, "at least 1 and at most 6 constraint directions in a set (a body has six), got " +
                          std::to_string(directions.size()));
  std::vector<spatial::Force<double>> fixed;
  const auto text = [](const Eigen::Matrix<double, 6, 1>& v) {
    std::ostringstream out;
    out.precision(17);
    out << "[" << v[0];
    for (int i = 1; i < 6; ++i) out << ", " << v[i];
    return out.str() + "]";
  };
  for (const Item& direction : directions) {
    const auto components = reader.sequence(direction);
    if (components.size() != 6)
      reader.fail(direction, "expected 6 numbers [moment; force], got " + std::to_string(components.size()));
    Eigen::Matrix<double, 6, 1> written;
    for (int i = 0; i < 6; ++i) written[i] = reader.number(components[i]);
    // A huge component's square overflows: scaled by the largest component first.
    Eigen::Matrix<double, 6, 1> v = written;
    if (!std::isfinite(v.norm())) v /= v.cwiseAbs().maxCoeff();
    if (!(v.norm() > 1e-12)) reader.fail(direction, "a zero direction constrains nothing (norm " + std::to_string(v.norm()) + ")");
    v /= v.norm();
    if (v != written)
      scene.notes.push_back(reader.where(direction) + ": constraint direction " + text(written) +
                            " taken as the unit vector " + text(v));
    spatial::Force<double> f;
    f.moment = v.head<3>();
    f.force = v.tail<3>();
    fixed.push_back(f);
    scene.locations[direction.element] = reader.where(direction);
  }
  return fixed;
}

// A frame's pose on its link, {xyz: [x, y, z], rpy: [roll, pitch, yaw]} as a URDF <origin> (either
// key may be left out: zeros), as the motion transform link -> frame.
model::Transform read_origin(const Reader& reader, const Item& origin) {
  model::Vec3 xyz = model::Vec3::Zero(), rpy = model::Vec3::Zero();
  for (const auto& [k, v] : reader.entries(origin, {"xyz", "rpy"})) {
    const auto components = reader.sequence(v);
    if (components.size() != 3) reader.fail(v, "expected 3 numbers, got " + std::to_string(components.size()));
    model::Vec3& into = k.node.Scalar() == "xyz" ? xyz : rpy;
    for (int i = 0; i < 3; ++i) into[i] = reader.number(components[static_cast<std::size_t>(i)]);
  }
  return model::origin_transform(xyz, rpy);
}

// drivers.constraints: a count (run-time directions on the tip), {directions} (fixed, on the
// tip), or a list of sets {link, count} / {link, directions}. Links are checked against the
// chain later (load_scene_chain), at the locations recorded here.
void read_constraints(const Reader& reader, const Item& value, Scene& scene) {
  solver::DriverLayout& layout = scene.layout;
  const auto add = [&](solver::ConstraintSet set) {
    layout.constraints += set.count;
    layout.sets.push_back(std::move(set));
  };
  if (value.node.IsMap()) {
    const auto fields = reader.entries(value, keys_under("drivers.constraints"));
    if (fields.empty()) reader.fail(value, "missing key 'directions'");
    auto fixed = read_directions(reader, fields[0].second, scene);
    add(solver::ConstraintSet::on("", fixed.size(), fixed));
  } else if (value.node.IsSequence()) {
    const auto sets = reader.sequence(value);
    if (sets.empty()) reader.fail(value, "an empty list of constraint sets; leave 'constraints' out for none");
    if (sets.size() > solver::kMaxConstraints)
      reader.fail(value, "at most " + std::to_string(solver::kMaxConstraints) + " constraint directions in all, got " +
                             std::to_string(sets.size()) + " sets");
    std::map<std::pair<std::string, std::string>, Item> seen;  // (link, relative_to)
    for (std::size_t c = 0; c < sets.size(); ++c) {
      std::map<std::string, Item> field;
      for (const auto& [k, v] : reader.entries(sets[c], keys_under("drivers.constraints[]"))) field.emplace(k.node.Scalar(), v);
      const auto get = [&](const char* key) -> std::optional<Item> {
        const auto found = field.find(key);
        return found == field.end() ? std::nullopt : std::optional<Item>(found->second);
      };
      const std::optional<Item> link_item = get("link"), count_item = get("count"), directions_item = get("directions");
      if (!link_item) reader.fail(sets[c], "missing key 'link' (the link the set acts on)");
      if (count_item.has_value() == directions_item.has_value())
        reader.fail(sets[c], "give exactly one of 'count' (run-time directions) and 'directions' (fixed ones)");
      solver::ConstraintSet set;
      set.link = reader.string(*link_item);
      if (set.link.empty()) reader.fail(*link_item, "link name is empty");
      if (const auto at = get("at")) set.at = read_origin(reader, *at);
      if (const auto relative_to = get("relative_to")) {
        set.relative_to = reader.string(*relative_to);
        if (set.relative_to.empty()) reader.fail(*relative_to, "link name is empty");
        scene.locations["drivers.constraints[" + std::to_string(c) + "].relative_to"] = reader.where(*relative_to);
      }
      if (const auto relative_at = get("relative_at")) {
        if (!set.relative())
          reader.fail(*relative_at, "relative_at places frame B on the link 'relative_to' names; give relative_to");
        set.relative_at = read_origin(reader, *relative_at);
      }
      const std::pair<std::string, std::string> key{set.link, set.relative_to};
      if (const auto previous = seen.find(key); previous != seen.end())
        reader.fail(*link_item, "a second constraint set on link " + quote_name(set.link) +
                                    (set.relative() ? " relative to " + quote_name(set.relative_to) : "") + " (first at " +
                                    reader.where(previous->second) + "); give one set with all its directions");
      seen.emplace(key, *link_item);
      if (count_item) {
        const long long count = reader.integer(*count_item);
        if (count < 1 || count > static_cast<long long>(solver::kMaxSetDirections))
          reader.fail(*count_item, "at least 1 and at most 6 constraint directions in a set (a body has six), got " +
                                       std::to_string(count));
        set.count = static_cast<std::size_t>(count);
      } else {
        set.fixed = read_directions(reader, *directions_item, scene);
        set.count = set.fixed.size();
      }
      scene.locations["drivers.constraints[" + std::to_string(c) + "].link"] = reader.where(*link_item);
      add(std::move(set));
    }
    if (layout.constraints > solver::kMaxConstraints)
      reader.fail(value, "at most " + std::to_string(solver::kMaxConstraints) + " constraint directions in all, got " +
                             std::to_string(layout.constraints));
  } else {
    const long long count = reader.integer(value);
    if (count < 0 || count > static_cast<long long>(solver::kMaxSetDirections))
      reader.fail(value, "constraint count must be in 0..6, got " + std::to_string(count));
    if (count > 0) add(solver::ConstraintSet::on("", static_cast<std::size_t>(count)));
  }
  scene.locations["drivers.constraints"] = reader.where(value);
}

// Reads `drivers:` into the layout (no tracks yet). `instances` collects every instance name
// with its item, for the decomposition.
void read_drivers(const Reader& reader, const Item& drivers, Scene& scene, std::map<std::string, Item>& instances) {
  const auto add_instance = [&](const Item& item) {
    const std::string name = reader.string(item);
    if (const std::string problem = driver_name_problem(name); !problem.empty()) reader.fail(item, problem);
    if (const auto previous = instances.find(name); previous != instances.end())
      reader.fail(item, "duplicate driver instance name " + quote_name(name) + " (first given at " + reader.where(previous->second) + ")");
    instances.emplace(name, item);
    return name;
  };
  for (const auto& [key, value] : reader.entries(drivers, keys_under("drivers"))) {
    const std::string& name = key.node.Scalar();
    // Before the instances are read one by one (names checked, tracks built, each traced).
    if (name != "constraints" && value.node.IsSequence() && instances.size() + value.node.size() > kMaxInstances)
      reader.fail(value, "more than " + std::to_string(kMaxInstances) + " driver instances (torques and external forces " +
                             "together), the limit (README, \"Limits\")");
    if (name == "torques") {
      for (const Item& item : reader.sequence(value)) scene.layout.torques.push_back(add_instance(item));
    } else if (name == "external_forces") {
      std::size_t index = 0;
      for (const Item& item : reader.sequence(value)) {
        std::optional<Item> name_item, link_item;
        for (const auto& [k, v] : reader.entries(item, keys_under("drivers.external_forces[]")))
          (k.node.Scalar() == "name" ? name_item : link_item) = v;
        if (!name_item) reader.fail(item, "missing key 'name'");
        if (!link_item) reader.fail(item, "missing key 'link'");
        solver::ExternalForceDriver driver;
        driver.name = add_instance(*name_item);
        driver.link = reader.string(*link_item);
        if (driver.link.empty()) reader.fail(*link_item, "link name is empty");
        scene.locations["drivers.external_forces[" + std::to_string(index) + "].link"] = reader.where(*link_item);
        scene.layout.external_forces.push_back(driver);
        ++index;
      }
    } else {  // constraints
      read_constraints(reader, value, scene);
    }
  }
}

// Builds the tracks from `decomposition:` (absent: decomposed).
void read_decomposition(const Reader& reader, const std::optional<Item>& decomposition, Scene& scene,
                        const std::map<std::string, Item>& instances) {
  solver::DriverLayout& layout = scene.layout;
  if (!decomposition) {
    layout.decompose_all();
    return;
  }
  if (!decomposition->node.IsSequence()) {
    if (!decomposition->node.IsScalar())
      reader.fail(*decomposition, "expected 'composed', 'decomposed' or a list of groups (lists of instance names)");
    const std::string mode = reader.choice(*decomposition, {"composed", "decomposed"}, "decomposition");
    mode == "composed" ? layout.compose_all() : layout.decompose_all();
    return;
  }
  std::vector<std::string> known = {"bias"};
  for (const auto& [name, item] : instances) known.push_back(name);
  std::map<std::string, std::size_t> torque_of, external_force_of;  // instance name -> index
  for (std::size_t i = 0; i < layout.torques.size(); ++i) torque_of.emplace(layout.torques[i], i);
  for (std::size_t i = 0; i < layout.external_forces.size(); ++i) external_force_of.emplace(layout.external_forces[i].name, i);
  std::map<std::string, Item> grouped;
  layout.tracks.clear();
  for (const Item& group : reader.sequence(*decomposition)) {
    const auto members = reader.sequence(group);
    if (members.empty()) reader.fail(group, "empty group");
    solver::Track track;
    for (const Item& member : members) {
      const std::string name = reader.string(member);
      if (name != "bias" && instances.count(name) == 0)
        reader.fail(member, "unknown driver instance " + quote_name(name) + nearest_name_hint(name, known) +
                                " (known: " + listed(known) + ")");
      if (const auto previous = grouped.find(name); previous != grouped.end())
        reader.fail(member, quote_name(name) + " is already in a group (at " + reader.where(previous->second) +
                                "); an instance can be on one track only");
      grouped.emplace(name, member);
      if (track.name.empty()) track.name = name;
      if (name == "bias") track.bias = true;
      else if (const auto t = torque_of.find(name); t != torque_of.end()) track.torques.push_back(t->second);
      else track.external_forces.push_back(external_force_of.at(name));
    }
    layout.tracks.push_back(track);
  }
  if (!grouped.count("bias")) layout.tracks.push_back(solver::Track{"bias", true, {}, {}});
  for (std::size_t i = 0; i < layout.torques.size(); ++i)
    if (!grouped.count(layout.torques[i])) layout.tracks.push_back(solver::Track{layout.torques[i], false, {i}, {}});
  for (std::size_t i = 0; i < layout.external_forces.size(); ++i)
    if (!grouped.count(layout.external_forces[i].name))
      layout.tracks.push_back(solver::Track{layout.external_forces[i].name, false, {}, {i}});
}

// Why prioritize_external cannot run on this layout, or "".
std::string unseparable_external_force(const solver::DriverLayout& layout) {
  for (const auto& track : layout.tracks) {
    if (track.external_forces.empty() || track.only_external_forces()) continue;
    std::vector<std::string> others;
    if (track.bias) others.push_back("the bias");
    for (auto i : track.torques) others.push_back("torque " + quote_name(layout.torques[i]));
    return "external force " + quote_name(layout.external_forces[track.external_forces.front()].name) + " shares track " +
           quote_name(track.name) + " with " + join(others);
  }
  return "";
}

}  // namespace

const std::vector<std::string>& scene_keys() {
  static const std::vector<std::string> keys = {
      "sweepgen_scene", "solver", "urdf", "root", "tip", "tips", "base", "gravity", "rotor_inertia",
      "snap_quarter_turns", "mimic", "locked_joints", "drivers", "drivers.torques", "drivers.external_forces",
      "drivers.external_forces[].name", "drivers.external_forces[].link", "drivers.constraints",
      "drivers.constraints.directions", "drivers.constraints[].link", "drivers.constraints[].count",
      "drivers.constraints[].directions", "drivers.constraints[].at", "drivers.constraints[].relative_to",
      "drivers.constraints[].relative_at", "decomposition", "policies", "scalars", "expose",
      "constraint_factorisation", "pivot_tolerance", "refinement", "constraint_rows", "outputs", "check_inputs", "derivatives"};
  return keys;
}

std::string Scene::location(const std::string& element) const {
  if (const auto it = locations.find(element); it != locations.end()) return it->second;
  return path.empty() ? "command line" : path;
}

solver::FlatLayout Scene::flat_layout(const model::Chain& loaded) const {
  return solver::FlatLayout::of(layout, loaded, outputs);
}

solver::SolverOptions Scene::solver_options() const {
  solver::SolverOptions options;
  options.gravity = gravity;
  options.constraint_factorisation = constraint_factorisation;
  options.pivot_tolerance = pivot_tolerance;
  options.refinement = refinement;
  return options;
}

Scene load_scene(const std::string& path) {
  const std::string text = read_input_file(path, kMaxSceneBytes, "scene");
  YAML::Node document;
  try {
    check_yaml_outline(text, path);  // before the nodes: their memory follows the entries
    refuse_unread_yaml(text, path);
    document = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    throw InputError(format_mark(path, e.mark), "YAML",
                     "collections nested more than " + std::to_string(kMaxYamlDepth) + " deep, the limit (README, \"Limits\")");
  } catch (const YAML::ParserException& e) {
    throw InputError(format_mark(path, e.mark), "YAML", "syntax error: " + escaped_text(e.msg, '\0', 4 * kShownBytes));
  }

  const Reader reader(path);
  const Item root{document, "", document.Mark().is_null() ? YAML::Mark() : document.Mark()};
  if (!document.IsMap()) {
    reader.fail(Item{document, "scene", root.mark}, document.IsNull() ? "the scene file is empty; expected a mapping with at least "
                                              "'sweepgen_scene', 'solver' and 'urdf'"
                                            : "expected a mapping (key: value) at the top level");
  }

  Scene scene;
  scene.path = path;
  std::map<std::string, Item> values;
  for (const auto& [key, value] : reader.entries(root, keys_under(""))) values.emplace(key.node.Scalar(), value);
  const auto get = [&](const std::string& key) -> std::optional<Item> {
    const auto it = values.find(key);
    return it == values.end() ? std::nullopt : std::optional<Item>(it->second);
  };
  const auto require = [&](const std::string& key, const std::string& what) {
    const auto item = get(key);
    if (!item) reader.fail(Item{document, key, root.mark}, "missing required key " + quote_name(key) + " (" + what + ")");
    return *item;
  };

  // Version first: a file of another version is reported as such, not by its first odd key.
  const Item version = require("sweepgen_scene", "the scene schema version, 1");
  if (reader.integer(version) != kSceneVersion)
    reader.fail(version, "unsupported scene version " + version.node.Scalar() + " (this sweepgen reads version " +
                             std::to_string(kSceneVersion) + ")");

  const Item solver_item = require("solver", "C++ namespace of the generated solver");
  scene.solver = reader.string(solver_item);
  if (const std::string problem = solver_namespace_problem(scene.solver); !problem.empty())
    reader.fail(solver_item, problem);

  const Item urdf = require("urdf", "path of the URDF file, relative to the scene file");
  const std::string urdf_text = reader.string(urdf);
  if (urdf_text.empty()) reader.fail(urdf, "path is empty");
  // The file system would read the path only up to the NUL (YAML "\0"): another file than named.
  if (urdf_text.find('\0') != std::string::npos) reader.fail(urdf, "path contains a NUL character");
  // A path goes into messages and the depfile as it is: one line of text.
  if (std::any_of(urdf_text.begin(), urdf_text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }))
    reader.fail(urdf, "path " + quote_name(urdf_text) + " contains a control character");
  const std::filesystem::path urdf_path(urdf_text);
  scene.chain.urdf = urdf_path.is_absolute()
                         ? urdf_path.lexically_normal().string()
                         : (std::filesystem::path(path).parent_path() / urdf_path).lexically_normal().string();
  scene.locations["urdf"] = reader.where(urdf);

  for (const char* key : {"root", "tip"}) {
    if (const auto item = get(key)) {
      const std::string link = reader.string(*item);
      if (link.empty()) reader.fail(*item, "link name is empty");
      (std::string(key) == "root" ? scene.chain.root_link : scene.chain.tip_link) = link;
      scene.locations[key] = reader.where(*item);
    }
  }

  if (const auto item = get("tips")) {
    if (const auto tip = get("tip"))
      reader.fail(*item, "give either 'tip' (one chain) or 'tips' (the tree of several), not both ('tip' at " +
                             reader.where(*tip) + ")");
    const auto tips = reader.sequence(*item);
    if (tips.empty()) reader.fail(*item, "at least one tip link is needed");
    std::map<std::string, Item> seen;
    for (std::size_t k = 0; k < tips.size(); ++k) {
      const Item& entry = tips[k];
      const std::string link = reader.string(entry);
      if (link.empty()) reader.fail(entry, "link name is empty");
      if (const auto previous = seen.find(link); previous != seen.end())
        reader.fail(entry, "tip " + quote_name(link) + " named twice (first at " + reader.where(previous->second) + ")");
      seen.emplace(link, entry);
      (scene.chain.tip_link.empty() ? scene.chain.tip_link : scene.chain.branch_tips.emplace_back()) = link;
      scene.locations[entry.element] = reader.where(entry);  // "tips[k]": a bad tip is reported at its own entry
    }
    scene.locations["tip"] = reader.where(*item);
  }

  if (const auto item = get("snap_quarter_turns"))
    scene.chain.snap_quarter_turns = reader.choice(*item, {"true", "false"}, "snap_quarter_turns value") == "true";

  if (const auto item = get("mimic")) {  // docs/derivation.md (M1)
    scene.chain.couple_mimics = reader.choice(*item, {"independent", "coupled"}, "mimic mode") == "coupled";
    scene.chain.mimic_location = "scene key mimic at " + reader.where(*item);
  }

  if (const auto item = get("base")) {
    scene.chain.floating_base = reader.choice(*item, {"fixed", "floating"}, "base") == "floating";
    scene.locations["base"] = reader.where(*item);
  }

  if (const auto item = get("gravity")) {
    const auto components = reader.sequence(*item);
    if (components.size() != 3) reader.fail(*item, "expected 3 numbers [x, y, z], got " + std::to_string(components.size()));
    for (int i = 0; i < 3; ++i) {
      scene.gravity[i] = reader.number(components[i]);
      if (const std::string problem = magnitude_problem(scene.gravity[i]); !problem.empty())
        reader.fail(components[i], "gravity component " + problem);
    }
  }

  // rotor_inertia and locked_joints: mappings from joint name to a number.
  const auto read_joint_numbers = [&](const Item& item, const std::string& key, const std::string& what,
                                      std::map<std::string, double>& values) {
    scene.locations[key] = reader.where(item);
    if (!item.node.IsMap()) reader.fail(item, "expected a mapping (joint name: " + what + ")");
    std::map<std::string, YAML::Mark> seen;
    for (auto it = item.node.begin(); it != item.node.end(); ++it) {
      Item name{it->first, item.element, it->first.Mark()};
      const std::string joint = reader.string(name);
      name.element = element_path(key, joint);
      if (const auto previous = seen.find(joint); previous != seen.end())
        reader.fail(name, "duplicate joint (first given at " + format_mark(path, previous->second) + ")");
      seen.emplace(joint, name.mark);
      const Item value{it->second, name.element, it->second.IsNull() ? name.mark : it->second.Mark()};
      values[joint] = reader.number(value);
      scene.locations[key + "." + joint] = reader.where(name);
      if (key == "rotor_inertia" && values[joint] < 0) reader.fail(value, "rotor inertia must be >= 0");
    }
  };
  if (const auto item = get("rotor_inertia")) {
    scene.chain.rotor_inertia_source = reader.where(*item);
    read_joint_numbers(*item, "rotor_inertia", "rotor inertia", scene.chain.rotor_inertia);
  }
  if (const auto item = get("locked_joints")) {
    read_joint_numbers(*item, "locked_joints", "position", scene.chain.locked_joints);
    for (const auto& [joint, position] : scene.chain.locked_joints)
      scene.chain.locked_joint_locations[joint] = scene.locations.at("locked_joints." + joint);
  }

  std::map<std::string, Item> instances;
  if (const auto item = get("drivers")) read_drivers(reader, *item, scene, instances);
  read_decomposition(reader, get("decomposition"), scene, instances);

  if (const auto item = get("policies")) {
    const auto entries = reader.sequence(*item);
    if (entries.empty()) reader.fail(*item, "at least one policy is needed");
    scene.policies.clear();
    std::map<std::string, Item> seen;
    for (const Item& entry : entries) {
      const std::string name = reader.choice(entry, policy_names(), "policy");
      if (const auto previous = seen.find(name); previous != seen.end())
        reader.fail(entry, "duplicate policy " + quote_name(name) + " (first given at " + reader.where(previous->second) + ")");
      seen.emplace(name, entry);
      const solver::Policy policy = *solver::policy_from_name(name);
      if (policy == solver::Policy::prioritize_external) {
        if (const std::string problem = unseparable_external_force(scene.layout); !problem.empty()) {
          const auto decomposition = get("decomposition");
          reader.fail(entry, "prioritize_external (Alg. 4) keeps external forces out of the constraint reaction, so "
                             "each needs a track without the bias or torques, but " + problem +
                             (decomposition ? " (decomposition at " + reader.where(*decomposition) + ")" : ""));
        }
      }
      scene.policies.push_back(policy);
    }
  }

  if (const auto item = get("scalars")) {
    const auto entries = reader.sequence(*item);
    if (entries.empty()) reader.fail(*item, "at least one scalar type is needed");
    scene.scalars.clear();
    std::map<std::string, Item> seen;
    for (const Item& entry : entries) {
      const std::string name = reader.choice(entry, scalar_names(), "scalar type");
      if (const auto previous = seen.find(name); previous != seen.end())
        reader.fail(entry, "duplicate scalar type " + quote_name(name) + " (first given at " + reader.where(previous->second) + ")");
      seen.emplace(name, entry);
      scene.scalars.push_back(name);
    }
  }

  if (const auto item = get("expose")) scene.expose_all = reader.choice(*item, {"outputs", "all"}, "expose mode") == "all";

  if (const auto item = get("constraint_factorisation"))
    scene.constraint_factorisation = reader.choice(*item, {"pivoted_ldlt", "damped"}, "constraint factorisation") == "damped"
                                          ? solver::ConstraintFactorisation::damped
                                          : solver::ConstraintFactorisation::pivoted_ldlt;
  if (const auto item = get("pivot_tolerance")) {
    const double t = reader.number(*item);
    if (!(t > 0 && t < 1)) reader.fail(*item, "relative pivot tolerance must be > 0 and < 1");
    scene.pivot_tolerance = t;
  }
  if (const auto item = get("refinement"))
    scene.refinement = reader.choice(*item, {"true", "false"}, "refinement value") == "true";
  if (const auto item = get("check_inputs"))
    scene.check_inputs = reader.choice(*item, {"true", "false"}, "check_inputs value") == "true";
  if (const auto item = get("constraint_rows")) {
    const std::string rows = reader.choice(*item, {"auto", "inward_columns", "outward_rows"}, "constraint_rows value");
    if (rows == "outward_rows" && scene.expose_all)
      reader.fail(*item, "outward_rows does not form the columns F^A_cstr,i that 'expose: all' lists; use inward_columns or auto");
    if (rows != "auto")
      scene.constraint_rows = rows == "outward_rows" ? solver::ConstraintRows::outward_rows : solver::ConstraintRows::inward_columns;
    scene.locations["constraint_rows"] = reader.where(*item);
  }
  if (const auto item = get("outputs")) {
    const auto entries = reader.sequence(*item);
    if (entries.empty()) reader.fail(*item, "at least one output is needed (leave the key out for all of them)");
    if (scene.expose_all) reader.fail(*item, "'expose: all' returns every intermediate; 'outputs' lists what 'expose: outputs' returns");
    scene.outputs = {false, false, false, false, false, false, false, false};
    std::map<std::string, Item> seen;
    for (const Item& entry : entries) {
      const std::string name =
          reader.choice(entry, {"qdd", "tau_cmd", "tau_ctrl", "nu", "tip_acceleration", "set_acceleration", "closure_error",
                                "coupling_torque"},
                        "output");
      if (const auto previous = seen.find(name); previous != seen.end())
        reader.fail(entry, "duplicate output " + quote_name(name) + " (first given at " + reader.where(previous->second) + ")");
      if (name == "nu" && scene.layout.constraints == 0)
        reader.fail(entry, "nu has no entries: the scene has no constraint directions");
      if (name == "set_acceleration" && scene.layout.listed_sets() == 0)
        reader.fail(entry, "set_acceleration has no entries: the scene lists no constraint sets");
      if (name == "coupling_torque" && !scene.chain.couple_mimics)
        reader.fail(entry, "coupling_torque has no entries without coupled <mimic> joints (mimic: coupled)");
      if (name == "closure_error" && scene.layout.loop_sets() == 0)
        reader.fail(entry, "closure_error has no entries: the scene has no set between two links (relative_to)");
      seen.emplace(name, entry);
      *scene.outputs.flag(name) = true;
    }
    // No set between two links: no closure error to leave out (the list still returns everything).
    if (scene.layout.loop_sets() == 0) scene.outputs.closure_error = true;
    if (!scene.chain.couple_mimics) scene.outputs.coupling_torque = true;  // likewise without couplings
  }
  if (const auto item = get("derivatives")) {
    if (item->node.IsSequence()) {  // the outputs whose Jacobians are returned
      const auto entries = reader.sequence(*item);
      if (entries.empty()) reader.fail(*item, "at least one of qdd, nu, tau_cmd is needed (or derivatives: false)");
      scene.derivative_outputs = {false, false, false};
      std::map<std::string, Item> seen;
      for (const Item& entry : entries) {
        const std::string name = reader.choice(entry, {"qdd", "nu", "tau_cmd"}, "derivatives output");
        if (const auto previous = seen.find(name); previous != seen.end())
          reader.fail(entry, "duplicate output " + quote_name(name) + " (first given at " + reader.where(previous->second) + ")");
        if (name == "nu" && scene.layout.constraints == 0)
          reader.fail(entry, "nu has no entries: the scene has no constraint directions");
        seen.emplace(name, entry);
        (name == "qdd" ? scene.derivative_outputs.qdd : name == "nu" ? scene.derivative_outputs.nu
                                                                    : scene.derivative_outputs.tau_cmd) = true;
      }
      scene.derivatives = true;
    } else {
      scene.derivatives = reader.choice(*item, {"true", "false"}, "derivatives value") == "true";
    }
    if (scene.derivatives && scene.layout.torques.empty())
      reader.fail(*item, "derivatives need a torque driver (drivers: torques), the columns of d/d tau_ff");
    if (scene.derivatives && std::none_of(scene.policies.begin(), scene.policies.end(), solver::differentiable))
      reader.fail(*item, "derivatives need a differentiable policy (original or prioritize_external) in 'policies'");
  }
  return scene;
}

namespace {

// The element path of fixed direction k of set c: a single set on the tip is the mapping form
// `constraints: {directions: [...]}`, every other set an entry of the list form.
std::string direction_element(const solver::ConstraintSet& set, std::size_t c, std::size_t k) {
  return (set.link.empty() ? std::string("drivers.constraints") : "drivers.constraints[" + std::to_string(c) + "]") +
         ".directions[" + std::to_string(k) + "]";
}

// A fixed constraint direction that no joint moves in any configuration (a force along z on a
// planar arm): its row of the constraint Jacobian is zero, so is its diagonal entry of
// E^A_cstr,0 (I3), and the pivoted factorisation (C2) would drop it in every state, reporting
// constraint_rank_deficient on every solve; like a structurally over-determined group of sets,
// the scene's error. The entry is evaluated once, at an arbitrary state: an exact zero there is a
// zero of the chain's geometry (the sweeps' products with it are exactly zero), anything else
// vanishes at such a state with probability zero. Throws InputError at the direction's entry.
void check_fixed_directions_move(const Scene& scene, const model::Chain& chain) {
  if (chain.floating_base || scene.layout.constraints == 0) return;  // a free base moves along every direction
  solver::ReferenceSolver<double> reference(chain, scene.layout, scene.solver_options());
  solver::SolveInputs<double> inputs;
  const std::size_t n = chain.dof();
  inputs.q = solver::JointVector<double>::LinSpaced(static_cast<Eigen::Index>(n), 0.3, 1.7);  // no quarter turn
  inputs.qd = solver::JointVector<double>::Zero(static_cast<Eigen::Index>(n));
  inputs.torques.assign(scene.layout.torques.size(), inputs.qd);
  inputs.wrenches.resize(scene.layout.external_forces.size());
  inputs.alpha = solver::directions_with(scene.layout, [] { return spatial::Force<double>{{0, 0, 0}, {0, 0, 1}}; });
  inputs.beta = solver::ConstraintVector<double>::Zero(static_cast<Eigen::Index>(scene.layout.constraints));
  reference.prepare(inputs);
  const auto& energy = reference.articulated().body[0].constraint_energy;
  const std::vector<std::string> links = solver::direction_links(scene.layout, chain);
  Eigen::Index row = 0;
  for (std::size_t c = 0; c < scene.layout.sets.size(); ++c) {
    const solver::ConstraintSet& set = scene.layout.sets[c];
    for (std::size_t k = 0; k < set.count; ++k, ++row) {
      // A set between two links may hold redundant directions (redundant_loop_warnings).
      if (!set.directions_fixed() || set.relative() || energy(row, row) != 0) continue;
      const spatial::Force<double>& alpha = set.fixed[k];
      std::ostringstream direction;
      direction << "[" << alpha.moment[0] << ", " << alpha.moment[1] << ", " << alpha.moment[2] << ", " << alpha.force[0]
                << ", " << alpha.force[1] << ", " << alpha.force[2] << "]";
      const std::string element = direction_element(set, c, k);
      throw InputError(scene.location(element), element,
                       "no joint moves link " + quote_name(links[static_cast<std::size_t>(row)]) + " along " +
                           direction.str() + " in any configuration: the direction would be dropped in every state "
                           "(status constraint_rank_deficient on every solve); leave it out");
    }
  }
}

// `step` (reading or loading the URDF of `s`, the scene's chain) with the URDF's own
// file/element/reason prefixed by the scene entry that led there.
template <class Step>
auto at_scene_entry(const Scene& scene, const model::ChainSpec& s, const Step& step) {
  try {
    return step();
  } catch (const InputError& e) {
    const std::string message = e.what();
    const bool from_urdf = e.file() == s.urdf || e.file().rfind(s.urdf + ":", 0) == 0;
    if (!from_urdf) throw;  // already names the scene (rotor inertia)
    std::string element = "urdf";  // names are compared as the message spells them (message_text)
    if (!s.root_link.empty() && message.find(message_text("root link " + quote_name(s.root_link))) != std::string::npos)
      element = "root";
    // A tip the message names ("tip link 'x'", or "links 'root' and 'x'" not connected): at its
    // own entry of a `tips` list where the scene has one.
    std::vector<std::string> tips;
    if (!s.tip_link.empty()) tips.push_back(s.tip_link);
    tips.insert(tips.end(), s.branch_tips.begin(), s.branch_tips.end());
    for (std::size_t k = 0; k < tips.size(); ++k)
      if (message.find(message_text("tip link " + quote_name(tips[k]))) != std::string::npos ||
          message.find(message_text("and " + quote_name(tips[k]) + ":")) != std::string::npos) {
        const std::string entry = "tips[" + std::to_string(k) + "]";
        element = scene.locations.count(entry) ? entry : "tip";
      }
    throw InputError(scene.location(element), element, message);
  }
}

// The scene's URDF bytes: those already read, else the file's.
std::shared_ptr<const std::string> urdf_bytes(const Scene& scene) {
  if (scene.chain.urdf_bytes) return scene.chain.urdf_bytes;
  return at_scene_entry(scene, scene.chain, [&] { return model::read_urdf(scene.chain.urdf); });
}

}  // namespace

void read_scene_urdf(Scene& scene) { scene.chain.urdf_bytes = urdf_bytes(scene); }

model::Chain load_scene_chain(const Scene& scene) {
  model::ChainSpec spec = scene.chain;
  spec.urdf_bytes = urdf_bytes(scene);  // read once for both loads below
  const auto load = [&](const model::ChainSpec& s) { return at_scene_entry(scene, s, [&] { return model::load_chain(s); }); };

  // Check the rotor-inertia names at their own positions first (the loader knows only one
  // position for the whole map). Without the rotor inertias the chain may fail the D_N check;
  // then the loader's own name check below still applies.
  if (!spec.rotor_inertia.empty()) {
    model::ChainSpec bare = spec;
    bare.rotor_inertia.clear();
    std::optional<model::Chain> chain;
    try {
      chain = load(bare);
    } catch (const InputError&) {
    }
    if (chain) {
      std::vector<std::string> joints;
      for (std::size_t i = 1; i <= chain->dof(); ++i) joints.push_back(chain->joints[i].name);
      for (const auto& [name, value] : spec.rotor_inertia) {
        if (chain->joint_index(name) == 0)
          throw InputError(scene.location("rotor_inertia." + name), element_path("rotor_inertia", name),
                           "no moving joint " + quote_name(name) + " on " + chain->extent() + nearest_name_hint(name, joints));
      }
    }
  }
  model::Chain chain = load(spec);

  std::vector<std::string> links;
  for (const auto& [name, frame] : chain.frames) links.push_back(name);
  // A link a driver acts on (`what`: the driver, for messages, and why the base will not do): on
  // the chain and not fixed to the base, checked at the scene entry `element`.
  const auto check_link = [&](const std::string& element, const std::string& link, const std::string& what,
                              const std::string& on_the_base) {
    const auto frame = chain.frames.find(link);
    if (frame == chain.frames.end())
      throw InputError(scene.location(element), element,
                       "link " + quote_name(link) + " of " + what + " is not on " + chain.extent() + nearest_name_hint(link, links));
    if (frame->second.body == 0)
      throw InputError(scene.location(element), element,
                       "link " + quote_name(link) + " of " + what + " is fixed to the base; " + on_the_base);
  };
  for (std::size_t i = 0; i < scene.layout.external_forces.size(); ++i) {
    const auto& ext = scene.layout.external_forces[i];
    check_link("drivers.external_forces[" + std::to_string(i) + "].link", ext.link, "external force " + quote_name(ext.name),
               "a force on it moves nothing");
  }
  for (std::size_t c = 0; c < scene.layout.sets.size(); ++c) {
    const solver::ConstraintSet& set = scene.layout.sets[c];
    const std::string element = "drivers.constraints[" + std::to_string(c) + "]";
    if (!set.link.empty())  // empty: the tip
      check_link(element + ".link", set.link, "a constraint set",
                 set.relative() ? "give the moving link as 'link' and this one as 'relative_to'"
                                : "a constraint on it holds nothing");
    // The second link of a set between two links may ride on the base (a loop closed to the ground).
    if (const std::string problem = solver::relative_to_problem(set, chain); !problem.empty())
      throw InputError(scene.location(element + ".relative_to"), element + ".relative_to", problem);
  }
  if (const std::string problem = solver::structurally_overdetermined(scene.layout.constraint_sets(), chain); !problem.empty())
    throw InputError(scene.location("drivers.constraints"), "drivers.constraints", problem);
  solver::validate(scene.layout, chain, scene.path.empty() ? "command line" : scene.path);
  check_fixed_directions_move(scene, chain);
  // The rows (I6) take steps with the square of a chain's length (solver/constraint_row_steps.hpp).
  if (scene.constraint_rows == solver::ConstraintRows::outward_rows) {
    const solver::ConstraintRowSteps steps = solver::constraint_row_steps(chain, scene.layout);
    if (steps.outward_rows > kMaxOutwardRowSteps)
      throw InputError(scene.location("constraint_rows"), "constraint_rows",
                       "outward_rows (I6) takes " + std::to_string(steps.outward_rows) +
                           " outward steps on this chain, more than the limit of " + std::to_string(kMaxOutwardRowSteps) +
                           " (README, \"Limits\"); inward_columns or auto take " + std::to_string(steps.inward_columns));
  }
  return chain;
}

Scene default_scene(const std::string& urdf, const std::string& root, const std::string& tip,
                    const std::vector<std::string>& branch_tips, bool snap_quarter_turns, const std::string& command) {
  Scene scene;
  std::string name = std::filesystem::path(urdf).stem().string();
  for (char& c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_')) c = '_';
  while (name.find("__") != std::string::npos) name.replace(name.find("__"), 2, "_");
  name.resize(std::min(name.size(), kMaxSolverNamespaceBytes));
  if (!solver_namespace_problem(name).empty()) name = "robot_" + name;  // "7dof_arm", "std", "linux"
  while (name.find("__") != std::string::npos) name.replace(name.find("__"), 2, "_");
  name.resize(std::min(name.size(), kMaxSolverNamespaceBytes));
  if (!solver_namespace_problem(name).empty()) name = "robot";
  scene.solver = name;

  scene.chain.urdf = urdf;
  scene.chain.root_link = root;
  scene.chain.tip_link = tip;
  scene.chain.branch_tips = branch_tips;
  scene.chain.snap_quarter_turns = snap_quarter_turns;
  scene.chain.naming_the_tip = command + " --urdf " + urdf + " --tip LINK (for a tree, --branch-tip LINK for each further tip)";
  scene.locations["urdf"] = "--urdf";
  if (!root.empty()) scene.locations["root"] = "--root";
  if (!tip.empty()) scene.locations["tip"] = "--tip";
  if (!branch_tips.empty()) scene.locations["tip"] = "--branch-tip";
  scene.layout.decompose_all();  // the bias alone, until the tip is known
  read_scene_urdf(scene);  // kept: the command's later load_scene_chain parses the same bytes
  const model::Chain chain = load_scene_chain(scene);  // resolves root and tip
  scene.chain.root_link = chain.root_link;
  scene.chain.tip_link = chain.tip_link;

  scene.layout.torques = {"tau_ff"};
  scene.layout.external_forces = {solver::ExternalForceDriver{"f_ext_tip", chain.tip_link}};
  // Six run-time directions on the tip, or as many as the joints that move it can meet.
  const std::size_t tip_directions = std::min(solver::kMaxSetDirections, chain.tip().body);
  scene.layout.constraints = tip_directions;
  if (tip_directions > 0) scene.layout.sets = {solver::ConstraintSet::on("", tip_directions)};
  scene.layout.decompose_all();
  scene.policies = {solver::Policy::original, solver::Policy::prioritize_external, solver::Policy::saturate,
                    solver::Policy::saturate_exact};
  return scene;
}

}  // namespace sweepgen::scene

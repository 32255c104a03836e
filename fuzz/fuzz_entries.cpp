#include "fuzz_entries.hpp"

#include <stdlib.h>  // mkdtemp

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli/json_problem.hpp"
#include "model/error.hpp"
#include "model/urdf_loader.hpp"
#include "scene/cpp_names.hpp"
#include "scene/scene.hpp"

namespace sweepgen::fuzz {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void violation(const std::string& what) { throw ContractViolation(what); }

// Where inputs are written: the readers take file paths. One directory per process, holding
// copies of the bundled URDFs (built in, so no source path is needed at run time) so that fuzzed
// scenes can name them as the bundled scenes do.
class Sandbox {
 public:
  Sandbox() {
    std::string pattern = (fs::temp_directory_path() / "sweepgen-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("fuzz harness: cannot create " + pattern);
    dir_ = pattern;
    // A name in two robots/ folders: the first one in path order.
    for (const auto& [path, text] : bundled_urdfs())
      if (!fs::exists(dir_ / fs::path(path).filename())) write(fs::path(path).filename().string(), text);
  }
  ~Sandbox() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  Sandbox(const Sandbox&) = delete;
  Sandbox& operator=(const Sandbox&) = delete;

  const fs::path& dir() const { return dir_; }

  // Writes `bytes` to `name` in the sandbox and returns its path.
  std::string write(const std::string& name, const std::string& bytes) const {
    const fs::path path = dir_ / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("fuzz harness: cannot write " + path.string());
    return path.string();
  }

 private:
  fs::path dir_;
};

const Sandbox& sandbox() {
  static const Sandbox instance;
  return instance;
}

// ---- Error messages -------------------------------------------------------------------------

// The index just past the quoted name (model/error.hpp: quote_name) that opens at `open`, or npos when
// it is not closed: inside, a backslash escapes the next byte.
std::size_t past_quoted(const std::string& text, std::size_t open) {
  for (std::size_t at = open + 1; at < text.size(); ++at) {
    if (text[at] == '\\') ++at;
    else if (text[at] == '\'') return at + 1;
  }
  return std::string::npos;
}

// Where ": " first occurs in `text` from `from` on outside quoted names, or npos.
std::size_t unquoted_separator(const std::string& text, std::size_t from) {
  for (std::size_t at = from; at < text.size(); ++at) {
    if (text[at] == '\'') {
      at = past_quoted(text, at);
      if (at == std::string::npos) return std::string::npos;
      --at;
    } else if (text.compare(at, 2, ": ") == 0) {
      return at;
    }
  }
  return std::string::npos;
}

// InputError's "FILE: ELEMENT: REASON", where FILE is `file` itself or, for scene positions,
// "file:LINE:COLUMN". ELEMENT and REASON must not be empty, and ELEMENT ends at the first ": "
// outside quoted names: a name from the input must be quoted wherever it could hold ": ".
void check_input_error(const std::string& message, const std::string& file) {
  if (message.rfind(file, 0) != 0) violation("error message does not start with the file '" + file + "': " + message);
  std::size_t at = file.size();
  for (int field = 0; field < 2 && at < message.size() && message[at] == ':' &&
                      at + 1 < message.size() && std::isdigit(static_cast<unsigned char>(message[at + 1]));
       ++field) {
    ++at;
    while (at < message.size() && std::isdigit(static_cast<unsigned char>(message[at]))) ++at;
  }
  if (message.compare(at, 2, ": ") != 0) violation("no ': ' after the file (and position): " + message);
  const std::size_t element = at + 2;
  const std::size_t separator = unquoted_separator(message, element);
  if (separator == element || separator == std::string::npos || separator + 2 == message.size())
    violation("error message names no element or gives no reason: " + message);
  // An element is names and words: a ':' in it outside quotes would blur where it ends.
  for (std::size_t i = element; i < separator; ++i) {
    if (message[i] == '\'') i = past_quoted(message, i) - 1;
    else if (message[i] == ':') violation("unquoted ':' in the element of: " + message);
  }
}

// KeyError's "key 'KEY': REASON" with a quoted KEY and a non-empty reason; a long KEY is cut,
// "'KEY'... (N bytes)" (quote_name).
void check_key_error(const std::string& message) {
  std::size_t closed = message.rfind("key '", 0) == 0 ? past_quoted(message, 4) : std::string::npos;
  if (closed != std::string::npos && message.compare(closed, 5, "... (") == 0) {
    const std::size_t size_end = message.find(" bytes)", closed);
    closed = size_end == std::string::npos ? std::string::npos : size_end + 7;
  }
  if (closed == std::string::npos || message.compare(closed, 2, ": ") != 0 || closed + 2 == message.size())
    violation("error message does not name the key and a reason: " + message);
}

// ---- Accepted results -----------------------------------------------------------------------

template <class Matrix>
void check_finite(const Matrix& m, const std::string& what) {
  if (!m.allFinite()) violation(what + " is not finite");
}

// A loaded chain is what the sweeps can run on: consistent sizes, unit axes, finite numbers,
// and the root/tip that were asked for.
void check_chain(const model::Chain& chain, const model::ChainSpec& spec) {
  if (chain.bodies.size() < 2 || chain.joints.size() != chain.bodies.size())
    violation("chain has " + std::to_string(chain.bodies.size()) + " bodies and " + std::to_string(chain.joints.size()) +
              " joints");
  if (!spec.root_link.empty() && chain.root_link != spec.root_link) violation("root link is not the one asked for");
  if (!spec.tip_link.empty() && chain.tip_link != spec.tip_link) violation("tip link is not the one asked for");
  for (const std::string& link : {chain.root_link, chain.tip_link})
    if (!chain.frames.count(link)) violation("link '" + link + "' has no frame");
  if (chain.floating_base != spec.floating_base) violation("floating base not as asked for");
  if (chain.frames.at(chain.root_link).body != chain.base_coordinates()) violation("root link is not on the base (body 6 of a floating base)");
  for (std::size_t i = 1; i < chain.joints.size(); ++i)
    if (chain.joints[i].floating_base_coordinate != (i <= chain.base_coordinates()))
      violation("joint " + std::to_string(i) + " is a floating-base coordinate out of place");
  for (const auto& [link, frame] : chain.frames) {
    if (frame.body >= chain.bodies.size()) violation("frame of '" + link + "' on a body that does not exist");
    check_finite(frame.X.E, "frame of '" + link + "'");
    check_finite(frame.X.r, "frame of '" + link + "'");
  }
  if (chain.parent.size() != chain.bodies.size() || chain.joints.size() != chain.bodies.size())
    violation("parents, joints and bodies differ in number");
  for (std::size_t i = 1; i < chain.joints.size(); ++i) {
    const model::Joint& joint = chain.joints[i];
    const std::string what = "joint " + std::to_string(i) + " ('" + joint.name + "')";
    if (chain.parent[i] >= i) violation(what + " hangs from a body that is not before it");
    check_finite(joint.axis, what + " axis");
    if (std::abs(joint.axis.norm() - 1) > 1e-9) violation(what + " axis is not a unit vector");
    check_finite(joint.tree_transform.E, what + " tree transform");
    check_finite(joint.tree_transform.r, what + " tree transform");
    if (!(std::isfinite(joint.rotor_inertia) && joint.rotor_inertia >= 0)) violation(what + " rotor inertia");
    if (!(joint.effort_limit > 0 && joint.velocity_limit > 0)) violation(what + " limits are not positive");
    const model::Body& body = chain.bodies[i];
    if (!(std::isfinite(body.mass) && body.mass >= 0)) violation("mass of body " + std::to_string(i));
    check_finite(body.inertia.A, "inertia of body " + std::to_string(i));
    check_finite(body.inertia.B, "inertia of body " + std::to_string(i));
    check_finite(body.inertia.C, "inertia of body " + std::to_string(i));
    for (const auto& lumped : body.lumped_links) {
      const auto frame = chain.frames.find(lumped.link);
      if (frame == chain.frames.end() || frame->second.body != i)
        violation("lumped link '" + lumped.link + "' has no frame on body " + std::to_string(i));
      if (!(std::isfinite(lumped.mass) && lumped.mass >= 0)) violation("mass of lumped link '" + lumped.link + "'");
    }
  }
  const auto is_mimic = [&chain](const std::string& joint) {
    return std::any_of(chain.mimics.begin(), chain.mimics.end(), [&joint](const auto& m) { return m.joint == joint; });
  };
  const auto is_locked = [&chain](const std::string& joint) {
    return std::any_of(chain.locked_joints.begin(), chain.locked_joints.end(), [&joint](const auto& l) { return l.name == joint; });
  };
  // Off the chain only what a moving body carries is locked; a <mimic> on a tip path may be locked
  // on the fixed base too (locked_joints), the links beyond then fixed to it.
  for (const auto& locked : chain.locked_joints)
    if ((locked.body == 0 && !is_mimic(locked.name)) || locked.body >= chain.bodies.size() || !std::isfinite(locked.position))
      violation("locked joint '" + locked.name + "'");
  for (const auto& mimic : chain.mimics) {
    if ((chain.joint_index(mimic.joint) != 0) == is_locked(mimic.joint))
      violation("mimic joint '" + mimic.joint + "' is not exactly one of moving and locked");
    if (!std::isfinite(mimic.multiplier) || !std::isfinite(mimic.offset)) violation("mimic joint '" + mimic.joint + "' numbers");
  }
  for (const auto& change : chain.changes)
    if (!(std::isfinite(change.deviation) && change.deviation >= 0)) violation("change of " + change.element);
  for (const auto& link : chain.left_out)
    if (chain.frames.count(link.link) != 0) violation("link '" + link.link + "' both on the chain and left out");
}

// A parsed scene holds what scene.hpp promises before the chain is known.
void check_scene(const scene::Scene& s) {
  if (s.solver.empty() || s.chain.urdf.empty()) violation("scene without solver namespace or URDF");
  check_finite(s.gravity, "gravity");
  const solver::DriverLayout& layout = s.layout;
  if (layout.constraints > solver::kMaxConstraints) violation("more constraints than kMaxConstraints");
  std::size_t directions = 0;
  for (const auto& set : layout.sets) {
    directions += set.count;
    if (set.count == 0 || set.count > solver::kMaxSetDirections) violation("a constraint set of 0 or more than 6");
    if (set.directions_fixed() && set.fixed.size() != set.count) violation("fixed directions and set count differ");
    if (set.link.empty() && layout.sets.size() > 1) violation("the tip set of a short form among listed sets");
    for (const auto& d : set.fixed) {
      const double norm = std::sqrt(d.moment.squaredNorm() + d.force.squaredNorm());
      if (!(std::abs(norm - 1) <= 1e-9)) violation("fixed direction is not a unit vector");
    }
  }
  if (directions != layout.constraints) violation("the sets' directions and the constraint count differ");
  if (s.policies.empty() || s.scalars.empty()) violation("no policy or no scalar type");
  if (!(s.pivot_tolerance == 0 || (s.pivot_tolerance > 0 && s.pivot_tolerance < 1))) violation("pivot tolerance");
  for (const auto& [joint, d] : s.chain.rotor_inertia)
    if (!(std::isfinite(d) && d >= 0)) violation("rotor inertia of '" + joint + "'");
  for (const auto& name : layout.torques)
    if (!scene::driver_name_problem(name).empty()) violation("torque instance '" + name + "' is not a usable name");
  for (const auto& force : layout.external_forces)
    if (!scene::driver_name_problem(force.name).empty() || force.link.empty()) violation("external force '" + force.name + "'");
  // Every instance, and the bias, on exactly one track.
  std::size_t bias = 0;
  std::vector<int> torque_tracks(layout.torques.size()), force_tracks(layout.external_forces.size());
  for (const auto& track : layout.tracks) {
    bias += track.bias;
    for (std::size_t i : track.torques) {
      if (i >= torque_tracks.size()) violation("track '" + track.name + "' names a torque that does not exist");
      ++torque_tracks[i];
    }
    for (std::size_t i : track.external_forces) {
      if (i >= force_tracks.size()) violation("track '" + track.name + "' names a force that does not exist");
      ++force_tracks[i];
    }
  }
  if (bias != 1) violation("the bias is on " + std::to_string(bias) + " tracks");
  for (const auto* counts : {&torque_tracks, &force_tracks})
    for (int count : *counts)
      if (count != 1) violation("a driver instance is on " + std::to_string(count) + " tracks");
}

void check_problem(const cli::Problem& p, const model::Chain& chain) {
  const auto n = static_cast<Eigen::Index>(chain.dof());
  if (p.q.size() != n || p.qd.size() != n || p.tau_ff.size() != n) violation("q, qd or tau_ff has the wrong size");
  check_finite(p.q, "q");
  check_finite(p.qd, "qd");
  check_finite(p.tau_ff, "tau_ff");
  if (p.alpha.size() > solver::kMaxConstraints || static_cast<Eigen::Index>(p.alpha.size()) != p.beta.size())
    violation("alpha and beta sizes");
  check_finite(p.beta, "beta");
  for (const auto& a : p.alpha) {
    check_finite(a.moment, "alpha");
    check_finite(a.force, "alpha");
  }
  for (const auto& [link, wrench] : p.f_ext) {
    const auto frame = chain.frames.find(link);
    if (frame == chain.frames.end() || frame->second.body == 0) violation("f_ext on link '" + link + "'");
    check_finite(wrench.moment, "f_ext");
    check_finite(wrench.force, "f_ext");
  }
}

// ---- Inputs ---------------------------------------------------------------------------------

// Root, tip and further tips from an optional "<!-- chain root=LINK tip=LINK branch=LINK ... -->"
// anywhere in the URDF (branch= repeatable: the tree of all root-to-tip paths; the word
// `floating` lets the root link float, F5). A name
// ends at white space or NUL: names come from the command line (--root, --tip), and argv
// strings cannot hold NUL.
void read_chain_directive(const std::string& input, model::ChainSpec& spec) {
  const std::string opening = "<!-- chain ";
  const std::size_t begin = input.find(opening);
  if (begin == std::string::npos) return;
  const std::size_t end = input.find("-->", begin);
  if (end == std::string::npos) return;
  std::istringstream words(input.substr(begin + opening.size(), end - begin - opening.size()));
  for (std::string word; words >> word;) {
    word = word.substr(0, word.find('\0'));
    if (word.rfind("root=", 0) == 0) spec.root_link = word.substr(5);
    if (word.rfind("tip=", 0) == 0) spec.tip_link = word.substr(4);
    if (word.rfind("branch=", 0) == 0) spec.branch_tips.push_back(word.substr(7));
    if (word == "floating") spec.floating_base = true;
  }
}

// Only URDFs in the sandbox are loaded for a fuzzed scene: a scene may name any path, and
// reading arbitrary host files (/dev/zero, say) tests the machine, not the reader.
bool in_sandbox(const std::string& path) {
  const fs::path p(path);
  std::error_code error;  // e.g. a name too long for the file system: not in the sandbox either
  return p.parent_path() == sandbox().dir() && fs::is_regular_file(p, error);
}

const model::Chain& panda() {
  static const model::Chain chain = [] {
    model::ChainSpec spec;
    spec.urdf = (sandbox().dir() / "panda.urdf").string();
    try {
      return model::load_chain(spec);
    } catch (const InputError& e) {
      throw std::runtime_error(std::string("fuzz harness: cannot load the bundled Panda: ") + e.what());
    }
  }();
  return chain;
}

}  // namespace

Outcome urdf_input(const std::string& input) {
  model::ChainSpec spec;
  read_chain_directive(input, spec);
  spec.urdf = sandbox().write("input.urdf", input);
  try {
    check_chain(model::load_chain(spec), spec);
    return {true, ""};
  } catch (const InputError& e) {
    check_input_error(e.what(), spec.urdf);
    return {false, e.what()};
  }
}

Outcome scene_input(const std::string& input) {
  const std::string path = sandbox().write("input.yaml", input);
  try {
    const scene::Scene s = scene::load_scene(path);
    check_scene(s);
    if (in_sandbox(s.chain.urdf)) {
      const model::Chain chain = scene::load_scene_chain(s);
      check_chain(chain, s.chain);
      for (const auto& force : s.layout.external_forces) {
        const auto frame = chain.frames.find(force.link);
        if (frame == chain.frames.end() || frame->second.body == 0)
          violation("external force '" + force.name + "' on link '" + force.link + "' accepted");
      }
    }
    return {true, ""};
  } catch (const InputError& e) {
    check_input_error(e.what(), path);
    return {false, e.what()};
  }
}

// `sweepgen solve`'s answer to a line it cannot read is one JSON line whatever the input's bytes.
void check_error_line(const std::string& message) {
  const std::string text = cli::error_line(1, message);
  try {
    if (nlohmann::json::parse(text).at("error") != message) violation("error line does not carry the message: " + text);
  } catch (const nlohmann::json::exception&) {
    violation("error line is not JSON: " + text);
  }
}

Outcome solve_line_input(const std::string& input) {
  const model::Chain& chain = panda();
  nlohmann::json line;
  try {
    line = nlohmann::json::parse(input);
  } catch (const nlohmann::json::exception& e) {
    if (std::string(e.what()).empty()) violation("JSON error without a message");
    check_error_line(cli::json_error_reason(e));
    return {false, e.what()};
  }
  try {
    cli::refuse_hidden_json(input);  // as `sweepgen solve` reads each line
    check_problem(cli::parse_problem(line, chain), chain);
    return {true, ""};
  } catch (const cli::KeyError& e) {
    check_key_error(e.what());
    check_error_line(e.what());
    return {false, e.what()};
  }
}

}  // namespace sweepgen::fuzz

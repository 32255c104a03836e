#include "cli/json_problem.hpp"

#include <cmath>
#include <set>

#include "model/error.hpp"
#include "solver/flat_layout.hpp"

namespace sweepgen::cli {
namespace {

using nlohmann::json;

const std::vector<std::string> kKeys = {"q", "qd", "tau_ff", "f_ext", "alpha", "beta", "constraints", "policy"};

spatial::Force<double> wrench(const json& value, const std::string& key) {
  const Eigen::VectorXd v = numbers(value, key, 6);
  return {v.head<3>(), v.tail<3>()};
}

// {"xyz": [3], "rpy": [3]} (either may be left out), a URDF origin, as the motion transform link -> frame.
model::Transform origin(const json& value, const std::string& key) {
  if (!value.is_object()) throw KeyError(key, "expected {\"xyz\": [x, y, z], \"rpy\": [roll, pitch, yaw]}");
  model::Vec3 xyz = model::Vec3::Zero(), rpy = model::Vec3::Zero();
  for (const auto& [name, part] : value.items()) {
    if (name != "xyz" && name != "rpy") throw KeyError(key + "." + name, "unknown key (xyz or rpy)");
    (name == "xyz" ? xyz : rpy) = numbers(part, key + "." + name, 3);
  }
  return model::origin_transform(xyz, rpy);
}

nlohmann::ordered_json array(const Eigen::VectorXd& v) { return nlohmann::ordered_json(std::vector<double>(v.data(), v.data() + v.size())); }

}  // namespace

Eigen::VectorXd numbers(const json& value, const std::string& key, std::size_t expected) {
  if (!value.is_array()) throw KeyError(key, "expected an array of " + std::to_string(expected) + " numbers");
  if (value.size() != expected)
    throw KeyError(key, "expected " + std::to_string(expected) + " numbers, got " + std::to_string(value.size()));
  Eigen::VectorXd v(expected);
  for (std::size_t i = 0; i < expected; ++i) {
    if (!value[i].is_number()) throw KeyError(key, "entry " + std::to_string(i) + " is not a number");
    v[i] = value[i].get<double>();
    if (!std::isfinite(v[i])) throw KeyError(key, "entry " + std::to_string(i) + " is not finite");
  }
  return v;
}

spatial::Mat3<double> base_rotation(const Eigen::VectorXd& q, const std::string& key) {
  spatial::Mat3<double> rotation;
  for (Eigen::Index r = 0; r < 9; ++r) rotation(r / 3, r % 3) = q[r];
  const double orthonormality = (rotation.transpose() * rotation - spatial::Mat3<double>::Identity()).cwiseAbs().maxCoeff();
  if (!(orthonormality <= 1e-9 && rotation.determinant() > 0))
    throw KeyError(key, "the first 9 numbers (world_R_base, row-major) are not a rotation matrix (|R^T R - 1| = " +
                            std::to_string(orthonormality) + ", det " + std::to_string(rotation.determinant()) + ")");
  return rotation;
}

namespace {

// The events of a line's JSON, for what its parsed value hides: a key given twice in one object
// (the value keeps the last) and a number that underflows to 0 (1e-400). Each value is named as
// the keys of KeyError name it: "q[2]", "constraints[0].link".
class HiddenInJson : public nlohmann::json_sax<json> {
 public:
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t number, const string_t& text) override {
    const std::string name = element();
    // A mantissa with a digit other than 0 that reads as 0: below the smallest subnormal.
    if (number == 0 && text.find_first_of("123456789") < text.find_first_of("eE"))
      throw KeyError(name, text + " is too small for a double (below about 4.9e-324): it would read as 0");
    return true;
  }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& name) override {
    Scope& scope = scopes_.back();
    scope.key = name;
    if (!scope.keys.insert(name).second) throw KeyError(element_of(scope), "given twice in one object (the last would count)");
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const json::exception&) override { return false; }

 private:
  struct Scope {
    std::string name;
    bool array = false;
    std::size_t entries = 0;    // an array's values so far
    std::set<std::string> keys;  // an object's keys so far
    std::string key;            // the key of the object's value that comes next
  };
  static std::string element_of(const Scope& scope) {
    if (scope.array) return scope.name + "[" + std::to_string(scope.entries) + "]";
    return scope.name.empty() ? scope.key : scope.name + "." + scope.key;
  }
  // The name of the value that starts now.
  std::string element() {
    if (scopes_.empty()) return "";
    const std::string name = element_of(scopes_.back());
    if (scopes_.back().array) ++scopes_.back().entries;
    return name;
  }
  bool value() {
    element();
    return true;
  }
  bool open(bool array) {
    scopes_.push_back({element(), array, 0, {}, {}});
    return true;
  }
  bool close() {
    scopes_.pop_back();
    return true;
  }

  std::vector<Scope> scopes_;
};

}  // namespace

Problem parse_problem(const json& line, const model::Chain& chain) {
  if (!line.is_object()) throw KeyError("(line)", "expected a JSON object");
  for (const auto& [key, value] : line.items())
    if (std::find(kKeys.begin(), kKeys.end(), key) == kKeys.end())
      throw KeyError(key, "unknown key" + nearest_name_hint(key, kKeys));
  const std::size_t n = chain.dof();
  Problem p;
  for (const char* key : {"q", "qd"})
    if (!line.contains(key)) throw KeyError(key, "missing");
  // q and qd as the generated code takes them: a floating base's world_R_base (9, row-major) first
  // (F5), no entry for a coupled <mimic> joint (M1), whose values its source gives.
  const std::size_t base = chain.base_coordinates(), rotation = base > 0 ? 9 : 0, coupled = chain.couplings.size();
  const Eigen::VectorXd q = numbers(line["q"], "q", n - base + rotation - coupled);
  const Eigen::VectorXd qd = numbers(line["qd"], "qd", n - coupled);
  solver::joint_values_from_generated(q.data() + rotation, qd.data(), n, chain.floating_base, chain.couplings, p.q, p.qd);
  if (rotation > 0) p.base_rotation = base_rotation(q, "q");
  p.tau_ff = line.contains("tau_ff") ? numbers(line["tau_ff"], "tau_ff", n) : Eigen::VectorXd::Zero(n);
  std::vector<std::string> links;
  for (const auto& [name, frame] : chain.frames) links.push_back(name);
  // A link a driver acts on: on the chain, and not fixed to the base (`on_the_base` says why).
  const auto check_link = [&](const std::string& key, const std::string& link, const std::string& on_the_base) {
    const auto frame = chain.frames.find(link);
    if (frame == chain.frames.end()) throw KeyError(key, "link is not on " + chain.extent() + nearest_name_hint(link, links));
    if (frame->second.body == 0) throw KeyError(key, "link is fixed to the base; " + on_the_base);
  };
  if (line.contains("f_ext")) {
    if (!line["f_ext"].is_object()) throw KeyError("f_ext", "expected an object {link: [mx,my,mz,fx,fy,fz]}");
    for (const auto& [link, value] : line["f_ext"].items()) {
      const std::string key = "f_ext." + link;
      check_link(key, link, "a force on it moves nothing");
      p.f_ext[link] = wrench(value, key);
    }
  }
  const bool has_alpha = line.contains("alpha"), has_beta = line.contains("beta");
  if (has_alpha != has_beta) throw KeyError(has_alpha ? "beta" : "alpha", "missing (alpha and beta go together)");
  if (has_alpha) {
    const json& alpha = line["alpha"];
    if (!alpha.is_array() || alpha.size() > solver::kMaxSetDirections)
      throw KeyError("alpha", "expected an array of 0 to 6 directions, each [mx,my,mz,fx,fy,fz]");
    for (std::size_t k = 0; k < alpha.size(); ++k) p.alpha.push_back(wrench(alpha[k], "alpha[" + std::to_string(k) + "]"));
    p.beta = numbers(line["beta"], "beta", alpha.size());
  }
  if (line.contains("constraints")) {
    if (has_alpha) throw KeyError("constraints", "give either alpha and beta (on the tip) or constraints, not both");
    const json& sets = line["constraints"];
    if (!sets.is_array() || sets.empty())
      throw KeyError("constraints", "expected an array of sets {\"link\": L, \"alpha\": [...], \"beta\": [...]}");
    if (sets.size() > solver::kMaxConstraints)
      throw KeyError("constraints", "at most " + std::to_string(solver::kMaxConstraints) + " directions in all, got " +
                                        std::to_string(sets.size()) + " sets");
    std::vector<double> beta;
    for (std::size_t c = 0; c < sets.size(); ++c) {
      const std::string key = "constraints[" + std::to_string(c) + "]";
      const json& set = sets[c];
      static const std::vector<std::string> set_keys = {"link", "alpha", "beta", "at", "relative_to", "relative_at"};
      if (!set.is_object() || !set.contains("link") || !set["link"].is_string() || !set.contains("alpha") || !set.contains("beta"))
        throw KeyError(key, "expected {\"link\": L, \"alpha\": [...], \"beta\": [...]} (optional: at, relative_to, relative_at)");
      for (const auto& [name, value] : set.items())
        if (std::find(set_keys.begin(), set_keys.end(), name) == set_keys.end())
          throw KeyError(key + "." + name, "unknown key" + nearest_name_hint(name, set_keys));
      solver::ConstraintSet placed;
      placed.link = set["link"].get<std::string>();
      const std::string& link = placed.link;
      if (set.contains("relative_to")) {
        if (!set["relative_to"].is_string()) throw KeyError(key + ".relative_to", "expected a link name");
        placed.relative_to = set["relative_to"].get<std::string>();
      }
      check_link(key + ".link", link,
                 placed.relative() ? "give the moving link as link and this one as relative_to" : "a constraint on it holds nothing");
      if (const std::string problem = solver::relative_to_problem(placed, chain); !problem.empty())
        throw KeyError(key + ".relative_to", problem);
      if (set.contains("at")) placed.at = origin(set["at"], key + ".at");
      if (set.contains("relative_at")) {
        if (!placed.relative())
          throw KeyError(key + ".relative_at", "places frame B on the link relative_to names; give relative_to");
        placed.relative_at = origin(set["relative_at"], key + ".relative_at");
      }
      for (const auto& earlier : p.sets)
        if (earlier.link == link && earlier.relative_to == placed.relative_to)
          throw KeyError(key + ".link", "a second set on " + quote_name(link) +
                                            (placed.relative() ? " relative to " + quote_name(placed.relative_to) : ""));
      const json& alpha = set["alpha"];
      if (!alpha.is_array() || alpha.empty() || alpha.size() > solver::kMaxSetDirections)
        throw KeyError(key + ".alpha", "expected an array of 1 to 6 directions, each [mx,my,mz,fx,fy,fz]");
      if (p.alpha.size() + alpha.size() > solver::kMaxConstraints)
        throw KeyError("constraints", "at most " + std::to_string(solver::kMaxConstraints) + " directions in all");
      for (std::size_t k = 0; k < alpha.size(); ++k)
        p.alpha.push_back(wrench(alpha[k], key + ".alpha[" + std::to_string(k) + "]"));
      const Eigen::VectorXd b = numbers(set["beta"], key + ".beta", alpha.size());
      beta.insert(beta.end(), b.data(), b.data() + b.size());
      placed.count = alpha.size();
      p.sets.push_back(placed);
    }
    if (const std::string problem = solver::structurally_overdetermined(p.sets, chain); !problem.empty())
      throw KeyError("constraints", problem);
    if (p.alpha.size() > solver::kMaxConstraints)
      throw KeyError("constraints", "at most " + std::to_string(solver::kMaxConstraints) + " directions in all");
    p.beta = Eigen::Map<const Eigen::VectorXd>(beta.data(), static_cast<Eigen::Index>(beta.size()));
  }
  if (line.contains("policy")) {
    const json& policy = line["policy"];
    const auto parsed = policy.is_string() ? solver::policy_from_name(policy.get<std::string>()) : std::nullopt;
    if (!parsed)
      throw KeyError("policy", "expected one of original, prioritize_external, saturate, saturate_exact");
    p.policy = *parsed;
  }
  return p;
}

void refuse_hidden_json(const std::string& text) {
  HiddenInJson events;
  json::sax_parse(text, &events);
}

std::string json_text(const nlohmann::ordered_json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string json_error_reason(const nlohmann::json::exception& error) {
  return "not valid JSON: " + escaped_text(error.what(), '\0', 4 * kShownBytes);
}

std::string error_line(std::size_t line, const std::string& message) {
  return json_text(nlohmann::ordered_json{{"line", line}, {"error", message}});
}

nlohmann::ordered_json solution_to_json(const solver::Solution<double>& s, unsigned status, const model::Chain& chain,
                                        const std::vector<solver::ConstraintSet>& sets) {
  nlohmann::ordered_json out;
  out["qdd"] = array(s.qdd);
  out["tau_ctrl"] = array(s.tau_ctrl);
  out["tau_cmd"] = array(s.tau_cmd);
  const auto set_directions = static_cast<Eigen::Index>(s.nu.size() - static_cast<Eigen::Index>(s.couplings));
  out["nu"] = array(Eigen::VectorXd(s.nu.head(set_directions)));
  if (s.couplings > 0) {  // each coupled <mimic> joint's transmission torque (M2), by joint
    nlohmann::ordered_json couplings;
    for (std::size_t c = 0; c < chain.couplings.size(); ++c)
      couplings[chain.joints[chain.couplings[c].joint].name] = s.nu[set_directions + static_cast<Eigen::Index>(c)];
    out["coupling_torque"] = couplings;
  }
  Eigen::VectorXd tip(6);
  tip << s.tip_acceleration.angular, s.tip_acceleration.linear;
  out["xdd_tip"] = array(tip);
  // A set by its link, a set between two links as "LINK relative_to OTHER".
  const auto set_name = [](const solver::ConstraintSet& set) {
    return set.relative() ? set.link + " relative_to " + set.relative_to : set.link;
  };
  const auto six = [](const spatial::Motion<double>& m) {
    Eigen::VectorXd a(6);
    a << m.angular, m.linear;
    return array(a);
  };
  if (!sets.empty()) {  // each listed set's acceleration, [angular; linear] in its frame (L1 for a loop)
    nlohmann::ordered_json links;
    for (std::size_t c = 0; c < sets.size(); ++c) links[set_name(sets[c])] = six(s.set_acceleration[c]);
    out["xdd_links"] = links;
  }
  if (!s.closure_error.empty()) {  // each set between two links: pose error (L3), v_rel (L1)
    nlohmann::ordered_json loops;
    std::size_t c = 0;
    for (const solver::ConstraintSet& set : sets) {
      if (!set.relative()) continue;
      loops[set_name(set)] = {{"pose_error", six(s.closure_error[c][0])}, {"relative_velocity", six(s.closure_error[c][1])}};
      ++c;
    }
    out["closure_error"] = loops;
  }
  std::vector<std::string> flags;
  if (status & solver::status_constraint_rank_deficient) flags.push_back("constraint_rank_deficient");
  if (status & solver::status_saturated) flags.push_back("saturated");
  if (status & solver::status_not_finite) flags.push_back("not_finite");
  if (status & solver::status_joint_inertia_singular) flags.push_back("joint_inertia_singular");
  std::string text = flags.empty() ? "ok" : flags[0];
  for (std::size_t k = 1; k < flags.size(); ++k) text += "," + flags[k];
  out["status"] = text;
  std::vector<std::string> saturated;
  for (std::size_t i = 1; i <= chain.dof(); ++i)
    if (s.saturated[i - 1] > 0) saturated.push_back(chain.joints[i].name);
  out["saturated_joints"] = saturated;
  return out;
}

}  // namespace sweepgen::cli

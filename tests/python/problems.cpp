// python_test_problems SCENE COUNT SEED [axes]: random problems of a scene for
// tests/python/test_module.py, as JSON lines. The first line describes the scene; each further
// line is one problem:
//   {"in": the generated code's flat input (solver/flat_layout.hpp),
//    "kappa": κ = max(1, cond_s(E^A_cstr,0), 1 / min_i ρ_i) of the state (docs/stability.md), from
//             the binary128 referee with the scene's options (report::precise_reference),
//    "cli": the same problem as a `sweepgen solve` input line (without "policy")}
// The problems are report::random_problems' (the distribution `sweepgen report` and the
// generated-scene tests draw from); with `axes`, constraint direction k is the k-th unit axis
// [moment x, y, z; force x, y, z] instead of a random one: six random directions on a 7-joint arm
// are nearly always beyond float's domain (kappa > 1e3), the axes mostly within it. Exits 1 with
// a message for a scene `sweepgen solve` cannot express (it knows one torque, one wrench per
// link, default gravity and factorisation).
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "report/measure.hpp"
#include "report/stability_errors.hpp"
#include "scene/scene.hpp"

namespace {

using sweepgen::report::Problem;
using sweepgen::scene::Scene;
using nlohmann::ordered_json;

std::vector<double> values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
std::vector<double> wrench(const sweepgen::spatial::Force<double>& f) {
  return {f.moment[0], f.moment[1], f.moment[2], f.force[0], f.force[1], f.force[2]};
}

// Why `sweepgen solve` (cli/solve_command.cpp) cannot run the scene's problems, or "".
std::string cli_mismatch(const Scene& s) {
  const sweepgen::solver::SolverOptions defaults;
  if (s.layout.torques.size() > 1) return "more than one torque driver";
  std::set<std::string> links;
  for (const auto& force : s.layout.external_forces)
    if (!links.insert(force.link).second) return "two external forces on link " + force.link;
  if (s.gravity != defaults.gravity) return "gravity other than the default";
  if (s.constraint_factorisation != defaults.constraint_factorisation || s.pivot_tolerance != defaults.pivot_tolerance)
    return "a constraint factorisation or pivot tolerance other than the default";
  if (!s.chain.locked_joints.empty()) return "locked_joints";
  return "";
}

ordered_json scene_line(const Scene& s, const sweepgen::model::Chain& chain) {
  ordered_json line;
  line["urdf"] = s.chain.urdf;
  line["cli_args"] = {"--root", chain.root_link, "--tip", chain.tip_link};
  for (const std::string& tip : chain.branch_tips) {
    line["cli_args"].push_back("--branch-tip");
    line["cli_args"].push_back(tip);
  }
  if (chain.floating_base) line["cli_args"].push_back("--floating-base");
  if (s.chain.couple_mimics) {
    line["cli_args"].push_back("--mimic");
    line["cli_args"].push_back("coupled");
  }
  for (const auto& [joint, value] : s.chain.rotor_inertia)
    line["cli_args"].push_back("--rotor-inertia=" + joint + "=" + nlohmann::json(value).dump());
  line["dof"] = chain.dof();
  line["nq"] = s.flat_layout(chain).positions();
  line["nv"] = s.flat_layout(chain).velocities();
  line["couplings"] = chain.couplings.size();
  line["constraints"] = s.layout.constraints;
  line["sets"] = s.layout.listed_sets();  // each reports its link's acceleration
  line["loop_sets"] = s.layout.loop_sets();  // each reports its closure error (12)
  line["run_time_directions"] = s.layout.run_time_directions();
  line["flat_in_size"] = s.flat_layout(chain).in_size();
  std::vector<std::string> joints, policies;
  for (std::size_t i = 1; i <= chain.dof(); ++i) joints.push_back(chain.joints[i].name);
  for (const auto policy : s.policies) policies.push_back(sweepgen::solver::name(policy));
  line["joints"] = joints;
  line["policies"] = policies;
  line["status"] = {{"ok", sweepgen::solver::status_ok},
                    {"constraint_rank_deficient", sweepgen::solver::status_constraint_rank_deficient},
                    {"saturated", sweepgen::solver::status_saturated},
                    {"not_finite", sweepgen::solver::status_not_finite},
                    {"joint_inertia_singular", sweepgen::solver::status_joint_inertia_singular}};
  return line;
}

// Direction k := unit axis k, for a scene whose directions are run-time inputs.
void use_axis_directions(const Scene& s, const sweepgen::model::Chain& chain, Problem& p) {
  if (s.layout.run_time_directions() != s.layout.constraints) return;
  for (std::size_t k = 0; k < p.alpha.size(); ++k) {
    p.alpha[k].moment.setZero();
    p.alpha[k].force.setZero();
    (k < 3 ? p.alpha[k].moment : p.alpha[k].force)[static_cast<Eigen::Index>(k % 3)] = 1;
  }
  sweepgen::report::pack_flat(s, chain, p);
}

ordered_json cli_problem(const Scene& s, const sweepgen::model::Chain& chain, const Problem& p) {
  ordered_json line;
  // q and qd as `in` holds them (a floating base's rotation first, no coupled <mimic> joint)
  line["q"] = sweepgen::solver::generated_positions(p.q, p.base_rotation, s.chain.floating_base, chain.couplings);
  line["qd"] = sweepgen::solver::generated_velocities(p.qd, chain.couplings);
  line["tau_ff"] = values(p.tau_ff);
  if (!p.wrenches.empty()) {
    line["f_ext"] = ordered_json::object();
    for (std::size_t e = 0; e < p.wrenches.size(); ++e)
      line["f_ext"][s.layout.external_forces[e].link] = wrench(p.wrenches[e]);
  }
  if (s.layout.listed_sets() > 0) {  // sets on their links: `sweepgen solve`'s "constraints"
    line["constraints"] = ordered_json::array();
    std::size_t k = 0;
    for (const auto& set : s.layout.sets) {
      ordered_json entry{{"link", set.link}, {"alpha", ordered_json::array()}, {"beta", ordered_json::array()}};
      if (set.relative()) {  // a set between two links: its frames as URDF origins (rpy from R = E^T)
        const auto origin = [](const sweepgen::model::Transform& X) {
          const sweepgen::model::Mat3 R = X.E.transpose();
          return ordered_json{{"xyz", values(X.r)},
                              {"rpy", {std::atan2(R(2, 1), R(2, 2)), std::asin(-R(2, 0)), std::atan2(R(1, 0), R(0, 0))}}};
        };
        entry["at"] = origin(set.at);
        entry["relative_to"] = set.relative_to;
        entry["relative_at"] = origin(set.relative_at);
      }
      for (std::size_t d = 0; d < set.count; ++d, ++k) {
        entry["alpha"].push_back(wrench(p.alpha[k]));
        entry["beta"].push_back(p.beta[static_cast<Eigen::Index>(k)]);
      }
      line["constraints"].push_back(entry);
    }
  } else if (!p.alpha.empty()) {
    line["alpha"] = ordered_json::array();
    for (const auto& direction : p.alpha) line["alpha"].push_back(wrench(direction));
    line["beta"] = values(p.beta);
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  const bool axes = argc == 5 && std::string(argv[4]) == "axes";
  if (argc != 4 && !axes) {
    std::cerr << "usage: " << argv[0] << " SCENE COUNT SEED [axes]\n";
    return 2;
  }
  try {
    const Scene s = sweepgen::scene::load_scene(argv[1]);
    const sweepgen::model::Chain chain = sweepgen::scene::load_scene_chain(s);
    if (const std::string mismatch = cli_mismatch(s); !mismatch.empty()) {
      std::cerr << argv[1] << ": sweepgen solve cannot run this scene's problems: " << mismatch << "\n";
      return 1;
    }
    std::vector<Problem> problems =
        sweepgen::report::random_problems(s, chain, std::stoul(argv[2]), std::stoull(argv[3]));
    if (axes)
      for (Problem& p : problems) use_axis_directions(s, chain, p);
    const std::vector<sweepgen::report::Truth> truths = sweepgen::report::precise_reference(s, chain, problems);
    std::cout << scene_line(s, chain).dump() << "\n";
    for (std::size_t k = 0; k < problems.size(); ++k) {
      ordered_json line;
      line["in"] = problems[k].flat;
      line["kappa"] = sweepgen::report::kappa(truths[k].cond_scaled, truths[k].min_relative_D);
      line["cli"] = cli_problem(s, chain, problems[k]);
      std::cout << line.dump() << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << argv[1] << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}

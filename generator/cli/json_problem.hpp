// One line of `sweepgen solve` input and output (README, "sweepgen solve").
#pragma once

#include <nlohmann/json.hpp>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "model/error.hpp"
#include "solver/drivers.hpp"
#include "solver/policy.hpp"
#include "solver/state.hpp"

namespace sweepgen::cli {

// A problem that cannot be read: names the offending key.
class KeyError : public std::runtime_error {
 public:
  KeyError(const std::string& key, const std::string& reason)
      : std::runtime_error(message_text("key " + quote_name(key) + ": " + reason)) {}
};

struct Problem {
  Eigen::VectorXd q, qd, tau_ff;  // N each (a floating base's first six q are 0: never read)
  spatial::Mat3<double> base_rotation = spatial::Mat3<double>::Identity();  // world_R_base (F5)
  std::map<std::string, spatial::Force<double>> f_ext;  // link -> wrench [mx,my,mz,fx,fy,fz]
  std::vector<spatial::Force<double>> alpha;             // tip frame, or each set's link frame; [moment; force]
  Eigen::VectorXd beta;
  std::vector<solver::ConstraintSet> sets;  // from "constraints" (empty: alpha, beta on the tip)
  solver::Policy policy = solver::Policy::original;
};

// `value` as `expected` finite numbers; throws KeyError naming `key`.
Eigen::VectorXd numbers(const nlohmann::json& value, const std::string& key, std::size_t expected);

// world_R_base from the first 9 numbers of a floating base's q (F5, row-major); throws KeyError
// naming `key` where they are not a rotation matrix within 1e-9.
spatial::Mat3<double> base_rotation(const Eigen::VectorXd& q, const std::string& key);

// Throws KeyError where the text of a line, valid JSON, holds what its parsed value would hide: a
// key given twice in one object (the value keeps the last) or a number too small for a double,
// which reads as 0 (1e-400).
void refuse_hidden_json(const std::string& text);

// Reads and checks a problem for `chain` (sizes, finiteness, link names). Throws KeyError.
Problem parse_problem(const nlohmann::json& line, const model::Chain& chain);

// One output line's text: names from the URDF (saturated_joints) need not be UTF-8, which JSON
// must be; their other bytes are written as U+FFFD instead of nlohmann's exception.
std::string json_text(const nlohmann::ordered_json& value);

// Why a line is not JSON: nlohmann's message quotes the bytes it read, which need not be UTF-8
// nor short: escaped and cut (escaped_text).
std::string json_error_reason(const nlohmann::json::exception& error);

// The answer to a line that cannot be solved: {"line": N, "error": "..."}.
std::string error_line(std::size_t line, const std::string& message);

// `sets`: the problem's constraint sets (their link accelerations become "xdd_links").
nlohmann::ordered_json solution_to_json(const solver::Solution<double>& solution, unsigned status,
                                        const model::Chain& chain, const std::vector<solver::ConstraintSet>& sets = {});

}  // namespace sweepgen::cli

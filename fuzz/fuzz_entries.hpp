// The fuzzed contract of sweepgen's three input readers, shared by the libFuzzer targets
// (fuzz_*.cpp) and the regression test (tests/test_fuzz_regressions.cpp).
//
// Contract: on any input a reader either accepts it (and what it returns is consistent: sizes
// match, numbers are finite, names exist) or rejects it with the documented error type whose
// message names the file (or key), the element and a reason. Each entry below returns the
// outcome in those two cases and lets everything else escape: any other exception type, and
// ContractViolation when an accepted result or an error message breaks the contract. Under
// libFuzzer an escaping exception aborts the run, which records the input as a finding.
#pragma once

#include <map>
#include <stdexcept>
#include <string>

namespace sweepgen::fuzz {

// An accepted result or an error message that breaks the contract above.
class ContractViolation : public std::logic_error {
 public:
  explicit ContractViolation(const std::string& what) : std::logic_error("fuzz contract violated: " + what) {}
};

struct Outcome {
  bool accepted = false;
  std::string error;  // what() of the documented error when rejected
};

// robots/*/*.urdf as built in (cmake/embed_files.cmake), keyed by the path under robots/.
const std::map<std::string, std::string>& bundled_urdfs();

// The URDF loader (model::load_chain) on `input` written to a file. The input may start with
// "<!-- chain root=LINK tip=LINK -->" (an XML comment, so still a URDF; either part optional)
// to choose the root and tip links instead of the defaults. Documented error: InputError.
Outcome urdf_input(const std::string& input);

// The scene reader (scene::load_scene) on `input` written to a scene file whose directory holds
// copies of the bundled URDFs (panda.urdf, iiwa14.urdf, ur5.urdf, planar_rpr.urdf), as the
// bundled scenes expect; when the scene parses and names one of those files, also
// scene::load_scene_chain. Documented error: InputError.
Outcome scene_input(const std::string& input);

// One `sweepgen solve` input line: nlohmann::json::parse, then cli::refuse_hidden_json (a key
// twice, a number that reads as 0) and cli::parse_problem for the bundled Panda
// (robots/panda/panda.urdf, default root and tip). Documented errors: nlohmann::json::exception
// from json::parse (the line is not JSON), cli::KeyError from the other two.
Outcome solve_line_input(const std::string& input);

}  // namespace sweepgen::fuzz

#include "report/flat_judgement.hpp"

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <limits>
#include <vector>

#include "model/error.hpp"
#include "model/input_limits.hpp"
#include "report/measure.hpp"
#include "report/stability_errors.hpp"

namespace sweepgen::report {
namespace {

// The lines of `file` that hold a state: each as its `values` numbers. Throws InputError for an
// unreadable file or a line that is not that many numbers.
std::vector<std::vector<double>> read_states(const std::string& file, std::size_t values) {
  std::istringstream in(read_input_file(file, kMaxJudgedBytes, "file of results (--judge)"));
  std::vector<std::vector<double>> states;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::vector<double> state;
    const char* cursor = line.c_str();
    for (;;) {
      char* end = nullptr;
      const double v = std::strtod(cursor, &end);
      if (end == cursor) break;
      state.push_back(v);
      cursor = end;
    }
    const std::string where = "line " + std::to_string(number);
    const std::string rest(cursor);
    if (const std::size_t word = rest.find_first_not_of(" \t\r"); word != std::string::npos)
      throw InputError(file, where, "not a number: '" + rest.substr(word, 40) + "'");
    if (state.size() != values)
      throw InputError(file, where, std::to_string(state.size()) + " numbers, the scene's flat input and output are " +
                                               std::to_string(values));
    states.push_back(std::move(state));
  }
  return states;
}

}  // namespace

FlatJudgement judge_flat_results(const scene::Scene& s, const std::string& file, std::ostream& out) {
  const model::Chain chain = scene::load_scene_chain(s);
  const solver::FlatLayout layout = s.flat_layout(chain);
  const std::vector<std::vector<double>> lines = read_states(file, layout.in_size() + layout.out_size());
  std::vector<Problem> problems;
  for (const std::vector<double>& line : lines) {
    Problem p;
    static_cast<solver::SolveInputs<double>&>(p) = solver::solve_inputs_from_flat(line.data(), layout, s.layout);
    p.tau_ff = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(chain.dof()));
    for (const auto& tau : p.torques) p.tau_ff += tau;
    p.flat.assign(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(layout.in_size()));
    problems.push_back(std::move(p));
  }
  // The referee with double's tolerances (its rank decisions are the ones a double solve should
  // make), and at half and twice them: where those two decide differently, rounding may tip the
  // decision and the status is not compared.
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const auto truth = precise_reference(s, chain, problems, with_tolerance_factor(s, 1, eps));
  const auto lower = precise_reference(s, chain, problems, with_tolerance_factor(s, 0.5, eps), solver::Policy::original, false);
  const auto upper = precise_reference(s, chain, problems, with_tolerance_factor(s, 2, eps), solver::Policy::original, false);

  FlatJudgement result;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    ++result.states;
    const Outcome outcome = outcome_of(lines[k].data() + layout.in_size(), layout);
    const StateJudgement j = judge(outcome, truth[k], problems[k], chain, std::numeric_limits<double>::max());
    const std::string state = "state " + std::to_string(k) + ": ";
    if (!j.finite && j.representable) {
      ++result.not_finite;
      out << state << "a NaN or Inf where the referee's results fit in double\n";
    }
    if (j.status != j.exact_status && lower[k].status == upper[k].status) {
      ++result.status_differs;
      out << state << "status " << j.status << ", the referee's " << j.exact_status << "\n";
    }
    if (!j.full_rank()) {
      ++result.not_full_rank;
      continue;
    }
    double kappa = j.kappa();
    if (kFlatErrorFactor * eps * kappa > kFlatErrorCeiling) {
      ++result.beyond_ceiling;
      continue;
    }
    if (j.error() > kFlatErrorFactor * eps * kappa) kappa = std::max(kappa, j.cond_M);
    ++result.judged;
    const double ratio = j.error() / (eps * kappa);
    if (!(ratio <= result.worst_ratio)) {
      result.worst_ratio = ratio;
      result.worst_state = k;
    }
    if (!(ratio <= kFlatErrorFactor)) {
      ++result.over_bound;
      out << state << "error " << j.error() << " = " << ratio << " eps kappa (kappa " << kappa << "), above "
          << kFlatErrorFactor << "\n";
    }
  }
  out << file << ": " << result.states << " states against the binary128 referee; " << result.judged
      << " judged, worst " << result.worst_ratio << " eps kappa (state " << result.worst_state << "), allowed "
      << kFlatErrorFactor << "; " << result.beyond_ceiling << " beyond the bound's ceiling " << kFlatErrorCeiling
      << " and " << result.not_full_rank << " rank-deficient or locked (status and finiteness only); "
      << result.status_differs << " with another status, " << result.not_finite << " not finite, " << result.over_bound
      << " over the bound: " << (result.passed() ? "passed" : "FAILED") << "\n";
  return result;
}

}  // namespace sweepgen::report

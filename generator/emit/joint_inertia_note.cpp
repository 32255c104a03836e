#include "emit/joint_inertia_note.hpp"

#include "model/inert_text.hpp"

namespace sweepgen::emit {
namespace {

std::string listed(const std::vector<std::string>& names, std::size_t of) {
  if (names.empty()) return "none";
  if (names.size() == of) return "all " + std::to_string(of);
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

std::string note_for(const model::Chain& chain, const solver::DriverLayout& layout, const solver::SolverOptions& options,
                     double epsilon) {
  const solver::SolverModel<double> model(chain, layout, options, epsilon);
  std::vector<std::string> tested, exact;
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    if (model.joints[i].can_lock) tested.push_back(inert_text(chain.joints[i].name));
    if (model.joints[i].exact_zero_component >= 0) exact.push_back(inert_text(chain.joints[i].name));
  }
  const std::string lock = tested.empty()                ? "no joint can lock (J2), no lock test (J1)"
                           : tested.size() == chain.dof() ? "lock test (J1) on every joint"
                                                          : "lock test (J1) on " + listed(tested, chain.dof()) +
                                                                " (the others cannot lock, J2)";
  return lock + "; S_i^T P_i^T = 0 written exactly on " + listed(exact, chain.dof());
}

}  // namespace

std::string joint_inertia_note(const model::Chain& chain, const solver::DriverLayout& layout,
                               const solver::SolverOptions& options, const std::vector<std::string>& scalars,
                               const std::vector<double>& epsilons) {
  std::vector<std::string> notes;
  for (double epsilon : epsilons) notes.push_back(note_for(chain, layout, options, epsilon));
  bool same = true;
  for (const std::string& note : notes) same = same && note == notes.front();
  if (same) return "Joint inertia: " + notes.front() + ".";
  std::string text = "Joint inertia, per scalar:";
  for (std::size_t k = 0; k < notes.size(); ++k) text += (k ? "; " : " ") + scalars[k] + ": " + notes[k];
  return text + ".";
}

}  // namespace sweepgen::emit

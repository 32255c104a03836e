// What the model does not take from the URDF as written, or leaves to the application, a
// sentence each, for `sweepgen info`, `sweepgen generate` and the generated header: joints off
// the chain locked at a default position, joint <dynamics> not modelled, <mimic> joints taken as
// joints of their own, and every number changed by a rule of the loader (Chain::changes: the
// quarter-turn rule, axes scaled to unit length, inertias made symmetric). Nothing is changed
// silently.
#pragma once

#include <string>
#include <vector>

#include "model/chain.hpp"

namespace sweepgen::model {

// Every note, a line each: what the generated header lists, and `--notes` prints.
std::vector<std::string> model_notes(const Chain& chain);

// The same notes for a terminal: a kind with more than two notes (a humanoid's dozens of locked
// finger joints) as one line with its count and the first; a kind with one or two as they are.
std::vector<std::string> model_note_summary(const Chain& chain);

}  // namespace sweepgen::model

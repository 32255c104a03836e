// The quarter-turn rule of docs/derivation.md (F2): URDF roll, pitch and yaw angles within
// 1e-10 rad of a multiple of pi/2 are taken as exactly that multiple, so that such rotations are
// signed permutations (they fold away in generated code). Files write pi/2 as 1.57079632679 (5e-12
// rad off) as often as at full precision; the rule changes the robot by that much, so every use of
// it is reported (Chain::changes), and ChainSpec::snap_quarter_turns = false takes the file
// literally.
#pragma once

#include <urdf_model/pose.h>

#include <array>
#include <map>
#include <string>

#include "model/chain.hpp"

namespace sweepgen::model {

// An <origin>'s rotation as the model takes it.
struct OriginRotation {
  Mat3 R = Mat3::Identity();          // child axes -> parent axes
  std::array<double, 3> rpy{};        // roll, pitch, yaw as urdfdom reads them back from its quaternion
  std::array<long, 3> quarter_turns{};  // per angle: the multiple of pi/2 it was taken as
  std::array<bool, 3> snapped{};        // per angle: whether the rule changed it (not for an angle of 0)
  double deviation = 0;  // [rad] angle of the rotation between the literal R and the one taken
};

// The rotation of a URDF <origin> (urdfdom keeps it as a unit quaternion). snap: R is
// Rz(yaw) Ry(pitch) Rx(roll) of the quaternion's angles under the quarter-turn rule; otherwise the
// quaternion's own rotation matrix, the file literally (to rounding: urdfdom's angles read back
// from it clamp a pitch within 1e-5 of pi/2 to pi/2).
OriginRotation origin_rotation(const urdf::Rotation& rotation, bool snap);

// A deviation below this [rad] is how a double (and urdfdom's quaternion) spells k pi/2 itself
// (1.5707963267948966 is 6e-17 off): listed as one count, not origin by origin.
constexpr double kRoundingOfQuarterTurns = 1e-14;

// The rpy attributes of the joints' and inertials' <origin>s as the file writes them, keyed as the
// loader names those elements: "joint 'j' <origin>", "link 'l' <inertial> <origin>". urdfdom keeps
// only a quaternion, whose angles read back differ from the text (4.71238898038 reads as
// -1.5707963267995864). `urdf_text` ends in NUL bytes (TinyXML reads past a last UTF-8 lead byte:
// load_chain).
std::map<std::string, std::string> written_rpy(const std::string& urdf_text);

// The rotation taken, `taken_as` ("(pi, 0, pi)": the rule applied to urdfdom's angles), in the form
// the file writes it: for rpy="0 3.14159265359 0", "(0, pi, 0)". Where the angles written and those
// taken are all multiples of pi/2 (within 1e-10 rad, or 0), both triples are the same signed
// permutation, exactly: that one said as written. "" otherwise (taken_as is then the triple to give).
std::string quarter_turns_as_written(const std::string& taken_as, const std::string& rpy_attribute);

// "pi/2", "-pi", "3pi/2", "0": k quarter turns as text.
std::string quarter_turns_text(long k);

}  // namespace sweepgen::model
